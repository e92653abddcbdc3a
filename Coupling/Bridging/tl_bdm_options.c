/* Options of the bridging domain coupling, their check, and the weight
 * profile alpha across the zones. */
#include <math.h>
#include <string.h>

#include "tl_bdm_private.h"
#include "tl_math.h"
#include "tl_registry.h"

static const char *const constraints[] = {"strong", "weak", NULL};
static const char *const lumpings[] = {"rowsum", "diag", "none", NULL};
static const char *const profiles[] = {"linear", "cosine", NULL};
static const char *const ghosts[] = {"none", "fe", "dem", "both", NULL};
static const char *const mass_weights[] = {"nodal", "quadrature", NULL};

/* The real parameters, as the registry lists them (-help, catalogue). */
static const TlParam params[] = {
    {"alpha_min", 1e-3, 1e-12, 0.499, "-", "smallest weight of either model inside a zone (the masses are divided by)",
     offsetof(TlBdmOptions, alpha_min)},
    {"locate_tol", 1e-9, 0.0, 1e-3, "-", "tolerance of the mesh locator in reference coordinates",
     offsetof(TlBdmOptions, locate_tol)},
};

TlStatus tl_bdm_register_all(void)
{
  static const TlTypeEntry e = {"coupling", "bdm",
                                "bridging domain method (seeds/000): energy weighting and Lagrange velocity correction",
                                NULL, NULL, params, (int)(sizeof params / sizeof params[0])};
  return tl_registry_register(&e);
}

void tl_bdm_options_default(TlBdmOptions *o)
{
  *o = (TlBdmOptions){.constraint = TL_BDM_STRONG, .lumping = TL_BDM_LUMP_ROWSUM, .jacobi = 0,
                      .profile = TL_BDM_ALPHA_LINEAR, .alpha_min = 1e-3, .ghost = TL_BDM_GHOST_BOTH,
                      .mass_weight = TL_BDM_MASS_NODAL, .locate_tol = 1e-9};
}

TlStatus tl_bdm_options_check(const TlBdmOptions *o)
{
  if (o->constraint != TL_BDM_STRONG && o->constraint != TL_BDM_WEAK)
    TL_ERROR(TL_ERR_ARG, "bdm: constraint %d is neither strong (0) nor weak (1)", (int)o->constraint);
  if (o->lumping < TL_BDM_LUMP_ROWSUM || o->lumping > TL_BDM_LUMP_NONE)
    TL_ERROR(TL_ERR_ARG, "bdm: lumping %d outside rowsum (0), diag (1), none (2)", (int)o->lumping);
  if (o->profile != TL_BDM_ALPHA_LINEAR && o->profile != TL_BDM_ALPHA_COSINE)
    TL_ERROR(TL_ERR_ARG, "bdm: alpha profile %d is neither linear (0) nor cosine (1)", (int)o->profile);
  if (o->ghost < TL_BDM_GHOST_NONE || o->ghost > TL_BDM_GHOST_BOTH)
    TL_ERROR(TL_ERR_ARG, "bdm: ghost-force scope %d outside none (0), fe (1), dem (2), both (3)", (int)o->ghost);
  if (o->mass_weight != TL_BDM_MASS_NODAL && o->mass_weight != TL_BDM_MASS_QUADRATURE)
    TL_ERROR(TL_ERR_ARG, "bdm: mass weighting %d is neither nodal (0) nor quadrature (1)", (int)o->mass_weight);
  if (o->jacobi < 0 || o->jacobi > 1000) TL_ERROR(TL_ERR_ARG, "bdm: Jacobi sweeps %d outside [0, 1000]", o->jacobi);
  if (o->jacobi > 0 && (o->constraint == TL_BDM_WEAK || o->lumping == TL_BDM_LUMP_NONE))
    TL_ERROR(TL_ERR_ARG, "bdm: %d Jacobi sweeps asked for a consistent A (%s constraint, lumping %s): sweeps refine a "
             "lumped strong A only", o->jacobi, tl_bdm_constraint_name(o->constraint), tl_bdm_lumping_name(o->lumping));
  const TlParam *p = &params[0];
  if (!(o->alpha_min >= p->lo && o->alpha_min <= p->hi))
    TL_ERROR(TL_ERR_ARG, "bdm: alpha_min = %g outside [%g, %g]: both weighted masses must stay > 0 (the correction "
             "divides by them)", o->alpha_min, p->lo, p->hi);
  p = &params[1];
  if (!(o->locate_tol >= p->lo && o->locate_tol <= p->hi))
    TL_ERROR(TL_ERR_ARG, "bdm: locate_tol = %g outside [%g, %g]", o->locate_tol, p->lo, p->hi);
  return TL_OK;
}

