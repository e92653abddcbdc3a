/* The plane-strain biaxial test of Desrues et al. 2019 §2.5.3 and §3 (the
 * F1 test): a rectangle of -width x -height under a
 * constant lateral pressure, shortened axially at a constant rate, a
 * constitutive law at every Gauss point chosen by name (-material: the
 * DEM-cell law, or an analytic law standing in for it).
 *
 * Macro problem: plane-strain Q8 with 2 x 2 Gauss points (-macro q8), or
 * one layer of hexahedra with u_z = 0 (-macro hex8 | hex27, plane strain in
 * 3-D); -elements N makes an nx x ny mesh with ny = 2 nx (128: 8 x 16, the
 * paper's mesh; 8: 2 x 4; 1: one element), or -nx / -ny.  Bottom (y = 0)
 * held vertically and one corner horizontally, both as prescribed zero
 * displacements so their reactions count in |R|; top shortened by
 * -axial_strain x height over the run (smooth platens); the sides under
 * the follower pressure -pressure.  A law without a cell of its own
 * starts from the isotropic stress -pressure 1 (its initial stress), so the
 * specimen is in equilibrium at t = 0 as an isotropically prepared cell is.
 *
 * Loop: the quasi-static stepper with the convergence test of the paper,
 * |F|/|R| <= -ratio_tol (1e-3) before the peak and -ratio_tol_post (1e-2)
 * after it (the peak: the deviator falls below (1 - -peak_drop) of its
 * largest value), plain Newton with the law's operator as the Jacobian,
 * -steps load steps, a failed step halved up to -max_cuts times.  The
 * Gauss points are evaluated in parallel over -threads threads, longest
 * first (tl_solid_set_evaluation); results do not depend on the thread
 * count.
 *
 * Output (-output_dir): biaxial.csv (per step: axial strain, stresses,
 * volumetric strain, Newton iterations, halvings, |F|/|R|; the same bits
 * for any thread count), timing.csv (wall time per step, in the laws, per
 * Newton iteration), and every -snapshot_every steps biaxial.xmf + HDF5
 * (displacement; per element the Cauchy stress, the Green strain, von
 * Mises, and per Gauss point the cost and the first committed state
 * values); plot with tools/plot_fe2_biaxial.py.  -reference point drives
 * one material point along the homogeneous path of the test (lateral
 * Cauchy stress -pressure, F_yy from the platen) and reports the largest
 * difference of the deviator from it.  Last line: summary. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "talus.h"
#include "tl_papers.h"
#include "tl_material.h"
#include "tl_nhl_material.h"
#include "tl_options_renamed.h"
#include "tl_mesh_snapshot.h"
#include "tl_output_dir.h"
#include "tl_plot_hint.h"
#include "tl_solid.h"
#include "tl_stepper.h"
#include "tl_timeseries.h"

typedef struct {
  long nx, ny, elements, steps, max_iterations, max_cuts, accept_loose_after, snapshot_every, threads;
  int macro, evaluation, reference, check, predictor;
  double width, height, pressure, axial_strain, ratio_tol, ratio_tol_post, peak_drop, ref_tolerance, ratio_diverge;
  const char *material, *op, *cells, *output_dir;
  long cell_particles, cell_seed;
  double cell_mu, cell_kappa;
  TlOptions *options;
} Config;

static const char *const macros[] = {"q8", "q8_3x3", "hex8", "hex27", NULL};
static const char *const evaluations[] = {"auto", "chunked", "points", NULL};
static const char *const references[] = {"none", "point", NULL};
static const char *const predictors[] = {"last", "extrapolate", NULL};

/* Defaults of the analytic stand-in that make it a soil-like specimen at
 * the test's pressure (100 kPa): E / p = 1000, yield at a deviator of
 * 1.5 p, then mild hardening (H = E / 20; -mat_H < 0 with -mat_sigma_res
 * softens, and localises on fine meshes: the local law has no internal
 * length).  The law's own defaults stay what its table says. */
static const struct {
  const char *law, *param;
  double value;
} scene_defaults[] = {
    {"mises_plastic", "E", 1e8},      {"mises_plastic", "nu", 0.3},      {"mises_plastic", "sigma_y", 1.5e5},
    {"mises_plastic", "H", 5e6},      {"mises_plastic", "sigma_res", 0.0},
};

static double scene_default(const char *law, const TlParam *p)
{
  for (size_t k = 0; k < sizeof scene_defaults / sizeof scene_defaults[0]; ++k)
    if (!strcmp(scene_defaults[k].law, law) && !strcmp(scene_defaults[k].param, p->name)) return scene_defaults[k].value;
  return p->def;
}

/* The law named -material with its parameters from -mat_<name> options;
 * -operator mapped onto a law's "operator" parameter by name. */
