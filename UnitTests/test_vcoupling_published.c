/* Volume coupling: the choices of the authors' published runs
 * (tl_vcoupling_set_profile, _set_lumped_penalty, _set_reach_shrink): the
 * linear weight ramp, the row-sum lumped penalty matrix, the gathering
 * box shrunk by a particle diameter, and the element's lagged mismatch. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_solid.h"
#include "tl_test.h"
#include "tl_vcoupling.h"
#include "tl_vcoupling_element.h"

/* A 2 x 10 x 2 hex8 bar on y in [8, 12] (element size 0.4) and a simple
 * cubic lattice of n^3 particles per element on y in [6, 12]. */
enum { MAXP = 3000 };
static double xp[3 * MAXP], mp[MAXP], dup[3 * MAXP], fp[3 * MAXP];

static size_t make_lattice(int n)
{
  double d = 0.4 / n;
  size_t np = 0;
  int nx = (int)lround(0.8 / d), ny = (int)lround(6.0 / d);
  for (int j = 0; j < ny; ++j)
    for (int k = 0; k < nx; ++k)
      for (int i = 0; i < nx; ++i) {
        xp[3 * np] = (i + 0.5) * d;
        xp[3 * np + 1] = 6.0 + (j + 0.5) * d;
        xp[3 * np + 2] = (k + 0.5) * d;
        mp[np] = 1.0;
        ++np;
      }
  return np;
}

static TlVCoupling *create(const TlMesh *mesh, double c, int per_element)
{
  TlVCouplingParams p = {{1, 8.0, 12.0}, c, "lucy", 1e10, 4, per_element};
  TlVCoupling *vc = NULL;
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_OK);
  return vc;
}

/* The linear ramp: w = 1 - (y - 8) / 4 at the nodes and, interpolated by
 * the trilinear shape functions, exactly at every particle. */
static void test_linear_profile(const TlMesh *mesh)
{
  TlVCoupling *vc = create(mesh, 0.0, 0);
  if (!vc) return;
  TL_TEST_STATUS(tl_vcoupling_set_profile(vc, TL_VCOUPLING_LINEAR), TL_OK);
  const double *wn = tl_vcoupling_node_weights(vc);
  double worst = 0.0;
  for (size_t i = 0; i < mesh->n_nodes; ++i)
    worst = fmax(worst, fabs(wn[i] - (1.0 - (mesh->x[3 * i + 1] - 8.0) / 4.0)));
  TL_TEST_ASSERT(worst < 1e-14, "nodal weights off the linear ramp by %g", worst);
  size_t np = make_lattice(1);
  TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, np, xp, mp), TL_OK);
  static double w[MAXP];
  TL_TEST_STATUS(tl_vcoupling_point_weights(vc, np, xp, w), TL_OK);
  worst = 0.0;
  double sum = 0.0;
  for (size_t a = 0; a < np; ++a) {
    double y = xp[3 * a + 1], lin = y <= 8.0 ? 1.0 : 1.0 - (y - 8.0) / 4.0;
    worst = fmax(worst, fabs(w[a] - lin));
    if (y > 8.0) sum += w[a];
  }
  TL_TEST_ASSERT(worst < 1e-12, "particle weights off the linear ramp by %g", worst);
  /* ten layers of four at w = 0.95, 0.85, ..., 0.05: the weighted count is 20 */
  TL_TEST_CLOSE(sum, 20.0, 1e-10);
  /* the cosine comes back */
  TL_TEST_STATUS(tl_vcoupling_set_profile(vc, TL_VCOUPLING_COSINE), TL_OK);
  TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, np, xp, mp), TL_OK);
  TL_TEST_STATUS(tl_vcoupling_point_weights(vc, np, xp, w), TL_OK);
  int differs = 0;
  for (size_t a = 0; a < np; ++a)
    if (xp[3 * a + 1] > 8.0 && fabs(w[a] - (1.0 - (xp[3 * a + 1] - 8.0) / 4.0)) > 1e-3) differs = 1;
  TL_TEST_ASSERT(differs, "the cosine profile must differ from the ramp");
  TL_TEST_STATUS(tl_vcoupling_set_profile(vc, (TlVCouplingProfile)7), TL_ERR_ARG);
  /* weight_min: the zone's nodes, its ends included, span [0.1, 0.9] */
  TL_TEST_STATUS(tl_vcoupling_set_profile(vc, TL_VCOUPLING_LINEAR), TL_OK);
  TL_TEST_STATUS(tl_vcoupling_set_weight_min(vc, 0.1), TL_OK);
  wn = tl_vcoupling_node_weights(vc);
  worst = 0.0;
  for (size_t i = 0; i < mesh->n_nodes; ++i)
    worst = fmax(worst, fabs(wn[i] - (0.1 + 0.8 * (1.0 - (mesh->x[3 * i + 1] - 8.0) / 4.0))));
  TL_TEST_ASSERT(worst < 1e-12, "nodal weights off the ramp 0.9 -> 0.1 by %g", worst);
  double inside[3] = {0.3, 7.9, 0.3}, past[3] = {0.3, 12.1, 0.3}, wi[2];
  TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, np, xp, mp), TL_OK);
  TL_TEST_STATUS(tl_vcoupling_point_weights(vc, 1, inside, wi), TL_OK);
  TL_TEST_STATUS(tl_vcoupling_point_weights(vc, 1, past, wi + 1), TL_OK);
  TL_TEST_ASSERT(wi[0] == 1.0 && wi[1] == 0.0, "outside the zone w = 1 and 0, got %g and %g", wi[0], wi[1]);
  TL_TEST_STATUS(tl_vcoupling_set_weight_min(vc, 0.5), TL_ERR_ARG);
  TL_TEST_STATUS(tl_vcoupling_set_weight_min(vc, -0.1), TL_ERR_ARG);
  tl_vcoupling_destroy(&vc);
}

