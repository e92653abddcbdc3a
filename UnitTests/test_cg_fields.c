/* CG fields on arrays: mass and momentum integrals, neighbour search
 * against the brute-force oracle, the volume average of the CG stress of a
 * static periodic packing against its Cauchy-Poisson stress (seeds/004
 * Eq. 27), kinetic stress, boundary force density, time averaging, and the
 * refusals. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include "talus.h"
#include "tl_cg_fields.h"
#include "tl_test.h"

static double uniform(uint64_t *s)
{
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

static const double gl5x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
static const double gl5w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};

/* Mass and momentum of isolated particles (supports disjoint), integrated
 * with a spherical quadrature around each particle that is exact for a
 * radial integrand: tolerance 1e-10.  Some particles sit across the
 * periodic boundary, so the nearest image is exercised. */
static void test_mass_isolated(const char *name)
{
  const double c = 0.8;
  TlCGKernel *k;
  TL_TEST_STATUS(tl_cg_kernel_create(name, c, 3, &k), TL_OK);
  TlCGBox box = {tl_v3(0, 0, 0), tl_v3(10, 8, 6), {1, 1, 0}};
  TlVec3 x[5] = {{0.1, 4, 3}, {9.9, 7.95, 1.0}, {5, 5, 5}, {5, 0.3, 1.2}, {2.5, 2.5, 3.0}};
  double m[5] = {1.0, 2.5, 0.3, 7.0, 1.1};
  TlVec3 v[5] = {{1, 0, 0}, {0, -2, 1}, {3, 3, 3}, {0.5, 0, -1}, {-1, 2, 0}};
  TlCGParticleArrays p = {5, x, m, v};
  TlCG *cg;
  TL_TEST_STATUS(tl_cg_create(k, &box, 0, &cg), TL_OK);
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, NULL, NULL), TL_OK);
  enum { NR = 8 * 5, NT = 5, NP = 7, NQ = NR * NT * NP };
  TlVec3 *pts = malloc(NQ * sizeof *pts);
  double *wq = malloc(NQ * sizeof *wq);
  TlCGFields *f;
  TL_TEST_STATUS(tl_cg_fields_create(NQ, TL_CG_DENSITY | TL_CG_MOMENTUM, &f), TL_OK);
  double mass = 0.0, total_mass = 0.0;
  TlVec3 mom = tl_v3(0, 0, 0), total_mom = tl_v3(0, 0, 0);
  for (int a = 0; a < 5; ++a) {
    int q = 0;
    for (int ir = 0; ir < NR; ++ir)
      for (int it = 0; it < NT; ++it)
        for (int ip = 0; ip < NP; ++ip) {
          double r = c * (ir / 5 + 0.5 * (1 + gl5x[ir % 5])) / 8.0, wr = c * gl5w[ir % 5] / 16.0;
          double ct = gl5x[it], st = sqrt(1 - ct * ct), ph = 2 * TL_PI * (ip + 0.3) / NP;
          /* wrapped into the box along periodic directions, as a grid would be */
          TlVec3 y = tl_v3_add(x[a], tl_v3(r * st * cos(ph), r * st * sin(ph), r * ct));
          y.x = fmod(y.x + 10.0, 10.0);
          y.y = fmod(y.y + 8.0, 8.0);
          pts[q] = y;
          wq[q] = wr * r * r * gl5w[it] * (2 * TL_PI / NP);
          ++q;
        }
    TL_TEST_STATUS(tl_cg_evaluate_points(cg, NQ, pts, f), TL_OK);
    for (int q2 = 0; q2 < NQ; ++q2) {
      mass += wq[q2] * f->density[q2];
      mom = tl_v3_axpy(mom, wq[q2], f->momentum[q2]);
    }
    total_mass += m[a];
    total_mom = tl_v3_axpy(total_mom, m[a], v[a]);
  }
  TL_TEST_ASSERT(fabs(mass - total_mass) < 1e-10 * total_mass, "%s: mass %.15g vs %.15g", name, mass, total_mass);
  /* outside the balls the field is exactly zero, so the integral over the
   * balls is the integral over the whole (enclosing) box */
  {
    uint64_t st = 17;
    int outside = 0, nonzero = 0;
    for (int q = 0; q < NQ; ++q) {
      TlVec3 y = tl_v3(10.0 * uniform(&st), 8.0 * uniform(&st), 6.0 * uniform(&st));
      int in = 0;
      for (int a = 0; a < 5; ++a) {
        TlVec3 dd = tl_v3_sub(y, x[a]);
        dd.x -= 10.0 * nearbyint(dd.x / 10.0);
        dd.y -= 8.0 * nearbyint(dd.y / 8.0);
        in |= tl_v3_norm(dd) < c;
      }
      pts[q] = y;
      wq[q] = in ? 0.0 : 1.0;
      outside += !in;
    }
    TL_TEST_STATUS(tl_cg_evaluate_points(cg, NQ, pts, f), TL_OK);
    for (int q = 0; q < NQ; ++q) nonzero += wq[q] > 0.0 && (f->density[q] != 0.0 || tl_v3_norm(f->momentum[q]) != 0.0);
    TL_TEST_ASSERT(outside > 100 && nonzero == 0, "%s: %d of %d points outside every support see a field", name,
                   nonzero, outside);
  }
  TL_TEST_ASSERT(tl_v3_norm(tl_v3_sub(mom, total_mom)) < 1e-10 * tl_v3_norm(total_mom),
                 "%s: momentum (%.15g %.15g %.15g) vs (%.15g %.15g %.15g)", name, mom.x, mom.y, mom.z,
                 total_mom.x, total_mom.y, total_mom.z);
  tl_cg_fields_destroy(&f);
  free(pts);
  free(wq);
  tl_cg_destroy(&cg);
  tl_cg_kernel_destroy(&k);
}

