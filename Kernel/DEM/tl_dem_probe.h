/* Elastic tensor of a periodic packing by strain probing (seeds/000 §3.2,
 * the LAMMPS ELASTIC example its authors used).
 *
 * From a reference state of a TlDem in a deformable periodic cell, each of
 * the six strain components J (Voigt order xx, yy, zz, yz, xz, xy) is
 * applied as ±ε by an affine map of the cell and of every particle centre,
 *   h <- F h,  x <- o + F (x - o),  F = I + (±ε) e_k e_lᵀ,
 * (k, l) = (x, x), (y, y), (z, z), (y, z), (x, z), (x, y): LAMMPS's
 * change_box ... remap of an upper-triangular box (lx, xy, xz scale with
 * ε_xx; ly, yz with ε_yy; tilt yz += ε lz for γ_yz, xz += ε lz for γ_xz,
 * xy += ε ly for γ_xy, engineering shears).  The stress is the
 * Cauchy-Poisson (Love-Weber) stress of the cell, contacts plus the kinetic
 * part (tl_dem_stress), tension positive, its symmetric part in Voigt order.
 *   C_iJ = (σ_i(+ε_J) - σ_i(-ε_J)) / (2ε)         (central difference)
 * cancels the O(ε) curvature of σ(ε); the one-sided (σ± - σ0)/(±ε) are
 * kept (their mean is C).  The pre-stress enters C as it enters a LAMMPS
 * probe: C is the derivative of the Cauchy stress of the deformed cell.
 *
 * Protocols:
 *   TL_PROBE_AFFINE   the mapped state is evaluated at once (LAMMPS's
 *                     "run 0"): nothing moves, the contact histories are the
 *                     reference ones (one force evaluation increments them
 *                     by the reference velocities times dt, the same for +ε
 *                     and -ε).  With the paper's preparation (frictionless
 *                     compaction, hence almost no tangential history) this is
 *                     the affine normal-contact stiffness plus pre-stress
 *                     terms; it obeys the Cauchy relation C12 ≈ C44.
 *   TL_PROBE_RELAXED  the mapped state is relaxed at fixed cell to static
 *                     balance (global viscous damping -c v, LAMMPS fix
 *                     viscous, until every grain's Δ_n of seeds/004 Eq. 19 is
 *                     below the tolerance, rattlers whose largest contact
 *                     carries less than 1e-3 of the mean contact force left
 *                     out), then the stress is read: what
 *                     the paper's text describes.  By default the reference
 *                     itself is relaxed the same way first.
 * Jiggle (the authors' scripts, LAMMPS displace_atoms random): before the
 * reference is taken every free particle is displaced by an independent
 * uniform amount in [-a, a] per component (a = 1e-5 m in the scripts); the
 * probes all start from that jiggled copy.  Talus's generator is not
 * LAMMPS's, so a jiggled probe reproduces the published tensor statistically,
 * not digit by digit.
 *
 * The reference state (positions, velocities, spins, cell, contact list and
 * histories) is kept in a scratch checkpoint file (tl_dem_checkpoint_ops) and
 * reloaded before every probe, so each probe starts from exactly the same
 * state; on return the world holds the reference state again.  During a
 * relaxation the probe sets the world's step hook (restoring the one it
 * found) and uses the coupling force P->f_coupling (enabled if absent, zero
 * on return) for the viscous force. */
#ifndef TL_DEM_PROBE_H
#define TL_DEM_PROBE_H

#include <stdint.h>
#include "tl_dem.h"

typedef enum { TL_PROBE_AFFINE = 0, TL_PROBE_RELAXED = 1 } TlProbeKind;

typedef struct {
  TlProbeKind kind;
  double strain;         /* ε (default 1e-6, the scripts' "up") */
  double jiggle;         /* a, m (default 0; the scripts: 1e-5) */
  uint64_t jiggle_seed;  /* seed of the jiggle (default 87287, the scripts') */
  /* relaxed probe */
  double viscous;        /* c of the global viscous force -c v, N s/m (default 0.5, the scripts') */
  double tolerance;      /* static balance: largest Δ_n (seeds/004 Eq. 19) of the grains
                          * that carry load, default 1e-4 */
  long max_steps;        /* longest relaxation, steps (default 1e6) */
  long check_every;      /* steps between balance checks (default 200) */
  int relax_reference;   /* relaxed: relax the reference first (default 1) */
  const char *scratch;   /* path of the scratch checkpoint (default "elastic_probe_reference.h5"
                          * in the working directory); removed on return */
} TlProbeSettings;

/* The defaults above. */
void tl_probe_settings_default(TlProbeSettings *s);

/* Cubic averages and isotropic moduli of a 6x6 tensor (Pa; the scripts'
 * formulas, seeds/000 §3.2 and in.elastic): C11c = mean of C11, C22, C33;
 * C12c = mean of C12, C13, C23 (symmetrised); C44c = mean of C44, C55, C66;
 * K = (C11c + 2 C12c)/3, G1 = C44c, G2 = (C11c - C12c)/2,
 * ν = 1/(1 + C11c/C12c), G = (G1 + G2)/2, E = 2 G (1 + ν),
 * Zener index Z = 2 C44c/(C11c - C12c) = G1/G2. */
typedef struct {
  double C11, C12, C44, K, G1, G2, G, E, nu, zener;
} TlElasticModuli;

void tl_elastic_moduli(const double (*C)[6], TlElasticModuli *m);

typedef struct {
  double C[6][6];        /* C_iJ, Pa: row i the stress component, column J the strain */
  double C_sym[6][6];    /* (C + Cᵀ)/2 */
  double C_pos[6][6];    /* (σ(+ε) - σ0)/ε */
  double C_neg[6][6];    /* (σ(-ε) - σ0)/(-ε) */
  double stress0[6];     /* reference stress, Voigt, Pa (tension positive) */
  double pressure0;      /* -trace/3 of the reference stress, Pa */
  TlElasticModuli moduli; /* of C_sym */
  double max_skew;       /* largest |σ_ab - σ_ba|/2 over the probes, Pa (spins out of balance) */
  /* relaxed probe: the largest step count and final imbalance over the 12
   * (13 with the reference) relaxations, and whether all met the tolerance */
  long relax_steps;
  double relax_imbalance;
  int relax_converged;
  /* each relaxation: the reference, then probe J with -ε ([J][0]) and +ε ([J][1]);
   * imbalance as for the tolerance */
  long reference_steps, probe_steps[6][2];
  double reference_imbalance, probe_imbalance[6][2];
} TlProbeResult;

/* Probes dem (set up, in a deformable periodic cell: tl_domain_init_cell)
 * with the given settings; dem ends in the reference state (jiggled and,
 * for the relaxed probe, relaxed).  Refuses an open or orthogonal-box
 * domain, walls, prescribed particles, ε outside
 * (0, 0.1], a jiggle < 0 or larger than the smallest radius. */
TlStatus tl_dem_probe_elastic(TlDem *dem, const TlProbeSettings *s, TlProbeResult *r);

/* The deformation gradient of probe J (0..5) with signed strain e. */
TlMat3 tl_probe_strain_map(int J, double e);

/* Maps the cell and every particle centre by F (x <- o + F (x - o)),
 * velocities and contact histories untouched. */
TlStatus tl_dem_map_affine(TlDem *dem, TlMat3 F);

#endif