static TlStatus make_material(const Config *c, TlOptions *o, TlMaterial **out)
{
  TlMaterial *m = NULL;
  TL_CHECK(tl_material_create(c->material, &m));
  TlStatus s = TL_OK;
  const TlMaterialOps *ops = m->ops;
  for (int i = 0; i < ops->n_params; ++i) {
    const TlParam *p = &ops->params[i];
    if (!strcmp(p->name, "operator")) continue;
    char name[96], help[256];
    snprintf(name, sizeof name, "-mat_%s", p->name);
    snprintf(help, sizeof help, "%s: %s", c->material, p->help ? p->help : p->name);
    double v = 0.0;
    TL_CHECK_GOTO(s, tl_options_get_real(o, name, scene_default(c->material, p), p->lo, p->hi, p->unit, help, &v), fail);
    TL_CHECK_GOTO(s, tl_material_set(m, p->name, v), fail);
  }
  const int cells = tl_nhl_material_is(m);
  const char *op = c->op[0] ? c->op : cells ? "demqo" : "consistent";
  if (cells) {
    /* One prepared cell, copied to every Gauss point: disks (2d) or
     * spheres (3d) compressed isotropically to the lateral pressure, so
     * the specimen starts in equilibrium (F1's k_t/k_n = 1, kappa, mu). */
    TlNhlPacking pk;
    tl_nhl_packing_default(&pk);
    pk.kind = "random";
    pk.dim = strcmp(c->cells, "3d") ? 2 : 3;
    pk.n = c->cell_particles > 0 ? c->cell_particles : pk.dim == 2 ? 400 : 1000;
    pk.seed = c->cell_seed;
    pk.mu = c->cell_mu;
    pk.kappa = c->cell_kappa;
    pk.pressure = c->pressure;
    TL_CHECK_GOTO(s, tl_nhl_material_set_operator(m, op), fail);
    TL_CHECK_GOTO(s, tl_nhl_material_set_packing(m, &pk), fail);
  } else if (tl_param_find(ops->params, ops->n_params, "operator")) {
    static const char *const names[] = {"consistent", "elastic"};
    int k = -1;
    for (int i = 0; i < 2; ++i)
      if (!strcmp(op, names[i])) k = i;
    if (k < 0) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "-operator %s: law %s knows consistent and elastic", op,
                       c->material);
      goto fail;
    }
    TL_CHECK_GOTO(s, tl_material_set(m, "operator", (double)k), fail);
  } else if (strcmp(op, "consistent")) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "-operator %s: law %s has one tangent only (consistent)", op,
                     c->material);
    goto fail;
  }
  /* A law without a sub-scale state of its own starts from the isotropic
   * stress of the prepared specimen. */
  if (!ops->commit && !ops->rollback)
    TL_CHECK_GOTO(s, tl_material_set_initial_stress(m, tl_m3_scale(tl_m3_identity(), -c->pressure)), fail);
  TL_CHECK_GOTO(s, tl_material_setup(m), fail);
  *out = m;
  return TL_OK;
fail:
  tl_material_destroy(&m);
  return s;
}

static TlStatus configure(int argc, char **argv, Config *c, TlMaterial **mat, TlMaterial **ref_mat)
{
  TlOptions *o = NULL;
  TlStatus s = TL_OK;
  TL_CHECK(tl_options_create(argc, argv,
                             "Plane-strain biaxial test (Desrues et al. 2019, §2.5.3, §3): constant lateral pressure, axial "
                             "shortening, a constitutive law per Gauss point (a DEM cell or an analytic stand-in), "
                             "the quasi-static Newton loop with the paper's |F|/|R| test.  Paper: " TL_PAPER_DESRUES_2019 ".",
                             &o));
  static const TlRenamedOption renamed[] = {
      {"-cell_mu", "-contact_mu", "the cells' contact friction, named as in every DEM driver"}};
  TL_CHECK_GOTO(s, tl_options_refuse_renamed(o, renamed, 1), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-macro", "q8", macros,
                                         "macro elements: q8 (plane strain, 2 x 2 Gauss points: the paper's), q8_3x3 "
                                         "(3 x 3) or one layer of hex8 / hex27 with u_z = 0", &c->macro), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-elements", 128, 1, 1000000,
                                      "elements, nx x ny with ny = 2 nx (128: 8 x 16); -nx/-ny override", &c->elements),
                done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nx", 0, 0, 10000, "elements across the width (0: from -elements)", &c->nx),
                done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-ny", 0, 0, 10000, "elements along the height (0: from -elements)", &c->ny),
                done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-width", 0.05, 1e-6, 1e6, "m", "specimen width (x)", &c->width), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-height", 0.1, 1e-6, 1e6, "m", "specimen height (y)", &c->height), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-pressure", 1e5, 1e-6, 1e12, "Pa", "lateral (confining) pressure",
                                       &c->pressure), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-axial_strain", 0.02, 1e-9, 0.5, "",
                                       "final axial shortening / height (Table 2: 2 %)", &c->axial_strain), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-steps", 50, 1, 1000000,
                                      "load steps (50 to 2 %: 0.04 % each, as Table 3's step 30 = 1.2 %)", &c->steps),
                done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-material", "mises_plastic",
                                         "law by registered name (dem_cell, mises_plastic, hooke, ...); its "
                                         "parameters are the -mat_<name> options", &c->material), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-operator", "",
                                         "tangent operator: dem_cell any registered nhl_operator (cto, aeo, demqo, "
                                         "pstlo, uko, ucko, ucko_2dof, kao; default demqo); mises_plastic consistent "
                                         "(default) | elastic, the upper bound as UKO is for a cell", &c->op), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-cells", "2d", "dem_cell: 2d (disks) or 3d (spheres); other laws "
                                         "ignore it", &c->cells), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-cell_particles", 0, 0, 1000000,
                                      "dem_cell: particles per cell (0: 400 disks, 1000 spheres)", &c->cell_particles),
                done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-cell_seed", 1, 0, 1000000000, "dem_cell: seed of the packing",
                                      &c->cell_seed), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-contact_mu", 0.5, 0.0, 10.0, "", "dem_cell: Coulomb friction of the cells' grain contacts",
                                       &c->cell_mu), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-cell_kappa", 500.0, 1.0, 1e9, "",
                                       "dem_cell: stiffness level kappa = k_n / sigma0 (2-D), k_n / (sigma0 <d>) (3-D)",
                                       &c->cell_kappa), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-ratio_tol", 1e-3, 1e-14, 0.5, "", "|F|/|R| before the peak",
                                       &c->ratio_tol), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-ratio_tol_post", 1e-2, 1e-14, 0.5, "", "|F|/|R| after the peak",
                                       &c->ratio_tol_post), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-accept_loose_after", 0, 0, 10000,
                                      "accept at -ratio_tol_post after this many iterations before the peak too "
                                      "(0: never)", &c->accept_loose_after), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-peak_drop", 0.005, 0.0, 0.99, "",
                                       "the peak is passed when the deviator falls below (1 - this) x its maximum",
                                       &c->peak_drop), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-ratio_diverge", 10.0, 0.0, 1e12, "",
                                       "halve an increment whose |F|/|R| grows this many times above its best (0: never)",
                                       &c->ratio_diverge), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-max_iterations", 30, 1, 10000, "Newton iterations per increment",
                                      &c->max_iterations), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-max_cuts", 6, 0, 60, "halvings of a failing load step", &c->max_cuts),
                done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-predictor", "last", predictors,
                                         "Newton's start: last (the last equilibrium, the platen moved: the paper's) or "
                                         "extrapolate (the last increment continued at the free dofs)", &c->predictor),
                done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-evaluation", "points", evaluations,
                                         "Gauss-point evaluation: points (parallel per point, longest first), "
                                         "chunked (batches) or auto", &c->evaluation), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-threads", 0, 0, 1024, "OpenMP threads for the Gauss points (0: default)",
                                      &c->threads), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-reference", "none", references,
                                         "point: also drive one material point along the homogeneous path and "
                                         "compare", &c->reference), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-ref_tolerance", 1e-2, 0.0, 1.0, "",
                                       "-check: largest deviator difference from the reference point, relative to "
                                       "its peak", &c->ref_tolerance), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-output_dir", "results/fe2_biaxial", "output folder", &c->output_dir),
                done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-snapshot_every", 10, 0, 1000000,
                                      "HDF5/XDMF snapshot every n steps and at the last (0: none)",
                                      &c->snapshot_every), done);
  TL_CHECK_GOTO(s, tl_options_get_bool(o, "-check", 0,
                                       "exit with an error unless every step converged and the reference matches",
                                       &c->check), done);
  TL_CHECK_GOTO(s, make_material(c, o, mat), done);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
  if (strcmp(c->cells, "2d") && strcmp(c->cells, "3d")) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "-cells %s is neither 2d nor 3d", c->cells);
    goto done;
  }
  if (c->nx == 0 || c->ny == 0) {
    long nx = lround(sqrt((double)c->elements / 2.0));
    if (nx < 1) nx = 1;
    long ny = c->elements / nx;
    if (nx * ny != c->elements || (ny != 2 * nx && c->elements != 1)) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "-elements %ld is not nx x 2nx (2, 8, 18, 32, ..., 128, 512, 2048); give -nx and -ny",
                       c->elements);
      goto done;
    }
    c->nx = nx;
    c->ny = c->elements == 1 ? 1 : ny;
  }
  c->elements = c->nx * c->ny;
  if (c->reference && ref_mat) {
    /* The reference point has a law of its own (a cell law's store). */
    Config quiet = *c;
    TlOptions *o2 = NULL;
    TL_CHECK_GOTO(s, tl_options_create(argc, argv, "", &o2), done);
    s = make_material(&quiet, o2, ref_mat);
    tl_options_destroy(&o2);
    if (s != TL_OK) goto done;
  }
  c->options = o;
  return TL_OK;
