/* The options database, in the manner of PETSc.
 *
 * A driver creates it from argv (which may name -options_file FILE), then asks
 * for each option it uses through a typed getter that states the default, the
 * range, the unit and a one-line description.  tl_options_finish() then either
 * prints the -help page built from those getters (and returns TL_HELP), or
 * refuses any option that was given but never asked for, so a typo is never
 * silently ignored.  Every value error names the option, the value and the
 * limit.
 *
 * Rules a user relies on:
 *  - the last value of a repeated option wins, so a wrapper may run
 *    `driver $DEFAULTS "$@"`; options files are read in order, a later one
 *    overriding an earlier one, and the command line overrides every file;
 *  - every program accepts -help (also --help, -h), -version (--version),
 *    -options_file FILE (repeatable), -options_left (list the options given
 *    but never read as warnings instead of refusing them) and -log_level
 *    error|warn|info|debug (over the environment's TALUS_LOG_LEVEL);
 *  - -help groups the options by module (tl_options_begin_group), shows each
 *    one's unit, default and range, wrapped at TL_OPTIONS_HELP_WIDTH columns;
 *  - an unknown option is refused with a suggestion only when a known name is
 *    close to it (edit distance 1 for names up to 4 letters, 2 up to 8, 3
 *    beyond; a transposition counts as one edit);
 *  - booleans accept true/false, yes/no, on/off, 1/0 (any case), and a bare
 *    -flag means true. */
#ifndef TL_OPTIONS_H
#define TL_OPTIONS_H

#include <stdio.h>
#include "tl_error.h"

typedef struct TlOptions TlOptions;

#define TL_OPTIONS_HELP_WIDTH 100

/* A unit suffix accepted by tl_options_get_scaled: "10d" means 10 * factor
 * of the suffix "d" (for instance the particle diameter). */
typedef struct {
  const char *suffix;
  double factor;
  const char *meaning; /* for -help: "particle diameter" */
} TlScale;

/* Parses argv[1..argc-1].  `description` is the first paragraph of -help. */
TlStatus tl_options_create(int argc, char **argv, const char *description, TlOptions **options);
void tl_options_destroy(TlOptions **options);
/* Adds options from a file: one "-name value" per line, '#' starts a comment.
 * A command-line value overrides a file value; a duplicate within one source
 * is an error. */
TlStatus tl_options_insert_file(TlOptions *options, const char *path);

/* Options asked for between begin and end are listed under `title` in -help
 * ("contact law", "output"); groups nest, and a title used again continues
 * its group.  Options asked for outside any group are the program's own. */
TlStatus tl_options_begin_group(TlOptions *o, const char *title);
void tl_options_end_group(TlOptions *o);

/* Typed getters: *value is the given value or the default. */
TlStatus tl_options_get_real(TlOptions *o, const char *name, double def, double lo, double hi,
                             const char *unit, const char *help, double *value);
TlStatus tl_options_get_int(TlOptions *o, const char *name, long def, long lo, long hi,
                            const char *help, long *value);
/* "-flag" alone means true; "-flag 0|1|true|false|yes|no" also accepted. */
TlStatus tl_options_get_bool(TlOptions *o, const char *name, int def, const char *help, int *value);
/* *value points into the database (valid until destroy) or to def. */
TlStatus tl_options_get_string(TlOptions *o, const char *name, const char *def, const char *help,
                               const char **value);
/* One of `choices` (NULL-terminated); *index is its position. */
TlStatus tl_options_get_choice(TlOptions *o, const char *name, const char *def,
                               const char *const *choices, const char *help, int *index);
/* A real number with an optional unit suffix from `scales` (n entries):
 * "-cg_width 10d" gives 10 * scales["d"].factor; a bare number is in `unit`. */
TlStatus tl_options_get_scaled(TlOptions *o, const char *name, const char *def, double lo, double hi,
                               const char *unit, const TlScale *scales, int n, const char *help,
                               double *value);
/* Comma-separated non-negative reals ("-c_list 0,2,4": times, sizes, widths);
 * up to max values, *count set.  An empty list or an empty field ("1,,2")
 * is refused by name. */
TlStatus tl_options_get_real_list(TlOptions *o, const char *name, const char *def, const char *unit,
                                  const char *help, double *values, int max, int *count);
/* The same with every value in [lo, hi]. */
TlStatus tl_options_get_real_list_range(TlOptions *o, const char *name, const char *def, double lo, double hi,
                                        const char *unit, const char *help, double *values, int max, int *count);
/* Whether the option was given (and marks it used). */
int tl_options_has(TlOptions *o, const char *name);

/* After every getter: TL_HELP (help, or with -version the version line,
 * printed to `out`) if asked for; an error naming every option given and
 * never asked for (warnings instead with -options_left); TL_OK otherwise,
 * and the database becomes the current one (tl_options_current). */
TlStatus tl_options_finish(TlOptions *o, FILE *out);
/* The known option closest to `name` (NULL when none is close enough). */
const char *tl_options_suggest(const TlOptions *o, const char *name);
/* The database of the running program: the last one finished and not yet
 * destroyed, NULL when none.  The output writers record its command line and
 * values in every file (Kernel/IO/tl_provenance.h). */
const TlOptions *tl_options_current(void);
void tl_options_set_current(const TlOptions *o);
/* The program name (argv[0] without its folder). */
/* The values in force of the options asked for so far (given or default),
 * in canonical text (reals with 17 digits, booleans true/false): what a
 * checkpoint stores so that a restart can be compared with the run it
 * continues (Kernel/IO/tl_options_checkpoint.h). */
size_t tl_options_n_values(const TlOptions *o);
void tl_options_value_at(const TlOptions *o, size_t i, const char **name, const char **value);
/* The value in force of `name`, NULL if it was never asked for. */
const char *tl_options_value(const TlOptions *o, const char *name);
/* Options a restart may change.  Built in: how far to run (-t_end,
 * -stop_step), where and how often to write (-output_dir, -output_*,
 * -snapshot*, -table_* (table cadence), -checkpoint_every), -restart, -threads, -check,
 * -tolerance, -progress*; a driver adds its own (cantilever_fem's
 * -periods, its end time). */
TlStatus tl_options_set_restart_safe(TlOptions *o, const char *name);
int tl_options_is_restart_safe(const TlOptions *o, const char *name);
const char *tl_options_program(const TlOptions *o);
/* The whole command line, for provenance in output files. */
const char *tl_options_command_line(const TlOptions *o);

#endif
