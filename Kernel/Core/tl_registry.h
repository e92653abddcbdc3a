/* Types registered by name, so that drivers and options choose them without
 * a switch statement, and a type defined outside the library (a driver, a
 * plug-in, an example) is created exactly like a built-in one.
 *
 * An entry names a type of one kind ("material", "element", "cg_kernel",
 * "wall", "contact_normal", ...) and carries what that kind's
 * create-by-name function needs: a constructor (`create`, a function whose
 * signature the kind defines; NULL where the ops table alone makes the type,
 * as for materials), the type's ops table, and its parameter table (name,
 * default, unit, range, description), which -help and the catalogue read.
 *
 * Each module registers its own types in one function
 *   TlStatus tl_<module>_register_all(void)
 * defined at the start of a line in a source file of its folder; the build
 * collects these definitions into the table that tl_initialize() calls, so
 * the core names no module. */
#ifndef TL_REGISTRY_H
#define TL_REGISTRY_H

#include <stddef.h>
#include "tl_error.h"
#include "tl_object.h"

/* A kind's constructor, stored untyped and cast back to the kind's
 * signature by that kind's create-by-name function. */
typedef void (*TlConstructor)(void);

/* A real parameter of a type, stored as a double at `offset` in the
 * type's object. */
typedef struct {
  const char *name;
  double def, lo, hi; /* default and the closed admissible range */
  const char *unit;
  const char *help;
  size_t offset;
} TlParam;

typedef struct {
  const char *kind;
  const char *name;
  const char *description; /* one line, listed by -help */
  TlConstructor create;    /* may be NULL */
  const void *ops;         /* may be NULL */
  const TlParam *params;
  int n_params;
} TlTypeEntry;

/* Registers a type (the entry is copied; its strings and tables must
 * outlive the registry).  The same kind and name registered again with the
 * same constructor and ops is harmless; another type under a taken name is
 * an error. */
TlStatus tl_registry_register(const TlTypeEntry *entry);
/* The entry of `kind` named `name`; the error lists the known names. */
TlStatus tl_registry_lookup(const char *kind, const char *name, const TlTypeEntry **entry);
/* The i-th entry of `kind` in registration order, or NULL past the end
 * (for listings: -help, catalogues). */
const TlTypeEntry *tl_registry_entry(const char *kind, size_t i);

/* The i-th entry of any kind in registration order, or NULL past the end
 * (for the catalogue of every registered type: talus_catalogue). */
const TlTypeEntry *tl_registry_at(size_t i);

/* Shorthand for types whose ops table, beginning with a TlOpsHeader, is all
 * there is to them: registers {kind, name, description} of the header with
 * `ops` = the table. */
TlStatus tl_registry_add(const TlOpsHeader *ops);
/* The ops table of `kind` named `name`. */
TlStatus tl_registry_find(const char *kind, const char *name, const TlOpsHeader **ops);
/* Copies up to max names of `kind` into names; returns how many exist. */
size_t tl_registry_list(const char *kind, const char **names, size_t max);
/* The parameter of an entry named `name`, or NULL. */
const TlParam *tl_param_find(const TlParam *params, int n_params, const char *name);
/* Empties the registry (tests). */
void tl_registry_clear(void);

#endif