done:
  tl_material_destroy(mat);
  if (ref_mat) tl_material_destroy(ref_mat);
  tl_options_destroy(&o);
  return s;
}

/* ------------------------------------------------------------ scene */
typedef struct {
  double rate; /* top displacement per unit time (m) */
} Platen;

static void prescribe_zero(double t, const double X[3], int c, void *ctx, double out[3])
{
  (void)t, (void)X, (void)c, (void)ctx;
  out[0] = out[1] = out[2] = 0.0;
}

static void prescribe_top(double t, const double X[3], int c, void *ctx, double out[3])
{
  (void)X, (void)c;
  const Platen *p = ctx;
  out[0] = p->rate * t;
  out[1] = p->rate;
  out[2] = 0.0;
}

typedef struct {
  TlMesh *mesh;
  TlSolid *solid;
  Platen platen;
  size_t *top, *left, *right; /* node lists */
  size_t n_top, n_left, n_right;
} Scene;

static TlStatus node_list(const TlMesh *mesh, const char *set, size_t **nodes, size_t *n)
{
  const TlNodeSet *ns = NULL;
  TL_CHECK(tl_mesh_find_node_set(mesh, set, &ns));
  TL_CHECK(tl_calloc(nodes, ns->n, sizeof **nodes));
  memcpy(*nodes, ns->nodes, ns->n * sizeof **nodes);
  *n = ns->n;
  return TL_OK;
}

static void scene_destroy(Scene *sc)
{
  tl_solid_destroy(&sc->solid);
  tl_mesh_destroy(&sc->mesh);
  tl_free(&sc->top);
  tl_free(&sc->left);
  tl_free(&sc->right);
}