/* A random cloud with contacts and wall contacts. */
typedef struct {
  size_t n, nc, nw;
  TlVec3 *x, *v, *cx, *cb, *cf, *wp, *wf, *wc;
  double *m;
} Cloud;

static void cloud_make(Cloud *cl, size_t n, TlVec3 L, uint64_t seed, double reach)
{
  uint64_t s = seed;
  cl->n = n;
  cl->x = malloc(n * sizeof(TlVec3));
  cl->v = malloc(n * sizeof(TlVec3));
  cl->m = malloc(n * sizeof(double));
  for (size_t i = 0; i < n; ++i) {
    cl->x[i] = tl_v3(L.x * uniform(&s), L.y * uniform(&s), L.z * uniform(&s));
    cl->v[i] = tl_v3(uniform(&s) - 0.5, uniform(&s) - 0.5, uniform(&s) - 0.5);
    cl->m[i] = 0.5 + uniform(&s);
  }
  cl->nc = 2 * n;
  cl->cx = malloc(cl->nc * sizeof(TlVec3));
  cl->cb = malloc(cl->nc * sizeof(TlVec3));
  cl->cf = malloc(cl->nc * sizeof(TlVec3));
  for (size_t i = 0; i < cl->nc; ++i) {
    cl->cx[i] = cl->x[i % n];
    cl->cb[i] = tl_v3(reach * (uniform(&s) - 0.5), reach * (uniform(&s) - 0.5), reach * (uniform(&s) - 0.5));
    cl->cf[i] = tl_v3(uniform(&s) - 0.5, uniform(&s) - 0.5, uniform(&s) - 0.5);
  }
  cl->nw = n / 4;
  cl->wp = malloc(cl->nw * sizeof(TlVec3));
  cl->wf = malloc(cl->nw * sizeof(TlVec3));
  cl->wc = malloc(cl->nw * sizeof(TlVec3));
  for (size_t i = 0; i < cl->nw; ++i) {
    cl->wc[i] = cl->x[i];
    cl->wp[i] = tl_v3(cl->x[i].x, cl->x[i].y, cl->x[i].z - 0.3 * reach);
    cl->wf[i] = tl_v3(0.1 * (uniform(&s) - 0.5), 0.1 * (uniform(&s) - 0.5), uniform(&s));
  }
}

static void cloud_free(Cloud *cl)
{
  free(cl->x); free(cl->v); free(cl->m); free(cl->cx); free(cl->cb); free(cl->cf);
  free(cl->wp); free(cl->wf); free(cl->wc);
}

static double mat_diff(TlMat3 a, TlMat3 b)
{
  double d = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) d = fmax(d, fabs(a.m[i][j] - b.m[i][j]));
  return d;
}

