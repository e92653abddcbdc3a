/* The options database's layout, shared by its files (tl_options.c: the
 * database and its getters; tl_options_help.c: -help and the suggestions for
 * mistyped names); not part of the public API. */
#ifndef TL_OPTIONS_PRIVATE_H
#define TL_OPTIONS_PRIVATE_H

#include <stdio.h>
#include "tl_options.h"

typedef struct {
  char *name;   /* with the leading '-' */
  char *value;  /* NULL for a bare flag */
  char *source; /* "command line (argument 3)" or "file:line" */
  int from_command_line;
  int used;
} TlOptionEntry;

typedef struct {
  char *name, *kind, *def, *unit, *help;
  char *range; /* "" or ">= 0", "[0, 10]" */
  size_t group; /* index into TlOptions.group */
  char *value;  /* the value in force, in canonical text (reals to 17 digits) */
} TlOptionDoc;

enum { TL_OPTIONS_GROUP_DEPTH = 8 };

struct TlOptions {
  TlOptionEntry *entry;
  size_t n_entry, cap_entry;
  TlOptionDoc *doc;
  size_t n_doc, cap_doc;
  char *program;
  char *description;
  char *command_line;
  int help, version, options_left;
  char **group; /* titles, in order of first use; 0 is the driver's own */
  size_t n_group, cap_group;
  size_t group_stack[TL_OPTIONS_GROUP_DEPTH];
  int group_depth;
  char **restart_safe; /* names a restart may change, beside the built-in ones */
  size_t n_restart_safe, cap_restart_safe;
};

/* Writes the -help text of o. */
void tl_options_print_help(const TlOptions *o, FILE *out);

#endif