static TlStatus scene_create(const Config *c, TlMaterial *mat, Scene *sc)
{
  memset(sc, 0, sizeof *sc);
  const int dim = c->macro <= 1 ? 2 : 3;
  if (dim == 2) {
    size_t n[2] = {(size_t)c->nx, (size_t)c->ny};
    double lo[2] = {0.0, 0.0}, hi[2] = {c->width, c->height};
    const TlElementType *q8 = &tl_element_quad8;
    if (c->macro == 0) TL_CHECK(tl_element_type_find("quad8r", &q8));
    TL_CHECK(tl_mesh_create_rectangle(q8, n, lo, hi, &sc->mesh));
  } else {
    size_t n[3] = {(size_t)c->nx, (size_t)c->ny, 1};
    double depth = c->width / (double)c->nx;
    double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {c->width, c->height, depth};
    TL_CHECK(tl_mesh_create_box(c->macro == 2 ? &tl_element_hex8 : &tl_element_hex27, n, lo, hi, &sc->mesh));
  }
  /* The anchor against horizontal rigid motion: the nodes at x = y = 0. */
  size_t anchor[4], n_anchor = 0;
  for (size_t i = 0; i < sc->mesh->n_nodes && n_anchor < 4; ++i)
    if (sc->mesh->x[3 * i] == 0.0 && sc->mesh->x[3 * i + 1] == 0.0) anchor[n_anchor++] = i;
  TL_CHECK(tl_mesh_add_node_set(sc->mesh, "anchor", n_anchor, anchor));
  if (dim == 3) {
    size_t *all = NULL;
    TL_CHECK(tl_calloc(&all, sc->mesh->n_nodes, sizeof *all));
    for (size_t i = 0; i < sc->mesh->n_nodes; ++i) all[i] = i;
    TlStatus s = tl_mesh_add_node_set(sc->mesh, "all", sc->mesh->n_nodes, all);
    tl_free(&all);
    TL_CHECK(s);
  }
  TL_CHECK(node_list(sc->mesh, "ymax", &sc->top, &sc->n_top));
  TL_CHECK(node_list(sc->mesh, "xmin", &sc->left, &sc->n_left));
  TL_CHECK(node_list(sc->mesh, "xmax", &sc->right, &sc->n_right));
  TL_CHECK(tl_solid_create(sc->mesh, &sc->solid));
  TlSolid *s = sc->solid;
  TL_CHECK(tl_solid_set_material(s, NULL, mat));
  sc->platen.rate = -c->axial_strain * c->height; /* t runs from 0 to 1 */
  TL_CHECK(tl_solid_prescribe(s, "ymin", 1, prescribe_zero, NULL));
  TL_CHECK(tl_solid_prescribe(s, "anchor", 0, prescribe_zero, NULL));
  TL_CHECK(tl_solid_prescribe(s, "ymax", 1, prescribe_top, &sc->platen));
  if (dim == 3) TL_CHECK(tl_solid_fix(s, "all", 4)); /* u_z = 0: plane strain */
  TL_CHECK(tl_solid_add_pressure(s, "xmin", c->pressure, NULL, NULL));
  TL_CHECK(tl_solid_add_pressure(s, "xmax", c->pressure, NULL, NULL));
  static const int modes[] = {TL_SOLID_EVAL_AUTO, TL_SOLID_EVAL_CHUNKED, TL_SOLID_EVAL_POINTS};
  TL_CHECK(tl_solid_set_evaluation(s, modes[c->evaluation], (int)c->threads));
  TL_CHECK(tl_solid_setup(s));
  TL_CHECK(tl_solid_check_constraints(s));
  return TL_OK;
}

/* Measures of the specimen at the accepted state of the stepper. */
typedef struct {
  double axial_strain, sigma_axial, sigma_lateral, q, eps_v, width, height;
} Measures;

static double mean_u(const TlSolid *s, const double *u, const size_t *nodes, size_t n, int comp)
{
  double sum = 0.0;
  for (size_t k = 0; k < n; ++k) {
    TlSparseIndex d = tl_solid_dof(s, nodes[k], comp);
    sum += d >= 0 ? u[d] : 0.0;
  }
  return sum / (double)n;
}

static void measure(const Config *c, const Scene *sc, const TlStepper *st, Measures *m)
{
  const TlSolid *s = sc->solid;
  const double depth = c->macro <= 1 ? 1.0 : c->width / (double)c->nx;
  /* The axial force: the reactions at the platen's dofs, f_int - lambda f_ext. */
  double force = 0.0;
  for (size_t k = 0; k < sc->n_top; ++k) {
    TlSparseIndex d = tl_solid_dof(s, sc->top[k], 1);
    force += st->f_int[d] - st->lambda * st->f_ext[d];
  }
  const double uy = mean_u(s, st->u, sc->top, sc->n_top, 1);
  const double w = c->width + mean_u(s, st->u, sc->right, sc->n_right, 0) - mean_u(s, st->u, sc->left, sc->n_left, 0);
  m->height = c->height + uy;
  m->width = w;
  m->axial_strain = -uy / c->height;
  m->sigma_axial = force / (w * depth); /* Cauchy, compression negative */
  m->sigma_lateral = -c->pressure;
  m->q = m->sigma_lateral - m->sigma_axial; /* sigma_1 - sigma_3 for axial compression */
  m->eps_v = (w * m->height) / (c->width * c->height) - 1.0;
}

/* ------------------------------------------------ the reference point */
typedef struct {
  TlMaterial *mat;
  double state[2][64];
  size_t ss;
  double a; /* F_xx */
} RefPoint;

/* One homogeneous step to F_yy = fyy: F_xx such that the lateral Cauchy
 * stress is -p (secant iteration), then commit.  Returns q. */