/* Binned search against the brute-force oracle, open and periodic. */
static void test_search_vs_brute(int periodic)
{
  TlVec3 L = tl_v3(6, 5, 4);
  Cloud cl;
  cloud_make(&cl, 400, L, 12345u + (uint64_t)periodic, 0.6);
  TlCGKernel *k;
  TL_TEST_STATUS(tl_cg_kernel_create("lucy", 0.9, 3, &k), TL_OK);
  TlCGBox box = {tl_v3(0, 0, 0), L, {periodic, periodic, 0}};
  TlCG *cg;
  TL_TEST_STATUS(tl_cg_create(k, periodic ? &box : NULL, 0, &cg), TL_OK);
  TlCGParticleArrays p = {cl.n, cl.x, cl.m, cl.v};
  TlCGContactArrays c = {cl.nc, cl.cx, cl.cb, cl.cf};
  TlCGWallContactArrays w = {cl.nw, cl.wp, cl.wf, cl.wc};
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, &c, &w), TL_OK);
  enum { NP = 300 };
  TlVec3 pts[NP];
  uint64_t s = 99;
  for (int i = 0; i < NP; ++i) pts[i] = tl_v3(L.x * uniform(&s), L.y * uniform(&s), L.z * (1.4 * uniform(&s) - 0.2));
  TlCGFields *a, *b;
  TL_TEST_STATUS(tl_cg_fields_create(NP, TL_CG_ALL, &a), TL_OK);
  TL_TEST_STATUS(tl_cg_fields_create(NP, TL_CG_ALL, &b), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_points(cg, NP, pts, a), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_points_brute_force(cg, NP, pts, b), TL_OK);
  double worst = 0.0, scale = 0.0, nonzero = 0;
  for (int i = 0; i < NP; ++i) {
    worst = fmax(worst, fabs(a->density[i] - b->density[i]));
    worst = fmax(worst, tl_v3_norm(tl_v3_sub(a->momentum[i], b->momentum[i])));
    worst = fmax(worst, mat_diff(a->stress_contact[i], b->stress_contact[i]));
    worst = fmax(worst, mat_diff(a->stress_kinetic[i], b->stress_kinetic[i]));
    worst = fmax(worst, mat_diff(a->fabric[i], b->fabric[i]));
    worst = fmax(worst, tl_v3_norm(tl_v3_sub(a->boundary_force[i], b->boundary_force[i])));
    scale = fmax(scale, b->density[i]);
    nonzero += tl_v3_norm(b->boundary_force[i]) > 0.0;
  }
  TL_TEST_ASSERT(scale > 1.0 && nonzero > 5, "the comparison sees data (max density %g, %g wall points)", scale, nonzero);
  TL_TEST_ASSERT(worst < 1e-12 * scale, "periodic %d: binned vs brute force differ by %g", periodic, worst);
  tl_cg_fields_destroy(&a);
  tl_cg_fields_destroy(&b);
  tl_cg_destroy(&cg);
  tl_cg_kernel_destroy(&k);
  cloud_free(&cl);
}

/* Particle candidates through the DEM world's hierarchical grid against the
 * brute-force oracle, open and periodic. */
static void test_hgrid(int periodic)
{
  TlVec3 L = tl_v3(6, 5, 4);
  Cloud cl;
  cloud_make(&cl, 500, L, 4321u + (uint64_t)periodic, 0.6);
  double *radius = malloc(cl.n * sizeof *radius);
  uint64_t s = 3;
  for (size_t i = 0; i < cl.n; ++i) radius[i] = 0.05 + 0.1 * uniform(&s);
  TlDomain dom;
  int per[3] = {periodic, periodic, 0};
  if (periodic) TL_TEST_STATUS(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, 0), L, per), TL_OK);
  else TL_TEST_STATUS(tl_domain_init_open(&dom, tl_v3(0, 0, 0), L), TL_OK);
  TlHGrid *hg = NULL;
  TL_TEST_STATUS(tl_hgrid_create(&hg), TL_OK);
  TL_TEST_STATUS(tl_hgrid_build(hg, &dom, cl.n, cl.x, radius, 0.02), TL_OK);
  TlCGKernel *k;
  TL_TEST_STATUS(tl_cg_kernel_create("lucy", 0.8, 3, &k), TL_OK);
  TlCGBox box = {tl_v3(0, 0, 0), L, {periodic, periodic, 0}};
  TlCG *cg;
  TL_TEST_STATUS(tl_cg_create(k, periodic ? &box : NULL, 0, &cg), TL_OK);
  TL_TEST_STATUS(tl_cg_use_hgrid(cg, hg), TL_OK);
  TlCGParticleArrays p = {cl.n, cl.x, cl.m, cl.v};
  TlCGContactArrays c = {cl.nc, cl.cx, cl.cb, cl.cf};
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, &c, NULL), TL_OK);
  enum { NP = 300 };
  TlVec3 pts[NP];
  for (int i = 0; i < NP; ++i) pts[i] = tl_v3(L.x * uniform(&s), L.y * uniform(&s), L.z * (1.4 * uniform(&s) - 0.2));
  TlCGFields *a, *b;
  TL_TEST_STATUS(tl_cg_fields_create(NP, TL_CG_ALL, &a), TL_OK);
  TL_TEST_STATUS(tl_cg_fields_create(NP, TL_CG_ALL, &b), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_points(cg, NP, pts, a), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_points_brute_force(cg, NP, pts, b), TL_OK);
  double worst = 0.0, scale = 0.0;
  for (int i = 0; i < NP; ++i) {
    worst = fmax(worst, fabs(a->density[i] - b->density[i]));
    worst = fmax(worst, tl_v3_norm(tl_v3_sub(a->momentum[i], b->momentum[i])));
    worst = fmax(worst, mat_diff(a->stress_kinetic[i], b->stress_kinetic[i]));
    worst = fmax(worst, mat_diff(a->stress_contact[i], b->stress_contact[i]));
    scale = fmax(scale, b->density[i]);
  }
  TL_TEST_ASSERT(scale > 1.0, "hgrid comparison sees data (max density %g)", scale);
  TL_TEST_ASSERT(worst < 1e-12 * scale, "periodic %d: hierarchical-grid candidates vs brute force differ by %g", periodic,
                 worst);
  /* a grid built on other particles is refused */
  TlCGParticleArrays fewer = {cl.n - 1, cl.x, cl.m, cl.v};
  TL_TEST_STATUS(tl_cg_set_data(cg, &fewer, NULL, NULL), TL_ERR_ARG);
  tl_cg_fields_destroy(&a);
  tl_cg_fields_destroy(&b);
  tl_cg_destroy(&cg);
  tl_cg_kernel_destroy(&k);
  tl_hgrid_destroy(&hg);
  free(radius);
  cloud_free(&cl);
}

