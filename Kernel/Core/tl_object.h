/* The object model.
 *
 * Every ops table begins with a TlOpsHeader: the kind of object ("contact",
 * "element", "material", ...) and the type's name.  Every object begins with
 * a pointer to its const ops table; a derived type embeds its base struct as
 * the first member and points it at its own static ops table:
 *
 *   typedef struct { TlOpsHeader header; TlStatus (*force)(...); } TlContactLawOps;
 *   typedef struct { const TlContactLawOps *ops; double k_n; } TlContactLaw;
 *   typedef struct { TlContactLaw base; double mu; } TlFrictionLaw;
 *
 * Ops are called once per batch (all contacts of a law, all elements of a
 * block), never once per item, so the indirect call is cheap.  Types are
 * found by name through the registry (tl_registry.h). */
#ifndef TL_OBJECT_H
#define TL_OBJECT_H

typedef struct {
  const char *kind;        /* registry namespace */
  const char *name;        /* type name, as given to options: "hertz_mindlin" */
  const char *description; /* one line, listed by -help */
} TlOpsHeader;

/* The type name of any object whose first member is a pointer to an ops
 * table beginning with a TlOpsHeader. */
static inline const char *tl_type_name(const void *object)
{
  return (*(const TlOpsHeader *const *)object)->name;
}

#endif