static TlStatus ref_step(RefPoint *rp, double fyy, double p, double *q)
{
  double a0 = rp->a, a1 = rp->a * (1.0 + 1e-6), r0 = 0.0, r1 = 0.0;
  TlMat3 S, F = tl_m3_identity();
  double sxx = 0.0, syy = 0.0;
  for (int it = 0; it < 100; ++it) {
    double a = it == 0 ? a0 : a1;
    F.m[0][0] = a, F.m[1][1] = fyy;
    TL_CHECK(tl_material_evaluate(rp->mat, 1, &F, rp->ss ? rp->state[0] : NULL, rp->ss ? rp->state[1] : NULL, &S,
                                  NULL, NULL));
    const double J = a * fyy;
    sxx = a * a * S.m[0][0] / J, syy = fyy * fyy * S.m[1][1] / J;
    double r = sxx + p;
    if (it == 0) {
      r0 = r;
      continue;
    }
    if (!isfinite(r)) TL_ERROR(TL_ERR_NUMERIC, "reference point: lateral stress %g Pa at F_xx = %.17g", sxx, a);
    r1 = r;
    if (fabs(r1) <= 1e-12 * p) break;
    /* A DEM cell's stress has a noise floor (its particles are in equilibrium
     * to eps_R, not to round-off): after ten chords, a millionth of the
     * confinement is as close as the lateral condition gets. */
    if (it >= 10 && fabs(r1) <= 1e-6 * p) break;
    /* A cell's stress is piecewise smooth in F (contacts open and close):
     * two points may give the same lateral stress, or the secant may stall
     * below round-off of F_xx; widen the chord, or stop where F_xx no longer
     * moves. */
    if (r1 == r0) {
      a1 = a0 + 100.0 * (a1 - a0);
      continue;
    }
    double an = a1 - r1 * (a1 - a0) / (r1 - r0);
    if (fabs(an - a1) <= 4.0 * DBL_EPSILON * fabs(a1)) break;
    a0 = a1, r0 = r1, a1 = an;
    if (it == 99) TL_ERROR(TL_ERR_CONVERGENCE, "reference point: lateral stress %g Pa, wanted %g Pa", sxx, -p);
  }
  rp->a = a1;
  if (rp->ss) memcpy(rp->state[0], rp->state[1], rp->ss * sizeof(double));
  if (rp->mat->ops->commit) TL_CHECK(rp->mat->ops->commit(rp->mat, 1, rp->state[0]));
  *q = sxx - syy;
  return TL_OK;
}

/* ------------------------------------------------------- snapshots */
typedef struct {
  TlMeshWriter *writer;
  int *conn;
  TlVec3 *ref, *disp;
  double *cauchy, *green, *mises, *cost, *state[3];
  size_t state_index[3];
  int n_state, nq;
  TlField fields[8];
  size_t n_fields;
  double *u_nodes;
} Snapshots;

static void snapshots_close(Snapshots *sn)
{
  tl_mesh_writer_destroy(&sn->writer);
  tl_free(&sn->conn);
  tl_free(&sn->ref);
  tl_free(&sn->disp);
  tl_free(&sn->cauchy);
  tl_free(&sn->green);
  tl_free(&sn->mises);
  tl_free(&sn->cost);
  for (int k = 0; k < 3; ++k) tl_free(&sn->state[k]);
  tl_free(&sn->u_nodes);
}

static TlStatus snapshots_open(const Config *c, const Scene *sc, const TlMaterial *mat, Snapshots *sn)
{
  memset(sn, 0, sizeof *sn);
  const TlMesh *mesh = sc->mesh;
  const TlElementBlock *blk = &mesh->blocks[0];
  const int nn = blk->type->n_nodes;
  const size_t ne = blk->n_elements;
  if (!blk->type->output) TL_ERROR(TL_ERR_UNSUPPORTED, "element type %s has no output cell", blk->type->header.name);
  TL_CHECK(tl_calloc(&sn->conn, ne * (size_t)nn, sizeof *sn->conn));
  const int *order = blk->type->output->order;
  for (size_t e = 0; e < ne; ++e)
    for (int k = 0; k < nn; ++k) sn->conn[e * nn + k] = (int)blk->conn[e * nn + (order ? order[k] : k)];
  TL_CHECK(tl_calloc(&sn->ref, mesh->n_nodes, sizeof *sn->ref));
  TL_CHECK(tl_calloc(&sn->disp, mesh->n_nodes, sizeof *sn->disp));
  TL_CHECK(tl_calloc(&sn->u_nodes, mesh->n_nodes * (size_t)mesh->dim, sizeof *sn->u_nodes));
  for (size_t i = 0; i < mesh->n_nodes; ++i) sn->ref[i] = tl_v3(mesh->x[3 * i], mesh->x[3 * i + 1], mesh->x[3 * i + 2]);
  TL_CHECK(tl_solid_point_data(sc->solid, 0, NULL, NULL, NULL, NULL, &sn->nq));
  TL_CHECK(tl_calloc(&sn->cauchy, 6 * ne, sizeof(double)));
  TL_CHECK(tl_calloc(&sn->green, 6 * ne, sizeof(double)));
  TL_CHECK(tl_calloc(&sn->mises, ne, sizeof(double)));
  TL_CHECK(tl_calloc(&sn->cost, ne * (size_t)sn->nq, sizeof(double)));
  sn->fields[sn->n_fields++] = (TlField){"stress_cauchy", 6, sn->cauchy};
  sn->fields[sn->n_fields++] = (TlField){"strain_green", 6, sn->green};
  sn->fields[sn->n_fields++] = (TlField){"von_mises", 1, sn->mises};
  sn->fields[sn->n_fields++] = (TlField){"gp_cost", sn->nq, sn->cost};
  /* The state summary: the laws this driver knows name theirs; others show
   * their first three state values. */
  static const char *const generic[3] = {"gp_state0", "gp_state1", "gp_state2"};
  static const char *const cell_names[3] = {"gp_dem_steps", "gp_imbalance", "gp_post_peak"};
  static const size_t cell_index[3] = {TL_NHL_STATE_DEM_STEPS, TL_NHL_STATE_IMBALANCE, TL_NHL_STATE_POST_PEAK};
  const char *const *names = generic;
  sn->n_state = mat->state_size < 3 ? (int)mat->state_size : 3;
  for (int k = 0; k < 3; ++k) sn->state_index[k] = (size_t)k;
  if (tl_nhl_material_is(mat)) {
    names = cell_names;
    for (int k = 0; k < 3; ++k) sn->state_index[k] = cell_index[k];
  } else if (!strcmp(mat->ops->header.name, "mises_plastic")) {
    static const char *const kappa[1] = {"gp_kappa"};
    names = kappa;
    sn->n_state = 1;
    sn->state_index[0] = 6;
  }
  for (int k = 0; k < sn->n_state; ++k) {
    TL_CHECK(tl_calloc(&sn->state[k], ne * (size_t)sn->nq, sizeof(double)));
    sn->fields[sn->n_fields++] = (TlField){names[k], sn->nq, sn->state[k]};
  }
  TL_CHECK(tl_mkdir_p(c->output_dir));
  TL_CHECK(tl_mesh_writer_create(c->output_dir, "biaxial", &sn->writer));
  return TL_OK;
}