/* Grid fields (scatter from sources) against point fields at the nodes
 * (gather through the bins), open and periodic: every field. */
static void test_grid_vs_points(int periodic)
{
  TlVec3 L = tl_v3(6, 5, 4);
  Cloud cl;
  cloud_make(&cl, 300, L, 555u + (uint64_t)periodic, 0.6);
  TlCGKernel *k;
  TL_TEST_STATUS(tl_cg_kernel_create("gaussian", 1.1, 3, &k), TL_OK);
  TlCGBox box = {tl_v3(0, 0, 0), L, {periodic, periodic, 0}};
  TlCG *cg;
  TL_TEST_STATUS(tl_cg_create(k, periodic ? &box : NULL, 0, &cg), TL_OK);
  TlCGParticleArrays p = {cl.n, cl.x, cl.m, cl.v};
  TlCGContactArrays c = {cl.nc, cl.cx, cl.cb, cl.cf};
  TlCGWallContactArrays w = {cl.nw, cl.wp, cl.wf, cl.wc};
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, &c, &w), TL_OK);
  /* a grid that does not tile the periodic box, with nodes outside it */
  TlCGGrid g = {tl_v3(-0.7, -0.3, -1.0), tl_v3(0.45, 0.5, 0.55), {17, 13, 12}};
  size_t nodes = 17 * 13 * 12;
  TlVec3 *pts = malloc(nodes * sizeof *pts);
  for (int kk = 0; kk < 12; ++kk)
    for (int j = 0; j < 13; ++j)
      for (int i = 0; i < 17; ++i) pts[i + 17 * (j + 13 * kk)] = tl_cg_grid_node(&g, i, j, kk);
  TlCGFields *a, *b;
  TL_TEST_STATUS(tl_cg_fields_create(nodes, TL_CG_ALL, &a), TL_OK);
  TL_TEST_STATUS(tl_cg_fields_create(nodes, TL_CG_ALL, &b), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_grid(cg, &g, a), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_points(cg, nodes, pts, b), TL_OK);
  double worst = 0.0, scale = 0.0;
  for (size_t i = 0; i < nodes; ++i) {
    worst = fmax(worst, fabs(a->density[i] - b->density[i]));
    worst = fmax(worst, tl_v3_norm(tl_v3_sub(a->momentum[i], b->momentum[i])));
    worst = fmax(worst, tl_v3_norm(tl_v3_sub(a->velocity[i], b->velocity[i])));
    worst = fmax(worst, mat_diff(a->stress_contact[i], b->stress_contact[i]));
    worst = fmax(worst, mat_diff(a->stress_kinetic[i], b->stress_kinetic[i]));
    worst = fmax(worst, mat_diff(a->fabric[i], b->fabric[i]));
    worst = fmax(worst, tl_v3_norm(tl_v3_sub(a->boundary_force[i], b->boundary_force[i])));
    scale = fmax(scale, b->density[i]);
  }
  TL_TEST_ASSERT(scale > 1.0, "grid sees data (max density %g)", scale);
  TL_TEST_ASSERT(worst < 1e-12 * scale, "periodic %d: grid scatter vs point gather differ by %g", periodic, worst);
  /* the grid is the same to the bit whatever the number of threads */
#ifdef _OPENMP
  {
    int threads = omp_get_max_threads();
    omp_set_num_threads(threads > 1 ? 1 : 2);
    TlCG *cg1;
    TL_TEST_STATUS(tl_cg_create(k, periodic ? &box : NULL, 0, &cg1), TL_OK);
    TL_TEST_STATUS(tl_cg_set_data(cg1, &p, &c, &w), TL_OK);
    TL_TEST_STATUS(tl_cg_evaluate_grid(cg1, &g, b), TL_OK);
    omp_set_num_threads(threads);
    int same = memcmp(a->density, b->density, nodes * sizeof(double)) == 0 &&
               memcmp(a->stress_contact, b->stress_contact, nodes * sizeof(TlMat3)) == 0 &&
               memcmp(a->stress_kinetic, b->stress_kinetic, nodes * sizeof(TlMat3)) == 0 &&
               memcmp(a->boundary_force, b->boundary_force, nodes * sizeof(TlVec3)) == 0;
    TL_TEST_ASSERT(same, "periodic %d: grid fields differ between %d and %d threads", periodic, threads,
                   threads > 1 ? 1 : 2);
    tl_cg_destroy(&cg1);
  }