/* Lumped penalty: F_i = eps m_i r_i with m_i = int N_i dV over the
 * coupling elements (V / 8 per element holding node i on this uniform
 * mesh), Eq. 41 to round-off; switching back restores the consistent one. */
static void test_lumped_penalty(const TlMesh *mesh)
{
  TlVCoupling *vc = create(mesh, 0.0, 0);
  if (!vc) return;
  size_t np = make_lattice(2);
  unsigned seed = 7u;
  for (size_t a = 0; a < 3 * np; ++a) {
    seed = seed * 1103515245u + 12345u;
    dup[a] = 1e-4 * (((seed >> 8) & 0xffff) / 65535.0 - 0.5);
  }
  static double du_n[3 * 400], f_lumped[3 * 400], f_cons[3 * 400], ude[3 * 400];
  static char reached[400];
  TL_TEST_ASSERT(mesh->n_nodes <= 400, "mesh has %zu nodes", mesh->n_nodes);
  memset(du_n, 0, sizeof du_n);
  TL_TEST_STATUS(tl_vcoupling_set_lumped_penalty(vc, 1), TL_OK);
  TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, np, xp, mp), TL_OK);
  memset(f_lumped, 0, sizeof f_lumped);
  memset(fp, 0, sizeof fp);
  TlVCouplingDiag dg;
  TL_TEST_STATUS(tl_vcoupling_forces(vc, dup, du_n, f_lumped, fp, &dg), TL_OK);
  TL_TEST_ASSERT(dg.eq41 < 1e-13, "Eq. 41 with the lumped penalty: %g", dg.eq41);
  memset(reached, 0, sizeof reached);
  TL_TEST_STATUS(tl_vcoupling_homogenise(vc, dup, ude, reached), TL_OK);
  size_t ne;
  const size_t *el;
  tl_vcoupling_elements(vc, &ne, &el);
  static double mi[400];
  memset(mi, 0, sizeof mi);
  const double V = 0.4 * 0.4 * 0.4;
  for (size_t s = 0; s < ne; ++s)
    for (int k = 0; k < 8; ++k) mi[mesh->blocks[0].conn[el[s] * 8 + k]] += V / 8.0;
  double worst = 0.0, scale = 0.0;
  size_t checked = 0;
  for (size_t i = 0; i < mesh->n_nodes; ++i) {
    if (!reached[i]) continue;
    for (int d = 0; d < 3; ++d) {
      double want = 1e10 * mi[i] * ude[3 * i + d];
      worst = fmax(worst, fabs(f_lumped[3 * i + d] - want));
      scale = fmax(scale, fabs(want));
    }
    ++checked;
  }
  TL_TEST_ASSERT(checked > 0 && worst <= 1e-12 * scale, "lumped F_i off eps m_i r_i by %g (scale %g, %zu nodes)",
                 worst, scale, checked);
  TL_TEST_STATUS(tl_vcoupling_set_lumped_penalty(vc, 0), TL_OK);
  memset(f_cons, 0, sizeof f_cons);
  TL_TEST_STATUS(tl_vcoupling_forces(vc, dup, du_n, f_cons, NULL, &dg), TL_OK);
  double diff = 0.0, sum_l = 0.0, sum_c = 0.0;
  for (size_t i = 0; i < 3 * mesh->n_nodes; i += 3) {
    diff = fmax(diff, fabs(f_cons[i + 1] - f_lumped[i + 1]));
    sum_l += f_lumped[i + 1];
    sum_c += f_cons[i + 1];
  }
  TL_TEST_ASSERT(diff > 1e-3 * scale, "the consistent penalty must differ from the lumped one (%g)", diff);
  /* the same row sums: the total force is the same */
  TL_TEST_ASSERT(fabs(sum_l - sum_c) <= 1e-10 * scale * (double)mesh->n_nodes, "total force %g against %g", sum_l,
                 sum_c);
  tl_vcoupling_destroy(&vc);
}