/* XDMF Tensor6 order: xx, xy, xz, yy, yz, zz. */
static void tensor6(TlMat3 a, double *v)
{
  v[0] = a.m[0][0], v[1] = a.m[0][1], v[2] = a.m[0][2];
  v[3] = a.m[1][1], v[4] = a.m[1][2], v[5] = a.m[2][2];
}

static TlStatus snapshots_write(Snapshots *sn, const Scene *sc, const TlMaterial *mat, long step, double t,
                                const double *u)
{
  if (!sn->writer) return TL_OK;
  const TlMesh *mesh = sc->mesh;
  const int dim = mesh->dim, nq = sn->nq;
  tl_solid_dofs_to_nodes(sc->solid, u, sn->u_nodes);
  for (size_t i = 0; i < mesh->n_nodes; ++i)
    sn->disp[i] = tl_v3(sn->u_nodes[i * dim], sn->u_nodes[i * dim + 1], dim == 3 ? sn->u_nodes[i * dim + 2] : 0.0);
  const TlMat3 *H = NULL, *S = NULL;
  const double *cost = NULL, *state = NULL;
  TL_CHECK(tl_solid_point_data(sc->solid, 0, &H, &S, &cost, &state, NULL));
  if (!H) TL_ERROR(TL_ERR_STATE, "snapshots need the point-by-point evaluation (-evaluation points)");
  const size_t ne = mesh->blocks[0].n_elements, ss = mat->state_size;
  for (size_t e = 0; e < ne; ++e) {
    TlMat3 sig = tl_m3_zero(), E = tl_m3_zero();
    for (int q = 0; q < nq; ++q) {
      const size_t p = e * nq + q;
      TlMat3 F = H[p];
      for (int i = 0; i < 3; ++i) F.m[i][i] += 1.0;
      const double J = tl_m3_det(F);
      sig = tl_m3_add(sig, tl_m3_scale(tl_m3_mul(tl_m3_mul(F, S[p]), tl_m3_transpose(F)), 1.0 / (J * nq)));
      TlMat3 C = tl_m3_mul(tl_m3_transpose(F), F);
      E = tl_m3_add(E, tl_m3_scale(tl_m3_add(C, tl_m3_scale(tl_m3_identity(), -1.0)), 0.5 / nq));
      sn->cost[p] = cost[p];
      for (int k = 0; k < sn->n_state; ++k) sn->state[k][p] = state ? state[p * ss + sn->state_index[k]] : 0.0;
    }
    tensor6(sig, sn->cauchy + 6 * e);
    tensor6(E, sn->green + 6 * e);
    double pm = tl_m3_trace(sig) / 3.0, j2 = 0.0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double d = sig.m[i][j] - (i == j ? pm : 0.0);
        j2 += 0.5 * d * d;
      }
    sn->mises[e] = sqrt(3.0 * j2);
  }
  const TlElementBlock *blk = &mesh->blocks[0];
  TlMeshBlock mb = {blk->name, blk->type->output->cell, ne, sn->conn, sn->n_fields, sn->fields};
  TlMeshView view = {mesh->n_nodes, sn->ref, sn->disp, 0, NULL, 1, &mb};
  TL_CHECK(tl_mesh_writer_write(sn->writer, step, t, &view));
  return TL_OK;
}

/* ------------------------------------------------------------- run */
/* Closes a table when open; a failure to write it is the run's status
 * unless the run failed first. */
static void close_table(TlTimeSeries **ts, TlStatus *s)
{
  if (!*ts) return;
  TlStatus s2 = tl_timeseries_close(ts);
  if (*s == TL_OK) *s = s2;
}

static TlStatus open_table(const Config *c, const char *name, size_t n, const TlColumn *cols, TlTimeSeries **ts)
{
  char *base = NULL;
  TL_CHECK(tl_mkdir_p(c->output_dir));
  TL_CHECK(tl_path_join(c->output_dir, name, &base));
  TlStatus s = tl_timeseries_create(base, TL_TIMESERIES_CSV, n, cols, ts);
  tl_free(&base);
  return s;
}

/* FNV-1a over the bytes of the final displacements: equal for equal bits. */
static unsigned long hash_doubles(const double *x, size_t n)
{
  unsigned long h = 1469598103934665603UL;
  const unsigned char *b = (const unsigned char *)x;
  for (size_t i = 0; i < n * sizeof *x; ++i) h = (h ^ b[i]) * 1099511628211UL;
  return h;
}