#endif
  free(pts);
  tl_cg_fields_destroy(&a);
  tl_cg_fields_destroy(&b);
  tl_cg_destroy(&cg);
  tl_cg_kernel_destroy(&k);
  cloud_free(&cl);
}

/* Overlapping particles: grid integral of density and momentum over a
 * grid enclosing them (trapezoid rule of the Lucy kernel, C^2 at r = c). */
static void test_mass_grid(void)
{
  TlVec3 L = tl_v3(3, 3, 3);
  Cloud cl;
  cloud_make(&cl, 60, L, 777u, 0.3);
  const double c = 0.6;
  TlCGKernel *k;
  TL_TEST_STATUS(tl_cg_kernel_create("lucy", c, 3, &k), TL_OK);
  TlCG *cg;
  TL_TEST_STATUS(tl_cg_create(k, NULL, 0, &cg), TL_OK);
  TlCGParticleArrays p = {cl.n, cl.x, cl.m, cl.v};
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, NULL, NULL), TL_OK);
  double h = c / 12.0;
  TlCGGrid g = {tl_v3(-c, -c, -c), tl_v3(h, h, h), {0, 0, 0}};
  for (int d = 0; d < 3; ++d) g.n[d] = (int)ceil(((&L.x)[d] + 2 * c) / h) + 1;
  size_t nodes = (size_t)g.n[0] * g.n[1] * g.n[2];
  TlCGFields *f;
  TL_TEST_STATUS(tl_cg_fields_create(nodes, TL_CG_DENSITY | TL_CG_MOMENTUM, &f), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_grid(cg, &g, f), TL_OK);
  double mass = 0, M = 0;
  TlVec3 mom = tl_v3(0, 0, 0), P = tl_v3(0, 0, 0);
  for (size_t i = 0; i < nodes; ++i) {
    mass += f->density[i] * h * h * h;
    mom = tl_v3_axpy(mom, h * h * h, f->momentum[i]);
  }
  for (size_t i = 0; i < cl.n; ++i) {
    M += cl.m[i];
    P = tl_v3_axpy(P, cl.m[i], cl.v[i]);
  }
  TL_TEST_ASSERT(fabs(mass - M) < 1e-6 * M, "grid mass %.12g vs %.12g", mass, M);
  TL_TEST_ASSERT(tl_v3_norm(tl_v3_sub(mom, P)) < 1e-6 * M, "grid momentum off by %g",
                 tl_v3_norm(tl_v3_sub(mom, P)));
  /* the Dirac kernel on the same grid (cell averages) conserves exactly */
  TlCGKernel *dk;
  TL_TEST_STATUS(tl_cg_kernel_create("dirac", 0.0, 3, &dk), TL_OK);
  TlCG *dcg;
  TL_TEST_STATUS(tl_cg_create(dk, NULL, 0, &dcg), TL_OK);
  TL_TEST_STATUS(tl_cg_set_data(dcg, &p, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_grid(dcg, &g, f), TL_OK);
  mass = 0;
  mom = tl_v3(0, 0, 0);
  for (size_t i = 0; i < nodes; ++i) {
    mass += f->density[i] * h * h * h;
    mom = tl_v3_axpy(mom, h * h * h, f->momentum[i]);
  }
  TL_TEST_ASSERT(fabs(mass - M) < 1e-12 * M, "dirac grid mass %.15g vs %.15g", mass, M);
  TL_TEST_ASSERT(tl_v3_norm(tl_v3_sub(mom, P)) < 1e-12 * M, "dirac grid momentum off by %g",
                 tl_v3_norm(tl_v3_sub(mom, P)));
  TlVec3 one = tl_v3(1, 1, 1);
  TlCGFields *f1;
  TL_TEST_STATUS(tl_cg_fields_create(1, TL_CG_DENSITY, &f1), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_points(dcg, 1, &one, f1), TL_ERR_UNSUPPORTED);
  tl_cg_fields_destroy(&f1);
  tl_cg_destroy(&dcg);
  tl_cg_kernel_destroy(&dk);
  tl_cg_fields_destroy(&f);
  tl_cg_destroy(&cg);
  tl_cg_kernel_destroy(&k);
  cloud_free(&cl);
}

/* A static periodic packing: a perturbed simple cubic lattice of spheres
 * slightly larger than the spacing, linear springs on overlapping pairs.
 * The volume average of the CG stress over the periodic box must equal the
 * Cauchy-Poisson stress (1/V) sum f (x) b. */