/* The gathering box shrunk by a particle diameter d: at one particle per
 * element and c = d, each element's rows see its own particle alone, as
 * at c = 0 (Pi = 1 on it); with the whole reach c they see its neighbours. */
static void test_reach_shrink(const TlMesh *mesh)
{
  size_t np = make_lattice(1);
  for (int shrink = 0; shrink <= 1; ++shrink) {
    TlVCoupling *vc = create(mesh, 0.4, 1);
    if (!vc) return;
    TL_TEST_STATUS(tl_vcoupling_set_reach_shrink(vc, shrink ? 0.4 : 0.0), TL_OK);
    TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, np, xp, mp), TL_OK);
    size_t n;
    const size_t *node, *part;
    const double *val;
    tl_vcoupling_operator(vc, &n, &node, &part, &val);
    size_t ne;
    const size_t *el;
    tl_vcoupling_elements(vc, &ne, &el);
    if (shrink) {
      int ones = n == 8 * ne;
      for (size_t j = 0; j < n; ++j)
        if (fabs(val[j] - 1.0) > 1e-14) ones = 0;
      TL_TEST_ASSERT(ones, "shrunk by d: %zu entries (expected %zu), each 1", n, 8 * ne);
    } else {
      TL_TEST_ASSERT(n > 8 * ne, "whole reach c = d: %zu entries, expected more than %zu", n, 8 * ne);
    }
    tl_vcoupling_destroy(&vc);
  }
  TlVCoupling *vc = create(mesh, 0.4, 1);
  if (!vc) return;
  TL_TEST_STATUS(tl_vcoupling_set_reach_shrink(vc, -0.1), TL_ERR_ARG);
  TL_TEST_STATUS(tl_vcoupling_set_reach_shrink(vc, NAN), TL_ERR_ARG);
  tl_vcoupling_destroy(&vc);
}

/* The lagged order (tl_vcoupling_element_set_step_lagged): the nodal force
 * is that of the given displacements, whatever the solid's iterate, and the
 * particles take its reaction (Eq. 41). */
