/* The point-by-point evaluation of a solid (TL_SOLID_EVAL_POINTS) on two
 * threads, whose points run costliest first (LPT) once their costs are
 * measured, gives the same bits as on one thread.
 *
 * A 3 x 3 Q8 block of a dem_cell material whose stand-in law (Hooke's law,
 * as test_nhl_fake_law) spins for a time that depends on the point's F, so
 * the measured costs differ and the LPT order is not the points' order; the
 * block's internal force and tangent under a non-uniform displacement are
 * compared with the one-thread evaluation, on the first two-thread
 * evaluation (the order of the one-thread costs) and a second one (its own
 * costs).  A point's result stored at another point's index changes both. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_memory.h"
#include "tl_nhl_material.h"
#include "tl_nhl_operator.h"
#include "tl_solid.h"
#include "tl_test.h"

static volatile double sink;

static TlStatus slow_hooke(void *ctx, TlMat3 F, TlMat3 *sigma)
{
  /* 20-400 us of work chosen by F (points differ, perturbations alike) */
  const int spins = 2000 + (int)(38000.0 * fabs(sin(1e3 * (F.m[0][0] + 3.0 * F.m[1][0]))));
  double acc = 0.0;
  for (int k = 0; k < spins; ++k) acc += 1e-9 * k;
  sink = acc;
  TlMat3 S;
  TL_CHECK(tl_material_evaluate((const TlMaterial *)ctx, 1, &F, NULL, NULL, &S, NULL, NULL));
  *sigma = tl_nhl_pk2_to_cauchy(F, S);
  return TL_OK;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  TlMaterial *law = NULL, *m = NULL;
  TL_TEST_STATUS(tl_material_create("saint_venant_kirchhoff", &law), TL_OK);
  if (!law) return tl_test_report();
  TL_TEST_STATUS(tl_material_set(law, "E", 1e7), TL_OK);
  TL_TEST_STATUS(tl_material_set(law, "nu", 0.3), TL_OK);
  TL_TEST_STATUS(tl_material_setup(law), TL_OK);
  TL_TEST_STATUS(tl_material_create("dem_cell", &m), TL_OK);
  if (!m) return tl_test_report();
  TL_TEST_STATUS(tl_nhl_material_set_analytic(m, slow_hooke, law), TL_OK);
  TL_TEST_STATUS(tl_nhl_material_set_operator(m, "cto"), TL_OK);
  TL_TEST_STATUS(tl_material_setup(m), TL_OK);

  size_t n[2] = {3, 3};
  double lo[2] = {0, 0}, hi[2] = {1.0, 1.0};
  TlMesh *mesh = NULL;
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_mesh_create_rectangle(&tl_element_quad8, n, lo, hi, &mesh), TL_OK);
  if (mesh) TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  if (!solid) return tl_test_report();
  TL_TEST_STATUS(tl_solid_set_material(solid, NULL, m), TL_OK);
  TL_TEST_STATUS(tl_solid_fix(solid, "xmin", 3), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);

  const size_t nn = mesh->n_nodes, nu = 2 * nn;
  double *u = NULL, *f1 = NULL, *f2 = NULL;
  TL_TEST_STATUS(tl_calloc(&u, nu, sizeof *u), TL_OK);
  TL_TEST_STATUS(tl_calloc(&f1, nu, sizeof *f1), TL_OK);
  TL_TEST_STATUS(tl_calloc(&f2, nu, sizeof *f2), TL_OK);
  if (!u || !f1 || !f2) return tl_test_report();
  /* a non-uniform field: every Gauss point its own F */
  for (size_t I = 0; I < nn; ++I) {
    const double x = mesh->x[3 * I], y = mesh->x[3 * I + 1];
    u[2 * I] = 0.02 * x * x + 0.01 * x * y;
    u[2 * I + 1] = 0.015 * x * x * y - 0.01 * x;
  }
  TlSparse *K1 = NULL, *K2 = NULL;
  TlMechSystem *sys = tl_solid_system(solid);
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 0, &K1), TL_OK);
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 0, &K2), TL_OK);
  if (!K1 || !K2) return tl_test_report();

  TL_TEST_STATUS(tl_solid_set_evaluation(solid, TL_SOLID_EVAL_POINTS, 1), TL_OK);
  TL_TEST_STATUS(tl_solid_block_forces(solid, 0, u, f1, 1.0, K1, NULL), TL_OK);
  TlSolidEvalStats es;
  tl_solid_get_evaluation_stats(solid, &es);
  const double mean = es.points ? es.t_points / (double)es.points : 0.0;
  printf("one thread: %ld points, %.3g us per point on average, costliest %.3g us\n", es.points, 1e6 * mean,
         1e6 * es.t_last_max);
  /* the LPT path takes points of 5 us or more on average */
  TL_TEST_ASSERT(mean >= 5e-6, "a point costs %g s on average: below the LPT path's 5e-6 s (the law must be slower)",
                 mean);
  for (int pass = 0; pass < 2; ++pass) {
    TL_TEST_STATUS(tl_solid_set_evaluation(solid, TL_SOLID_EVAL_POINTS, 2), TL_OK); /* re-evaluates */
    memset(f2, 0, nu * sizeof *f2);
    tl_sparse_zero(K2);
    TL_TEST_STATUS(tl_solid_block_forces(solid, 0, u, f2, 1.0, K2, NULL), TL_OK);
    size_t df = 0, dk = 0;
    double fmax_ = 0.0;
    for (size_t k = 0; k < nu; ++k) {
      df += f1[k] != f2[k];
      fmax_ = fmax(fmax_, fabs(f1[k]));
    }
    for (TlSparseIndex p = 0; p < K1->nnz; ++p) dk += K1->values[p] != K2->values[p];
    printf("two threads, pass %d: %zu of %zu force entries and %zu of %lld tangent entries differ from one thread "
           "(largest force %.3g N)\n",
           pass + 1, df, nu, dk, (long long)K1->nnz, fmax_);
    TL_TEST_ASSERT(fmax_ > 0.0, "the block carries no force: the check sees nothing");
    TL_TEST_ASSERT(df == 0, "pass %d: %zu force entries differ between one and two threads", pass + 1, df);
    TL_TEST_ASSERT(dk == 0, "pass %d: %zu tangent entries differ between one and two threads", pass + 1, dk);
  }
  tl_sparse_destroy(&K1);
  tl_sparse_destroy(&K2);
  tl_free(&u);
  tl_free(&f1);
  tl_free(&f2);
  tl_solid_destroy(&solid);
  tl_mesh_destroy(&mesh);
  tl_material_destroy(&m);
  tl_material_destroy(&law);
  return tl_test_report();
}