static void test_stress_periodic(const char *name, double c, double tol)
{
  const int m = 5;
  const double a = 1.0, d = 1.04, kn = 1000.0;
  const double Lb = m * a;
  int n = m * m * m;
  TlVec3 *x = malloc(n * sizeof *x);
  double *mass = malloc(n * sizeof *mass);
  TlVec3 *v = calloc(n, sizeof *v);
  uint64_t s = 4242;
  for (int i = 0; i < n; ++i) {
    x[i] = tl_v3((i % m + 0.5) * a + 0.02 * (uniform(&s) - 0.5), ((i / m) % m + 0.5) * a + 0.02 * (uniform(&s) - 0.5),
                 (i / (m * m) + 0.5) * a + 0.02 * (uniform(&s) - 0.5));
    mass[i] = 1.0;
  }
  TlVec3 *cx = malloc(6 * n * sizeof *cx), *cb = malloc(6 * n * sizeof *cb), *cf = malloc(6 * n * sizeof *cf);
  int nc = 0;
  TlMat3 cauchy = tl_m3_zero();
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      TlVec3 b = tl_v3_sub(x[j], x[i]);
      b.x -= Lb * nearbyint(b.x / Lb);
      b.y -= Lb * nearbyint(b.y / Lb);
      b.z -= Lb * nearbyint(b.z / Lb);
      double r = tl_v3_norm(b);
      if (r < d) {
        TlVec3 f = tl_v3_scale(b, -kn * (d - r) / r); /* on i from j: repulsive */
        cx[nc] = x[i];
        cb[nc] = b;
        cf[nc] = f;
        cauchy = tl_m3_add(cauchy, tl_m3_outer(f, b));
        ++nc;
      }
    }
  cauchy = tl_m3_scale(cauchy, 1.0 / (Lb * Lb * Lb));
  TL_TEST_ASSERT(nc >= 3 * n - 10 && cauchy.m[0][0] < 0.0, "packing has %d contacts, sxx %g (compressive)", nc,
                 cauchy.m[0][0]);
  TlCGKernel *k;
  TL_TEST_STATUS(tl_cg_kernel_create(name, c, 3, &k), TL_OK);
  TlCGBox box = {tl_v3(0, 0, 0), tl_v3(Lb, Lb, Lb), {1, 1, 1}};
  TlCG *cg;
  TL_TEST_STATUS(tl_cg_create(k, &box, 0, &cg), TL_OK);
  TlCGParticleArrays p = {(size_t)n, x, mass, v};
  TlCGContactArrays cc = {(size_t)nc, cx, cb, cf};
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, &cc, NULL), TL_OK);
  int ng = 40;
  double h = Lb / ng;
  TlCGGrid g = {tl_v3(0.5 * h, 0.5 * h, 0.5 * h), tl_v3(h, h, h), {ng, ng, ng}};
  size_t nodes = (size_t)ng * ng * ng;
  TlCGFields *f;
  TL_TEST_STATUS(tl_cg_fields_create(nodes, TL_CG_DENSITY | TL_CG_STRESS_CONTACT | TL_CG_STRESS_KINETIC, &f), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_grid(cg, &g, f), TL_OK);
  TlMat3 avg = tl_m3_zero();
  double kin = 0.0, mass_sum = 0.0;
  for (size_t i = 0; i < nodes; ++i) {
    avg = tl_m3_add(avg, f->stress_contact[i]);
    kin = fmax(kin, mat_diff(f->stress_kinetic[i], tl_m3_zero()));
    mass_sum += f->density[i] * h * h * h;
  }
  avg = tl_m3_scale(avg, 1.0 / nodes);
  double err = mat_diff(avg, cauchy), scale = fabs(tl_m3_trace(cauchy)) / 3.0;
  TL_TEST_ASSERT(err < tol * scale, "%s c=%g: volume average of CG stress differs from Cauchy-Poisson by %g (scale %g)",
                 name, c, err, scale);
  TL_TEST_ASSERT(kin == 0.0, "%s: kinetic stress of a packing at rest is %g", name, kin);
  /* grid quadrature of the mass: exact for cell averages, high order for the
   * smooth Lucy kernel, first order across the cut-off Gaussian's jump at c
   * (the kernels' own normalisation is checked to 1e-10 elsewhere) */
  double mass_tol = tl_cg_kernel_is_dirac(k) ? 1e-12 : (strcmp(name, "lucy") == 0 ? 1e-5 : 1e-3);
  TL_TEST_ASSERT(fabs(mass_sum - n) < mass_tol * n, "%s: periodic mass %.12g vs %d", name, mass_sum, n);
  printf("stress %s c=%g: |<sigma_CG> - sigma_CP| / |p| = %.3g\n", name, c, err / scale);
  tl_cg_fields_destroy(&f);
  tl_cg_destroy(&cg);
  tl_cg_kernel_destroy(&k);
  free(x); free(mass); free(v); free(cx); free(cb); free(cf);
}

/* Uniform motion: V = v0 everywhere with density, kinetic stress zero;
 * a shear of two populations gives the kinetic stress of the fluctuation. */