static void test_lagged(const TlMesh *mesh)
{
  TlVCoupling *vc = create(mesh, 0.0, 0);
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  TlVCouplingElement *el = NULL;
  TL_TEST_STATUS(tl_material_create("hooke", &mat), TL_OK);
  if (!vc || !mat) return;
  tl_material_set(mat, "E", 1e8);
  tl_material_set(mat, "nu", 0.0);
  tl_material_set(mat, "density", 1309.0);
  TL_TEST_STATUS(tl_material_setup(mat), TL_OK);
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  if (!solid) return;
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_vcoupling_element_create(vc, solid, &el), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  if (!el) return;
  size_t np = make_lattice(1), nn = mesh->n_nodes;
  static double du_n[3 * 400], u1[3 * 400], u2[3 * 400], f1[3 * 400], f2[3 * 400], fref[3 * 400];
  unsigned seed = 11u;
  for (size_t a = 0; a < 3 * np; ++a) {
    seed = seed * 1103515245u + 12345u;
    dup[a] = 1e-4 * (((seed >> 8) & 0xffff) / 65535.0 - 0.5);
  }
  for (size_t k = 0; k < 3 * nn; ++k) {
    seed = seed * 1103515245u + 12345u;
    du_n[k] = 1e-4 * (((seed >> 8) & 0xffff) / 65535.0 - 0.5);
    u1[k] = 0.0;
    u2[k] = 3.0 * du_n[k] + 1e-3;
  }
  TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, np, xp, mp), TL_OK);
  TL_TEST_STATUS(tl_vcoupling_element_set_step_lagged(el, dup, du_n), TL_OK);
  memset(f1, 0, sizeof f1);
  memset(f2, 0, sizeof f2);
  memset(fref, 0, sizeof fref);
  TL_TEST_STATUS(tl_vcoupling_element_nodal_forces(el, u1, f1), TL_OK);
  TL_TEST_STATUS(tl_vcoupling_element_nodal_forces(el, u2, f2), TL_OK);
  TL_TEST_STATUS(tl_vcoupling_forces(vc, dup, du_n, fref, NULL, NULL), TL_OK);
  double d12 = 0.0, dref = 0.0, scale = 0.0;
  for (size_t k = 0; k < 3 * nn; ++k) {
    d12 = fmax(d12, fabs(f1[k] - f2[k]));
    dref = fmax(dref, fabs(f1[k] - fref[k]));
    scale = fmax(scale, fabs(fref[k]));
  }
  TL_TEST_ASSERT(scale > 0.0 && d12 == 0.0, "lagged force depends on the iterate: %g (scale %g)", d12, scale);
  TL_TEST_ASSERT(dref <= 1e-14 * scale, "lagged force off the coupling's by %g", dref);
  memset(fp, 0, sizeof fp);
  TlVCouplingDiag dg;
  TL_TEST_STATUS(tl_vcoupling_element_particle_forces(el, u2, fp, &dg), TL_OK);
  TL_TEST_ASSERT(dg.eq41 < 1e-13, "Eq. 41 with the lagged mismatch: %g", dg.eq41);
  /* set_step goes back to the current mismatch: the force follows the iterate */
  TL_TEST_STATUS(tl_vcoupling_element_set_step(el, dup, u1), TL_OK);
  memset(f1, 0, sizeof f1);
  memset(f2, 0, sizeof f2);
  TL_TEST_STATUS(tl_vcoupling_element_nodal_forces(el, u1, f1), TL_OK);
  TL_TEST_STATUS(tl_vcoupling_element_nodal_forces(el, u2, f2), TL_OK);
  d12 = 0.0;
  for (size_t k = 0; k < 3 * nn; ++k) d12 = fmax(d12, fabs(f1[k] - f2[k]));
  TL_TEST_ASSERT(d12 > 1e-3 * scale, "current mismatch: the force must follow the iterate (%g)", d12);
  TL_TEST_STATUS(tl_vcoupling_element_set_step_lagged(el, dup, NULL), TL_ERR_ARG);
  tl_vcoupling_element_destroy(&el);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_vcoupling_destroy(&vc);
}

int main(void)
{
  if (tl_initialize() != TL_OK) {
    fprintf(stderr, "%s\n", tl_error_message());
    return 1;
  }
  TlMesh *mesh = NULL;
  size_t n[3] = {2, 10, 2};
  double lo[3] = {0, 8, 0}, hi[3] = {0.8, 12, 0.8};
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, n, lo, hi, &mesh), TL_OK);
  if (!mesh) return tl_test_report();
  test_linear_profile(mesh);
  test_lumped_penalty(mesh);
  test_reach_shrink(mesh);
  test_lagged(mesh);
  tl_mesh_destroy(&mesh);
  return tl_test_report();
}
