/* The perturbation operators that need the law's own path evaluation
 * (seeds/004 §2.5.1-2.5.2, Table 1):
 *   cto  the consistent tangent by forward differences of the NHL, each
 *        perturbation a full path from the committed state (Eq. 31):
 *        directions 9 (the default) perturbs G = dF F⁻¹ along the nine Λ^{kl}
 *        of Eq. 30 (four in 2-D); directions 6 perturbs along the six
 *        Green-strain directions F_J = F + ε F⁻ᵀ Γ_J (three in 2-D, spec §6),
 *        which give D = dS/dE column by column, consistent with the residual;
 *  aeo  the auxiliary elastic operator: the cto while the point is in its
 *        pre-peak regime, accumulating them; from the peak on the average of
 *        the pre-peak ones, frozen (one path per iteration instead of 1 + 9).
 * Both register in the nhl_operator registry next to the network operators. */
#include <math.h>
#include <string.h>

#include "tl_nhl_material.h"
#include "tl_nhl_operator.h"

/* c from the six (three) Green-strain directions. */
static TlStatus cto_green(const TlNhlOperator *op, const TlNhlOperatorInput *in, double c[81], TlNhlOperatorStats *st)
{
  static const int dirs3[6] = {0, 1, 2, 3, 4, 5}, dirs2[3] = {0, 1, 3};
  const int *dirs = in->dim == 2 ? dirs2 : dirs3, nd = in->dim == 2 ? 3 : 6;
  const double eps = op->eps;
  TlMat3 Fi;
  if (!tl_m3_inverse(in->F, &Fi)) TL_ERROR(TL_ERR_NUMERIC, "cto: F is singular (det %g)", tl_m3_det(in->F));
  const TlMat3 FiT = tl_m3_transpose(Fi);
  double S0[6], D[36];
  memset(D, 0, sizeof D);
  tl_voigt_from_sym(tl_nhl_cauchy_to_pk2(in->F, in->sigma), S0);
  for (int q = 0; q < nd; ++q) {
    const int J = dirs[q];
    const TlMat3 FJ = tl_m3_add(in->F, tl_m3_scale(tl_m3_mul(FiT, tl_voigt_unit_strain(J)), eps));
    TlMat3 s;
    TlNhlEvalStats es;
    memset(&es, 0, sizeof es);
    TL_CHECK(in->evaluate(in->ctx, TL_NHL_EVAL_PATH, FJ, &s, &es));
    st->evaluations++;
    st->dem_steps += es.dem_steps;
    st->imbalance = fmax(st->imbalance, es.imbalance);
    double SJ[6];
    tl_voigt_from_sym(tl_nhl_cauchy_to_pk2(FJ, s), SJ);
    for (int I = 0; I < 6; ++I) D[I * 6 + J] = (SJ[I] - S0[I]) / eps;
  }
  tl_nhl_operator_from_D(D, in->F, in->sigma, c);
  return TL_OK;
}

static TlStatus cto_compute(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *so, double *sn,
                            double c[81], TlNhlOperatorStats *st)
{
  (void)so, (void)sn;
  if (!in->evaluate) TL_ERROR(TL_ERR_STATE, "cto perturbs the law: the cell's owner gave no evaluate callback");
  if (op->directions > 7.5) return tl_nhl_operator_perturb(op, in, TL_NHL_EVAL_PATH, c, st);
  return cto_green(op, in, c, st);
}

/* aeo state: the sum of the pre-peak cto's (81) and their count. */
enum { AEO_STATE = 82 };

static TlStatus aeo_compute(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *so, double *sn,
                            double c[81], TlNhlOperatorStats *st)
{
  const double count = so[81];
  if (!in->pre_peak && count > 0.0) {
    for (int q = 0; q < 81; ++q) c[q] = so[q] / count;
    return TL_OK;
  }
  TL_CHECK(cto_compute(op, in, so, sn, c, st));
  if (in->pre_peak) {
    for (int q = 0; q < 81; ++q) sn[q] = so[q] + c[q];
    sn[81] = count + 1.0;
  }
  return TL_OK;
}

static const TlNhlOperatorOps cto_ops = {
    .header = {"nhl_operator", "cto",
               "consistent tangent operator: forward differences of the whole NHL path from the committed state "
               "(seeds/004 Eq. 31), 9 directions of Eq. 30 (4 in 2-D) or 6 Green-strain directions (3 in 2-D)"},
    .size = sizeof(TlNhlOperator),
    .compute = cto_compute,
};

static const TlNhlOperatorOps aeo_ops = {
    .header = {"nhl_operator", "aeo",
               "auxiliary elastic operator: the cto in the pre-peak regime, then the average of the pre-peak cto's, "
               "frozen (seeds/004 §2.5.2; the regime per point from its deviatoric stress, a reading)"},
    .size = sizeof(TlNhlOperator),
    .state_size = AEO_STATE,
    .compute = aeo_compute,
};

extern const TlMaterialOps tl_nhl_dem_cell_ops;

TlStatus tl_hierarchical_register_all(void)
{
  TL_CHECK(tl_material_register(&tl_nhl_dem_cell_ops));
  TL_CHECK(tl_nhl_operator_register(&cto_ops));
  TL_CHECK(tl_nhl_operator_register(&aeo_ops));
  return TL_OK;
}