static void test_kinetic(void)
{
  Cloud cl;
  TlVec3 L = tl_v3(4, 4, 4);
  cloud_make(&cl, 200, L, 31u, 0.3);
  TlVec3 v0 = tl_v3(0.3, -1.2, 2.0);
  for (size_t i = 0; i < cl.n; ++i) cl.v[i] = v0;
  TlCGKernel *k;
  TL_TEST_STATUS(tl_cg_kernel_create("gaussian", 1.0, 3, &k), TL_OK);
  TlCG *cg;
  TL_TEST_STATUS(tl_cg_create(k, NULL, 0, &cg), TL_OK);
  TlCGParticleArrays p = {cl.n, cl.x, cl.m, cl.v};
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, NULL, NULL), TL_OK);
  TlVec3 pts[3] = {{2, 2, 2}, {1, 3, 0.5}, {3.5, 0.2, 2.2}};
  TlCGFields *f;
  TL_TEST_STATUS(tl_cg_fields_create(3, TL_CG_DENSITY | TL_CG_MOMENTUM | TL_CG_STRESS_KINETIC, &f), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_points(cg, 3, pts, f), TL_OK);
  for (int i = 0; i < 3; ++i) {
    TL_TEST_ASSERT(f->density[i] > 0.0, "density at point %d", i);
    TL_TEST_ASSERT(tl_v3_norm(tl_v3_sub(f->velocity[i], v0)) < 1e-13, "velocity at %d off by %g", i,
                   tl_v3_norm(tl_v3_sub(f->velocity[i], v0)));
    TL_TEST_ASSERT(mat_diff(f->stress_kinetic[i], tl_m3_zero()) < 1e-12 * f->density[i], "kinetic stress %g",
                   mat_diff(f->stress_kinetic[i], tl_m3_zero()));
  }
  /* two particles at one spot moving at +u and -u along x: sxx = -(m1 + m2) u^2 W */
  TlVec3 x2[2] = {{0, 0, 0}, {0, 0, 0}}, v2[2] = {{1.5, 0, 0}, {-1.5, 0, 0}};
  double m2[2] = {2.0, 2.0};
  TlCGParticleArrays p2 = {2, x2, m2, v2};
  TL_TEST_STATUS(tl_cg_set_data(cg, &p2, NULL, NULL), TL_OK);
  TlVec3 q = tl_v3(0.2, 0.1, 0.0);
  TlCGFields *g;
  TL_TEST_STATUS(tl_cg_fields_create(1, TL_CG_DENSITY | TL_CG_MOMENTUM | TL_CG_STRESS_KINETIC, &g), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_points(cg, 1, &q, g), TL_OK);
  double W = tl_cg_kernel_value(k, tl_v3_norm(q));
  TL_TEST_CLOSE(g->stress_kinetic[0].m[0][0], -4.0 * 2.25 * W, 1e-13);
  TL_TEST_CLOSE(g->stress_kinetic[0].m[1][1], 0.0, 1e-13);
  TL_TEST_CLOSE(g->density[0], 4.0 * W, 1e-13);
  /* time average of the two data sets: density and momentum are linear */
  TlCGFields *avg;
  TL_TEST_STATUS(tl_cg_fields_create(1, TL_CG_DENSITY | TL_CG_MOMENTUM, &avg), TL_OK);
  TlCGFields *f0;
  TL_TEST_STATUS(tl_cg_fields_create(1, TL_CG_DENSITY | TL_CG_MOMENTUM | TL_CG_STRESS_KINETIC, &f0), TL_OK);
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_points(cg, 1, &q, f0), TL_OK);
  tl_cg_fields_zero(avg);
  TL_TEST_STATUS(tl_cg_fields_accumulate(avg, f0, 1.0), TL_OK);
  TL_TEST_STATUS(tl_cg_fields_accumulate(avg, g, 3.0), TL_OK);
  TL_TEST_STATUS(tl_cg_fields_average_finish(avg), TL_OK);
  TL_TEST_CLOSE(avg->density[0], 0.25 * f0->density[0] + 0.75 * g->density[0], 1e-14);
  TlVec3 jm = tl_v3_add(tl_v3_scale(f0->momentum[0], 0.25), tl_v3_scale(g->momentum[0], 0.75));
  TL_TEST_CLOSE(avg->velocity[0].y, jm.y / avg->density[0], 1e-13);
  TL_TEST_STATUS(tl_cg_fields_accumulate(avg, f0, -1.0), TL_ERR_ARG);
  tl_cg_fields_destroy(&avg);
  tl_cg_fields_destroy(&f0);
  tl_cg_fields_destroy(&g);
  tl_cg_fields_destroy(&f);
  tl_cg_destroy(&cg);
  tl_cg_kernel_destroy(&k);
  cloud_free(&cl);
}