static TlStatus from_db(TlOptions *db, TlBdmOptions *o)
{
  int k;
  TL_CHECK(tl_options_get_choice(db, "-bdm", constraints[o->constraint], constraints,
                                 "bridging constraint: strong (each particle tied to the FE interpolation, Eqs. 7-10) "
                                 "or weak (nodal projections, Eqs. 11-14)", &k));
  o->constraint = (TlBdmConstraint)k;
  TL_CHECK(tl_options_get_choice(db, "-bdm_lumped", lumpings[o->lumping], lumpings,
                                 "strong constraint matrix A: row-sum lumped, diagonal, or none (consistent, solved by "
                                 "Woodbury through a node-sized system factorised once); weak is always consistent",
                                 &k));
  o->lumping = (TlBdmLumping)k;
  long j;
  TL_CHECK(tl_options_get_int(db, "-bdm_jacobi", o->jacobi, 0, 1000,
                              "Jacobi sweeps on a lumped strong A towards the consistent multipliers", &j));
  o->jacobi = (int)j;
  TL_CHECK(tl_options_get_choice(db, "-bdm_alpha", profiles[o->profile], profiles,
                                 "weight profile alpha across each bridging zone (1 on the FE side)", &k));
  o->profile = (TlBdmProfile)k;
  TL_CHECK(tl_options_get_real(db, "-bdm_alpha_min", o->alpha_min, params[0].lo, params[0].hi, params[0].unit,
                               "alpha clamped to [alpha_min, 1 - alpha_min] inside a zone (weighted masses > 0)",
                               &o->alpha_min));
  TL_CHECK(tl_options_get_choice(db, "-ghost_force", ghosts[o->ghost], ghosts,
                                 "ghost-force correction: subtract the initial forces of the FE nodes (the paper's "
                                 "text), of the particles the weighting reaches, both (the default: either alone "
                                 "leaves the other model's weighted unbalance, which the overlap as a whole "
                                 "balanced), or none", &k));
  o->ghost = (TlBdmGhost)k;
  TL_CHECK(tl_options_get_choice(db, "-bdm_mass_weight", mass_weights[o->mass_weight], mass_weights,
                                 "FE weighted masses: nodal alpha(X_I) M_I (the paper) or alpha at the mass points",
                                 &k));
  o->mass_weight = (TlBdmMassWeight)k;
  return tl_bdm_options_check(o);
}

const char *tl_bdm_constraint_name(TlBdmConstraint c)
{
  return c == TL_BDM_STRONG || c == TL_BDM_WEAK ? constraints[c] : "?";
}
const char *tl_bdm_lumping_name(TlBdmLumping l)
{
  return l >= TL_BDM_LUMP_ROWSUM && l <= TL_BDM_LUMP_NONE ? lumpings[l] : "?";
}
const char *tl_bdm_ghost_name(TlBdmGhost g) { return g >= TL_BDM_GHOST_NONE && g <= TL_BDM_GHOST_BOTH ? ghosts[g] : "?"; }

double tl_bdm_alpha(const TlBdmZone *zones, int n, TlBdmProfile profile, double alpha_min, const double x[3])
{
  double a = 0.0;
  for (int z = 0; z < n; ++z) {
    const TlBdmZone *Z = &zones[z];
    double t = (x[Z->axis] - Z->s_dem) / (Z->s_fe - Z->s_dem), v;
    if (t < 0.0) v = 0.0;
    else if (t > 1.0) v = 1.0;
    else {
      v = profile == TL_BDM_ALPHA_COSINE ? 0.5 * (1.0 - cos(TL_PI * t)) : t;
      v = v < alpha_min ? alpha_min : v > 1.0 - alpha_min ? 1.0 - alpha_min : v;
    }
    a = v > a ? v : a;
  }
  return a;
}

/* The coupling's options under their own heading in -help. */
TlStatus tl_bdm_options_from_db(TlOptions *db, TlBdmOptions *o)
{
  TL_CHECK(tl_options_begin_group(db, "Bridging domain coupling"));
  TlStatus s = from_db(db, o);
  tl_options_end_group(db);
  return s == TL_OK ? TL_OK : tl_error_trace(s, __FILE__, __LINE__);
}