static TlStatus run(int argc, char **argv)
{
  Config c;
  memset(&c, 0, sizeof c);
  TlMaterial *mat = NULL;
  RefPoint rp;
  memset(&rp, 0, sizeof rp);
  TL_CHECK(tl_initialize());
  TL_CHECK(configure(argc, argv, &c, &mat, &rp.mat));
  if (c.threads > 0) omp_set_num_threads((int)c.threads);
  Scene sc;
  Snapshots sn;
  TlStepper *st = NULL;
  TlTimeSeries *ts = NULL, *tt = NULL;
  TlStatus s = TL_OK;
  memset(&sn, 0, sizeof sn);
  TL_CHECK_GOTO(s, scene_create(&c, mat, &sc), done);
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  so.convergence = TL_CONVERGENCE_FORCE_RATIO;
  so.ratio_tol = c.ratio_tol;
  so.ratio_tol_post = fmax(c.ratio_tol_post, c.ratio_tol);
  so.accept_loose_after = c.accept_loose_after;
  so.max_iterations = c.max_iterations;
  so.max_cuts = (int)c.max_cuts;
  so.ratio_diverge = c.ratio_diverge;
  so.predictor = c.predictor ? TL_PREDICTOR_TAYLOR : TL_PREDICTOR_LAST;
  TL_CHECK_GOTO(s, tl_stepper_create("quasi_static", tl_solid_system(sc.solid), &so, &st), done);
  TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), done);
  const TlColumn cols[] = {{"step", ""},          {"axial_strain", ""},      {"sigma_axial", "Pa"},
                           {"q", "Pa"},            {"volumetric_strain", ""}, {"iterations", ""},
                           {"failed_iterations", ""}, {"cuts", ""},           {"ratio", ""},
                           {"force", "N"},         {"reaction", "N"},         {"loose", ""},
                           {"post_peak", ""},      {"q_reference", "Pa"}};
  const TlColumn tcols[] = {{"step", ""},          {"wall", "s"},         {"t_points", "s"},
                            {"t_points_wall", "s"}, {"point_evaluations", ""}, {"t_costliest_point", "s"},
                            {"cell_evaluations", ""}, {"dem_steps", ""},  {"unconverged_cells", ""},
                            {"max_imbalance", ""}};
  TL_CHECK_GOTO(s, open_table(&c, "biaxial", 14, cols, &ts), done);
  TL_CHECK_GOTO(s, open_table(&c, "timing", 10, tcols, &tt), done);
  if (c.snapshot_every > 0) TL_CHECK_GOTO(s, snapshots_open(&c, &sc, mat, &sn), done);
  rp.ss = rp.mat ? rp.mat->state_size : 0;
  if (rp.ss > 64) {
    s = tl_error_set(TL_ERR_UNSUPPORTED, __FILE__, __LINE__, "reference point: %zu state values, at most 64", rp.ss);
    goto done;
  }
  if (rp.mat && rp.mat->ops->init_state) TL_CHECK_GOTO(s, rp.mat->ops->init_state(rp.mat, 1, rp.state[0]), done);
  rp.a = 1.0;
  tl_printf("fe2_biaxial: %s %ld x %ld (%zu nodes, %lld dofs), law %s (operator %s), pressure %g Pa, to %g %% in %ld "
            "steps, |F|/|R| <= %g / %g, %d threads\n",
            macros[c.macro], c.nx, c.ny, sc.mesh->n_nodes, (long long)st->n, c.material,
            c.op[0] ? c.op : tl_nhl_material_is(mat) ? "demqo" : "consistent", c.pressure,
            100.0 * c.axial_strain, c.steps, c.ratio_tol, so.ratio_tol_post,
            c.threads > 0 ? (int)c.threads : omp_get_max_threads());
  double q_max = -HUGE_VAL, strain_peak = 0.0, ref_diff = 0.0, ref_peak = 0.0, t0 = tl_wtime();
  long iterations = 0, iterations_pre = 0, steps_pre = 0, iterations_post = 0, steps_post = 0, cuts = 0, loose = 0,
       failed_it = 0;
  double worst_ratio = 0.0, worst_ratio_pre = 0.0, worst_ratio_post = 0.0;
  long cell_evaluations = 0, dem_steps = 0, unconverged = 0;
  Measures m = {0};
  TlSolidEvalStats es0, es1;
  tl_solid_get_evaluation_stats(sc.solid, &es0);
  for (long k = 1; k <= c.steps; ++k) {
    double tw = tl_wtime();
    TL_CHECK_GOTO(s, tl_stepper_step(st, 1.0 / (double)c.steps), done);
    tw = tl_wtime() - tw;
    const TlStepInfo *si = &st->last_step;
    measure(&c, &sc, st, &m);
    double q_ref = NAN;
    if (rp.mat) {
      TL_CHECK_GOTO(s, ref_step(&rp, 1.0 - c.axial_strain * (double)k / (double)c.steps, c.pressure, &q_ref), done);
      ref_diff = fmax(ref_diff, fabs(m.q - q_ref));
      ref_peak = fmax(ref_peak, fabs(q_ref));
    }
    iterations += si->iterations;
    failed_it += si->failed_iterations;
    cuts += si->cuts;
    loose += si->loose;
    worst_ratio = fmax(worst_ratio, si->ratio);
    if (si->post_peak) iterations_post += si->iterations, steps_post++, worst_ratio_post = fmax(worst_ratio_post, si->ratio);
    else iterations_pre += si->iterations, steps_pre++, worst_ratio_pre = fmax(worst_ratio_pre, si->ratio);
    if (m.q > q_max) q_max = m.q, strain_peak = m.axial_strain;
    if (!st->post_peak && m.q < (1.0 - c.peak_drop) * q_max) {
      tl_stepper_set_post_peak(st, 1);
      /* the cells' operators (AEO freezes) follow the macro peak */
      if (tl_nhl_material_is(mat)) tl_nhl_material_set_regime(mat, 0);
    }
    TlNhlMaterialTotals nt = {0};
    if (tl_nhl_material_is(mat)) tl_nhl_material_totals(mat, &nt, 1);
    cell_evaluations += nt.evaluations, dem_steps += nt.dem_steps, unconverged += nt.unconverged;
    tl_solid_get_evaluation_stats(sc.solid, &es1);
    double row[14] = {(double)k,           m.axial_strain, m.sigma_axial,     m.q,
                      m.eps_v,             (double)si->iterations, (double)si->failed_iterations, (double)si->cuts,
                      si->ratio,           si->force,      si->reaction,      (double)si->loose,
                      (double)si->post_peak, q_ref};
    double trow[10] = {(double)k, tw, es1.t_points - es0.t_points, es1.t_wall - es0.t_wall,
                       (double)(es1.points - es0.points), es1.t_last_max, (double)nt.evaluations,
                       (double)nt.dem_steps, (double)nt.unconverged, nt.max_imbalance};
    es0 = es1;
    TL_CHECK_GOTO(s, tl_timeseries_append(ts, row), done);
    TL_CHECK_GOTO(s, tl_timeseries_append(tt, trow), done);
    tl_printf("step %4ld  eps_a %.5f  q %.6e Pa  eps_v %+.3e  iterations %ld%s  cuts %ld  |F|/|R| %.2e%s  %.3f s\n", k,
              m.axial_strain, m.q, m.eps_v, si->iterations, si->failed_iterations ? " (+failed)" : "", si->cuts,
              si->ratio, si->post_peak ? " post-peak" : "", tw);
    if (sn.writer && (k % c.snapshot_every == 0 || k == c.steps))
      TL_CHECK_GOTO(s, snapshots_write(&sn, &sc, mat, k, st->t, st->u), done);
  }
  double wall = tl_wtime() - t0;
  TlSolidEvalStats es;
  tl_solid_get_evaluation_stats(sc.solid, &es);
  TlStepperStats ss;
  tl_stepper_get_stats(st, &ss);
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "elements", c.elements);
  tl_summary_int(&sum, "steps", c.steps);
  tl_summary_int(&sum, "iterations", iterations);
  tl_summary_real(&sum, "iterations_per_step_pre", steps_pre ? (double)iterations_pre / steps_pre : 0.0);
  tl_summary_real(&sum, "iterations_per_step_post", steps_post ? (double)iterations_post / steps_post : 0.0);
  tl_summary_int(&sum, "steps_post_peak", steps_post);
  tl_summary_int(&sum, "cuts", cuts);
  tl_summary_int(&sum, "failed_iterations", failed_it);
  tl_summary_int(&sum, "loose_accepts", loose);
  tl_summary_real(&sum, "worst_ratio", worst_ratio);
  /* the thresholds differ on the two sides of the peak (1e-3 / 1e-2) */
  tl_summary_real(&sum, "worst_ratio_pre", worst_ratio_pre);
  tl_summary_real(&sum, "worst_ratio_post", worst_ratio_post);
  tl_summary_real(&sum, "q_peak", q_max);
  tl_summary_real(&sum, "strain_at_peak", strain_peak);
  tl_summary_real(&sum, "q_final", m.q);
  tl_summary_real(&sum, "eps_v_final", m.eps_v);
  if (rp.mat) tl_summary_real(&sum, "ref_diff", ref_peak > 0.0 ? ref_diff / ref_peak : 0.0);
  char hash[32];
  snprintf(hash, sizeof hash, "%016lx", hash_doubles(st->u, (size_t)st->n));
  tl_summary_string(&sum, "u_hash", hash);
  tl_summary_int(&sum, "threads", es.threads);
  tl_summary_real(&sum, "wall", wall);
  const long newton = ss.newton_iterations;
  tl_summary_real(&sum, "t_per_iteration", newton ? wall / (double)newton : 0.0);
  tl_summary_real(&sum, "t_per_point", es.points ? es.t_points / (double)es.points : 0.0);
  tl_summary_real(&sum, "t_points_wall", es.t_wall);
  tl_summary_int(&sum, "point_evaluations", es.points);
  tl_summary_int(&sum, "tangent_reuses", es.reuses);
  if (tl_nhl_material_is(mat)) {
    tl_summary_int(&sum, "cell_evaluations", cell_evaluations);
    tl_summary_int(&sum, "dem_steps", dem_steps);
    tl_summary_int(&sum, "unconverged_cells", unconverged);
  }
  tl_printf("%ld steps, %ld Newton iterations (%.2f per step before the peak, %.2f after), %ld halvings; %ld point "
            "evaluations at %.3g s each (%.3f s in the point loop of %.3f s)\n",
            c.steps, iterations, steps_pre ? (double)iterations_pre / steps_pre : 0.0,
            steps_post ? (double)iterations_post / steps_post : 0.0, cuts, es.points,
            es.points ? es.t_points / (double)es.points : 0.0, es.t_wall, wall);
  {
    char plot_cmd[4200], plot_dir[4200];
    tl_printf("plots: %s %s\n", tl_plot_command(TALUS_TOOLS_DIR, "plot_fe2_biaxial.py", plot_cmd, sizeof plot_cmd),
              tl_plot_abs_dir(c.output_dir, plot_dir, sizeof plot_dir));
  }
  s = tl_summary_print(&sum, stdout);
  if (c.check && rp.mat && !(ref_diff <= c.ref_tolerance * ref_peak))
    s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__,
                     "-check: the deviator differs from the reference point by %.3e of its peak, above %g",
                     ref_peak > 0.0 ? ref_diff / ref_peak : NAN, c.ref_tolerance);
done:
  close_table(&ts, &s);
  close_table(&tt, &s);
  snapshots_close(&sn);
  tl_stepper_destroy(&st);
  scene_destroy(&sc);
  tl_material_destroy(&mat);
  tl_material_destroy(&rp.mat);
  tl_options_destroy(&c.options);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