/* Boundary force density (Eq. 12) integrates to minus the wall forces. */
static void test_boundary_force(void)
{
  TlVec3 pt[3] = {{1, 1, 0}, {1.3, 1.2, 0}, {3, 3, 0}};
  TlVec3 fw[3] = {{0, 0, 2}, {0.5, 0, 1}, {0, -1, 3}};
  TlCGWallContactArrays w = {3, pt, fw, NULL};
  const char *names[2] = {"dirac", "lucy"};
  for (int t = 0; t < 2; ++t) {
    TlCGKernel *k;
    double c = t ? 0.5 : 0.0;
    TL_TEST_STATUS(tl_cg_kernel_create(names[t], c, 3, &k), TL_OK);
    TlCG *cg;
    TL_TEST_STATUS(tl_cg_create(k, NULL, 0, &cg), TL_OK);
    TL_TEST_STATUS(tl_cg_set_data(cg, NULL, NULL, &w), TL_OK);
    double h = 0.05;
    TlCGGrid g = {tl_v3(0, 0, -1), tl_v3(h, h, h), {81, 81, 41}};
    size_t nodes = 81 * 81 * 41;
    TlCGFields *f;
    TL_TEST_STATUS(tl_cg_fields_create(nodes, TL_CG_BOUNDARY_FORCE, &f), TL_OK);
    TL_TEST_STATUS(tl_cg_evaluate_grid(cg, &g, f), TL_OK);
    TlVec3 sum = tl_v3(0, 0, 0);
    for (size_t i = 0; i < nodes; ++i) sum = tl_v3_axpy(sum, h * h * h, f->boundary_force[i]);
    TlVec3 expect = tl_v3_neg(tl_v3_add(tl_v3_add(fw[0], fw[1]), fw[2]));
    TL_TEST_ASSERT(tl_v3_norm(tl_v3_sub(sum, expect)) < (t ? 1e-5 : 1e-12) * tl_v3_norm(expect),
                   "%s: integral of b^BC (%g %g %g), expected (%g %g %g)", names[t], sum.x, sum.y, sum.z, expect.x,
                   expect.y, expect.z);
    tl_cg_fields_destroy(&f);
    tl_cg_destroy(&cg);
    tl_cg_kernel_destroy(&k);
  }
}

static void test_refusals(void)
{
  TlCGKernel *k;
  TL_TEST_STATUS(tl_cg_kernel_create("lucy", 2.0, 3, &k), TL_OK);
  TlCG *cg = NULL;
  TL_TEST_STATUS(tl_cg_create(k, NULL, 11, &cg), TL_ERR_ARG);
  TlCGBox bad = {tl_v3(0, 0, 0), tl_v3(0, 1, 1), {1, 0, 0}};
  TL_TEST_STATUS(tl_cg_create(k, &bad, 0, &cg), TL_ERR_ARG);
  TlCGBox small = {tl_v3(0, 0, 0), tl_v3(3, 10, 10), {1, 0, 0}};
  TL_TEST_STATUS(tl_cg_create(k, &small, 0, &cg), TL_OK);
  TlVec3 x[1] = {{1, 1, 1}};
  double m[1] = {1.0};
  TlCGParticleArrays p = {1, x, m, NULL};
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, NULL, NULL), TL_ERR_ARG); /* 3 < 2c = 4 */
  tl_cg_destroy(&cg);
  TL_TEST_STATUS(tl_cg_create(k, NULL, 0, &cg), TL_OK);
  x[0].y = NAN;
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, NULL, NULL), TL_ERR_NUMERIC);
  x[0].y = 1.0;
  m[0] = -1.0;
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, NULL, NULL), TL_ERR_ARG);
  m[0] = 1.0;
  TL_TEST_STATUS(tl_cg_set_data(cg, &p, NULL, NULL), TL_OK);
  TlCGFields *f;
  TL_TEST_STATUS(tl_cg_fields_create(1, TL_CG_MOMENTUM, &f), TL_OK);
  TL_TEST_STATUS(tl_cg_evaluate_points(cg, 1, x, f), TL_ERR_ARG); /* no velocities */
  tl_cg_fields_destroy(&f);
  TL_TEST_STATUS(tl_cg_fields_create(1, 0, &f), TL_ERR_ARG);
  tl_cg_destroy(&cg);
  tl_cg_kernel_destroy(&k);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  test_mass_isolated("lucy");
  test_mass_isolated("gaussian");
  test_mass_isolated("heaviside");
  test_search_vs_brute(0);
  test_search_vs_brute(1);
  test_hgrid(0);
  test_hgrid(1);
  test_grid_vs_points(0);
  test_grid_vs_points(1);
  test_mass_grid();
  test_stress_periodic("dirac", 0.0, 1e-12);
  test_stress_periodic("lucy", 1.5, 1e-4);
  test_stress_periodic("gaussian", 1.8, 1e-4);
  test_kinetic();
  test_boundary_force();
  test_refusals();
  return tl_test_report();
}
