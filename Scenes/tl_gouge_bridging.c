/* The bridging-domain gouge scene (tl_gouge_bridging.h). */
#include "tl_gouge_bridging.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_contact_law.h"
#include "tl_dem.h"
#include "tl_dem_packing.h"
#include "tl_element.h"
#include "tl_lammps_data.h"
#include "tl_material.h"
#include "tl_math.h"
#include "tl_mech_linear.h"
#include "tl_memory.h"
#include "tl_mesh.h"
#include "tl_particle_snapshot.h"
#include "tl_pulse.h"
#include "tl_solid.h"
#include "tl_solid_output.h"
#include "tl_solid_tie.h"
#include "tl_stepper.h"
#include "tl_timer.h"

struct TlGouge {
  TlGougeParams p;
  TlGougeInfo info;
  TlDem *dem;
  TlMesh *mesh;
  TlMaterial *mat;
  TlSolid *solid;
  TlMechSystem *linear; /* the fast path's system, or NULL */
  TlStepper *st;
  TlBdm *bdm;
  TlPulse pulse;
  long step;
  TlGougeTimes times;
  /* recorded planes: plane k holds the root nodes of node plane y[k] */
  double *plane_y;
  size_t *plane_ptr, *plane_nodes;
  /* output */
  TlParticleWriter *pw;
  TlSolidOutput *so;
  double *weights; /* particle output field */
};

void tl_gouge_params_default(TlGougeParams *p)
{
  memset(p, 0, sizeof *p);
  p->packing = NULL;
  p->cells_section = 2;
  p->cells_y = 4;
  p->h = 0.036;
  p->bridge = 0.0;
  p->fe_length = 0.4;
  p->E = 0.977e9;
  p->nu = 0.255;
  p->rho = 1643.0;
  p->eigenstrain = 0.0025;
  p->linear_fe = 0;
  p->k_n = 3.663e10;
  p->k_t = 4.5249e10;
  p->gamma_n = 0.2;
  p->gamma_t = -1.0;
  p->mu = 0.5;
  p->grain_density = 2500.0;
  p->dt = 1e-8;
  p->threads = 0;
  tl_bdm_options_default(&p->bdm);
  p->mode = TL_GOUGE_REST;
  p->wave_component = 1;
  p->pulse_shape = TL_PULSE_GAUSSIAN;
  p->wavelength = 0.6;
  p->intensity = 5e-4;
  p->subtract_initial = 0;
}

/* The cell: n grains (positions wrapped into [0, a)^3, radii) from a
 * packing file (.h5, tl_dem_packing.h) or a LAMMPS data file. */
typedef struct {
  size_t n;
  TlVec3 *x;
  double *r;
  double a;
} Cell;

static void cell_free(Cell *c)
{
  tl_free(&c->x);
  tl_free(&c->r);
}

static TlStatus read_cell(const char *path, Cell *c)
{
  memset(c, 0, sizeof *c);
  size_t len = strlen(path);
  double lo[3], side[3];
  TlStatus s = TL_OK;
  if (len > 3 && strcmp(path + len - 3, ".h5") == 0) {
    TlParticleSnapshot snap;
    TlVec3 origin;
    TlMat3 h;
    TL_CHECK(tl_dem_packing_read(path, &snap, &origin, &h));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (i != j && h.m[i][j] != 0.0)
          s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "gouge: packing '%s' has a sheared cell (h[%d][%d] = %g)",
                           path, i, j, h.m[i][j]);
    for (int k = 0; k < 3; ++k) lo[k] = tl_v3_get(origin, k), side[k] = h.m[k][k];
    c->n = snap.n;
    if (s == TL_OK) s = tl_calloc(&c->x, snap.n + 1, sizeof *c->x);
    if (s == TL_OK) s = tl_calloc(&c->r, snap.n + 1, sizeof *c->r);
    for (size_t i = 0; s == TL_OK && i < snap.n; ++i) c->x[i] = snap.position[i], c->r[i] = snap.radius[i];
    tl_particle_snapshot_free(&snap);
  } else {
    TlLammpsData *data = NULL;
    TL_CHECK(tl_lammps_data_read(path, &data));
    if (data->triclinic) s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "gouge: packing '%s' has a tilted cell", path);
    for (int k = 0; k < 3; ++k) lo[k] = data->lo[k], side[k] = data->hi[k] - data->lo[k];
    c->n = data->n;
    if (s == TL_OK) s = tl_calloc(&c->x, data->n + 1, sizeof *c->x);
    if (s == TL_OK) s = tl_calloc(&c->r, data->n + 1, sizeof *c->r);
    for (size_t i = 0; s == TL_OK && i < data->n; ++i) c->x[i] = data->x[i], c->r[i] = 0.5 * data->diameter[i];
    tl_lammps_data_destroy(&data);
  }
  c->a = side[0];
  for (int k = 1; k < 3 && s == TL_OK; ++k)
    if (fabs(side[k] - side[0]) > 1e-12 * side[0])
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "gouge: packing '%s' is not a cubic cell (sides %g, %g, %g m)",
                       path, side[0], side[1], side[2]);
  if (s == TL_OK && c->n == 0) s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "gouge: packing '%s' is empty", path);
  for (size_t i = 0; s == TL_OK && i < c->n; ++i) {
    double w[3];
    for (int k = 0; k < 3; ++k) {
      double f = fmod(tl_v3_get(c->x[i], k) - lo[k], c->a);
      w[k] = f < 0 ? f + c->a : f;
    }
    c->x[i] = tl_v3(w[0], w[1], w[2]);
  }
  if (s) cell_free(c);
  return s;
}

/* The DEM bar: the cell replicated, wrapped into its periodic section. */
static TlStatus build_dem(TlGouge *g)
{
  const TlGougeParams *p = &g->p;
  Cell cell;
  TL_CHECK(read_cell(p->packing, &cell));
  TlStatus s = TL_OK;
  double a = cell.a;
  double rmin = INFINITY, rmax = 0.0;
  for (size_t i = 0; i < cell.n; ++i) {
    rmin = fmin(rmin, cell.r[i]);
    rmax = fmax(rmax, cell.r[i]);
  }
  g->info.a = a;
  double L = a * p->cells_section, Y = 0.5 * a * p->cells_y;
  g->info.section = L;
  g->info.Y = Y;
  if (s == TL_OK) s = tl_dem_create(&g->dem);
  TlParticles *P = s == TL_OK ? tl_dem_particles(g->dem) : NULL;
  int sp = 0;
  if (s == TL_OK) s = tl_particles_add_species(P, "gouge", p->grain_density, rmin, rmax, &sp);
  TlDomain dom;
  double margin = 4.0 * rmax;
  if (s == TL_OK)
    s = tl_domain_init_periodic_box(&dom, tl_v3(0, -Y - margin, 0), tl_v3(L, Y + margin, L), (int[3]){1, 0, 1});
  if (s == TL_OK) s = tl_dem_set_domain(g->dem, &dom);
  if (s == TL_OK) s = tl_particles_reserve(P, cell.n * (size_t)p->cells_section * p->cells_section * p->cells_y);
  for (int i = 0; s == TL_OK && i < p->cells_section; ++i)
    for (int j = 0; s == TL_OK && j < p->cells_y; ++j)
      for (int k = 0; s == TL_OK && k < p->cells_section; ++k)
        for (size_t n = 0; s == TL_OK && n < cell.n; ++n) {
          TlVec3 X = tl_v3(cell.x[n].x + i * a, cell.x[n].y + j * a - Y, cell.x[n].z + k * a);
          s = tl_dem_add_particle(g->dem, X, tl_v3(0, 0, 0), cell.r[n], sp, NULL);
        }
  cell_free(&cell);
  if (s) return s;
  const TlContactValue values[] = {{"k_n", p->k_n}, {"gamma_n", p->gamma_n}, {"k_t", p->k_t},
                                   {"gamma_t", p->gamma_t}, {"mu", p->mu}};
  const TlContactSpec spec = {"lammps_hertz", "lammps_history", NULL, NULL, values, 5};
  TlContactLaw *law = NULL;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  TlStatus sl = tl_dem_add_law(g->dem, law, NULL); /* the world owns it */
  if (sl) {
    tl_contact_law_destroy(&law);
    return sl;
  }
  if (p->threads > 0) tl_dem_set_threads(g->dem, p->threads);
  tl_dem_track_energy(g->dem, 0);
  TL_CHECK(tl_dem_set_timestep(g->dem, p->dt, 0));
  g->info.n_particles = P->n;
  return TL_OK;
}

/* Both bars in one mesh (one block "bars"), node sets xmin, xmax, zmin,
 * zmax (both bars), left_end, right_end (the far faces). */
static TlStatus build_mesh(TlGouge *g)
{
  const TlGougeParams *p = &g->p;
  TlGougeInfo *in = &g->info;
  double L = in->section, bridge = p->bridge > 0 ? p->bridge : in->a;
  if (bridge >= in->Y)
    TL_ERROR(TL_ERR_ARG, "gouge: bridging zone %g m must be shorter than the DEM half length %g m", bridge, in->Y);
  int ns = (int)lround(L / p->h);
  if (ns < 1) ns = 1;
  in->hx = L / ns;
  int nb = (int)lround(bridge / in->hx);
  if (nb < 1) nb = 1;
  in->hy = bridge / nb;
  int nbar = (int)lround(p->fe_length / in->hy);
  if (nbar < nb + 2)
    TL_ERROR(TL_ERR_ARG, "gouge: FE bar of %g m holds %d elements of %g m; at least the zone's %d + 2", p->fe_length,
             nbar, in->hy, nb);
  in->n_section = ns;
  in->n_bar = nbar;
  in->fe_start = in->Y - bridge;
  double y0 = in->fe_start, y1 = y0 + nbar * in->hy;
  TlMesh *box[2] = {NULL, NULL};
  size_t n[3] = {(size_t)ns, (size_t)nbar, (size_t)ns};
  TL_CHECK(tl_mesh_create_box(&tl_element_hex8, n, (double[3]){0, -y1, 0}, (double[3]){L, -y0, L}, &box[0]));
  TlStatus s = tl_mesh_create_box(&tl_element_hex8, n, (double[3]){0, y0, 0}, (double[3]){L, y1, L}, &box[1]);
  size_t nn = box[0] ? box[0]->n_nodes : 0, ne = box[0] ? box[0]->blocks[0].n_elements : 0;
  double *x = NULL;
  size_t *conn = NULL, *set = NULL;
  if (s == TL_OK) s = tl_calloc(&x, 6 * nn, sizeof *x);
  if (s == TL_OK) s = tl_calloc(&conn, 16 * ne, sizeof *conn);
  if (s == TL_OK) s = tl_calloc(&set, 2 * nn, sizeof *set);
  if (s == TL_OK) s = tl_mesh_create(3, &g->mesh);
  if (s == TL_OK) {
    for (int b = 0; b < 2; ++b) {
      memcpy(x + 3 * nn * b, box[b]->x, 3 * nn * sizeof *x);
      for (size_t k = 0; k < 8 * ne; ++k) conn[8 * ne * b + k] = box[b]->blocks[0].conn[k] + nn * b;
    }
    s = tl_mesh_set_nodes(g->mesh, 2 * nn, x);
  }
  if (s == TL_OK) s = tl_mesh_add_block(g->mesh, "bars", &tl_element_hex8, 2 * ne, conn, NULL, NULL);
  const char *names[4] = {"xmin", "xmax", "zmin", "zmax"};
  for (int k = 0; s == TL_OK && k < 4; ++k) {
    const TlNodeSet *a0, *a1;
    s = tl_mesh_find_node_set(box[0], names[k], &a0);
    if (s == TL_OK) s = tl_mesh_find_node_set(box[1], names[k], &a1);
    if (s == TL_OK) {
      for (size_t i = 0; i < a0->n; ++i) set[i] = a0->nodes[i];
      for (size_t i = 0; i < a1->n; ++i) set[a0->n + i] = a1->nodes[i] + nn;
      s = tl_mesh_add_node_set(g->mesh, names[k], a0->n + a1->n, set);
    }
  }
  if (s == TL_OK) {
    const TlNodeSet *e0, *e1;
    s = tl_mesh_find_node_set(box[0], "ymin", &e0);
    if (s == TL_OK) s = tl_mesh_add_node_set(g->mesh, "left_end", e0->n, e0->nodes);
    if (s == TL_OK) s = tl_mesh_find_node_set(box[1], "ymax", &e1);
    if (s == TL_OK) {
      for (size_t i = 0; i < e1->n; ++i) set[i] = e1->nodes[i] + nn;
      s = tl_mesh_add_node_set(g->mesh, "right_end", e1->n, set);
    }
  }
  if (s == TL_OK) s = tl_mesh_finalize(g->mesh);
  tl_free(&x);
  tl_free(&conn);
  tl_free(&set);
  tl_mesh_destroy(&box[0]);
  tl_mesh_destroy(&box[1]);
  if (s == TL_OK) in->n_nodes = g->mesh->n_nodes;
  return s;
}

/* Node planes: y sorted, each with the nodes that own their dofs (x < L
 * and z < L: the periodic images left out). */
static TlStatus build_planes(TlGouge *g)
{
  const TlMesh *m = g->mesh;
  double L = g->info.section, tol = 1e-6 * g->info.hy;
  size_t per = (size_t)g->info.n_section * g->info.n_section;
  size_t np = 2 * ((size_t)g->info.n_bar + 1);
  TL_CHECK(tl_calloc(&g->plane_y, np, sizeof *g->plane_y));
  TL_CHECK(tl_calloc(&g->plane_ptr, np + 1, sizeof *g->plane_ptr));
  TL_CHECK(tl_calloc(&g->plane_nodes, np * per, sizeof *g->plane_nodes));
  /* left bar planes from its far end inwards, then the right bar's */
  for (size_t k = 0; k < np; ++k) {
    size_t j = k <= (size_t)g->info.n_bar ? k : k - (size_t)g->info.n_bar - 1;
    double y0 = g->info.fe_start, y1 = y0 + g->info.n_bar * g->info.hy;
    g->plane_y[k] = k <= (size_t)g->info.n_bar ? -y1 + j * g->info.hy : y0 + j * g->info.hy;
  }
  for (size_t k = 0; k < np; ++k) {
    g->plane_ptr[k + 1] = g->plane_ptr[k];
    int bar = k > (size_t)g->info.n_bar;
    size_t lo = bar ? m->n_nodes / 2 : 0, hi = bar ? m->n_nodes : m->n_nodes / 2;
    for (size_t i = lo; i < hi; ++i) {
      const double *x = m->x + 3 * i;
      if (fabs(x[1] - g->plane_y[k]) < tol && x[0] < L - tol && x[2] < L - tol)
        g->plane_nodes[g->plane_ptr[k + 1]++] = i;
    }
    if (g->plane_ptr[k + 1] - g->plane_ptr[k] != per)
      TL_ERROR(TL_ERR_STATE, "gouge: node plane y = %g m holds %zu section nodes, expected %zu", g->plane_y[k],
               g->plane_ptr[k + 1] - g->plane_ptr[k], per);
  }
  g->info.n_planes = np;
  return TL_OK;
}

static size_t nearest_plane(const TlGouge *g, double y)
{
  size_t best = 0;
  for (size_t k = 1; k < g->info.n_planes; ++k)
    if (fabs(g->plane_y[k] - y) < fabs(g->plane_y[best] - y)) best = k;
  return best;
}

TlStatus tl_gouge_create(const TlGougeParams *p, TlGouge **out)
{
  if (!p || !out) TL_ERROR(TL_ERR_ARG, "gouge: NULL argument");
  *out = NULL;
  if (!p->packing || !p->packing[0]) TL_ERROR(TL_ERR_ARG, "gouge: no packing file given");
  if (p->cells_section < 1 || p->cells_y < 2)
    TL_ERROR(TL_ERR_ARG, "gouge: %d x %d cells; at least 1 across and 2 along y", p->cells_section, p->cells_y);
  if (!(p->h > 0) || !(p->fe_length > 0) || !(p->dt > 0))
    TL_ERROR(TL_ERR_ARG, "gouge: h = %g m, fe_length = %g m, dt = %g s must be > 0", p->h, p->fe_length, p->dt);
  if (p->wave_component != 0 && p->wave_component != 1)
    TL_ERROR(TL_ERR_ARG, "gouge: wave component %d is neither 1 (P, u_y) nor 0 (S, u_x)", p->wave_component);
  TL_CHECK(tl_bdm_options_check(&p->bdm));
  TlGouge *g = NULL;
  TL_CHECK(TL_NEW(g));
  g->p = *p;
  TlGougeInfo *in = &g->info;
  TlStatus s = build_dem(g);
  if (s == TL_OK) s = build_mesh(g);
  /* FE material: Table 2 with the eigenstrain pre-stress. */
  double K = p->E / (3.0 * (1.0 - 2.0 * p->nu)), G = p->E / (2.0 * (1.0 + p->nu)), M = K + 4.0 * G / 3.0;
  in->c_p = sqrt(M / p->rho);
  in->c_s = sqrt(G / p->rho);
  in->c = p->wave_component == 1 ? in->c_p : in->c_s;
  in->sigma0 = -3.0 * K * p->eigenstrain;
  if (s == TL_OK) s = tl_material_create("saint_venant_kirchhoff", &g->mat);
  if (s == TL_OK) s = tl_material_set(g->mat, "E", p->E);
  if (s == TL_OK) s = tl_material_set(g->mat, "nu", p->nu);
  if (s == TL_OK) s = tl_material_set(g->mat, "density", p->rho);
  double e0 = p->eigenstrain;
  if (s == TL_OK) s = tl_material_set_eigenstrain(g->mat, (TlMat3){{{e0, 0, 0}, {0, e0, 0}, {0, 0, e0}}});
  if (s == TL_OK) s = tl_solid_create(g->mesh, &g->solid);
  if (s == TL_OK) s = tl_solid_set_material(g->solid, NULL, g->mat);
  double L = in->section;
  if (s == TL_OK) s = tl_solid_tie(g->solid, "xmin", "xmax", (double[3]){L, 0, 0}, 1e-6 * in->hx);
  if (s == TL_OK) s = tl_solid_tie(g->solid, "zmin", "zmax", (double[3]){0, 0, L}, 1e-6 * in->hx);
  if (s == TL_OK) s = tl_solid_fix(g->solid, "right_end", 2);
  if (s == TL_OK) {
    if (p->mode == TL_GOUGE_WAVE) {
      s = tl_pulse_init(&g->pulse, p->pulse_shape, p->intensity, p->wavelength, in->c);
      g->pulse.subtract_initial = p->subtract_initial;
      if (s == TL_OK && p->wave_component == 0) s = tl_solid_fix(g->solid, "left_end", 2);
      if (s == TL_OK) s = tl_solid_prescribe(g->solid, "left_end", p->wave_component, tl_pulse_prescribed, &g->pulse);
    } else
      s = tl_solid_fix(g->solid, "left_end", 2);
  }
  /* The coupling sets both models' weights: before the solid's setup. */
  /* The zones end exactly on the bars' end planes as the mesh holds them
   * (a generated coordinate may differ from fe_start in the last bit). */
  double s_right = INFINITY, s_left = -INFINITY;
  for (size_t i = 0; s == TL_OK && i < g->mesh->n_nodes; ++i) {
    double yi = g->mesh->x[3 * i + 1];
    if (i < g->mesh->n_nodes / 2) s_left = fmax(s_left, yi);
    else s_right = fmin(s_right, yi);
  }
  TlBdmZone zones[2] = {{1, s_right, in->Y}, {1, s_left, -in->Y}};
  if (s == TL_OK) s = tl_bdm_create(g->solid, 0, g->dem, zones, 2, &p->bdm, &g->bdm);
  if (s == TL_OK) s = tl_solid_setup(g->solid);
  TlMechSystem *sys = s == TL_OK ? tl_solid_system(g->solid) : NULL;
  if (s == TL_OK && p->linear_fe) {
    s = tl_mech_linear_create(sys, 0.0, NULL, 0, &g->linear);
    sys = g->linear;
  }
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  if (s == TL_OK) s = tl_stepper_create("central_difference", sys, &so, &g->st);
  if (s == TL_OK) s = tl_stepper_set_state(g->st, 0.0, NULL, NULL);
  if (s == TL_OK && p->dt > g->st->dt_crit)
    s = tl_error_set(TL_ERR_UNSTABLE, __FILE__, __LINE__, "gouge: dt = %g s exceeds the FE critical step %g s", p->dt,
                     g->st->dt_crit);
  if (s == TL_OK) s = tl_dem_setup(g->dem);
  if (s == TL_OK) {
    double m_min, k_max;
    s = tl_dem_critical_timestep(g->dem, &in->dem_dt_critical, &k_max, &m_min);
  }
  if (s == TL_OK) s = tl_bdm_setup(g->bdm, g->st);
  if (s == TL_OK) s = build_planes(g);
  if (s == TL_OK) {
    TlBdmInfo bi;
    tl_bdm_info(g->bdm, &bi);
    in->n_coupled = bi.n_particles;
    in->n_dofs = (size_t)sys->ndof;
    double Ymid = in->fe_start + 0.5 * in->n_bar * in->hy;
    if (p->mode == TL_GOUGE_WAVE) {
      in->y_monitor[0] = g->plane_y[nearest_plane(g, -Ymid)];
      in->y_monitor[1] = g->plane_y[nearest_plane(g, Ymid)];
    } else {
      double bridge = in->Y - in->fe_start;
      in->y_monitor[0] = g->plane_y[nearest_plane(g, in->fe_start + 3.0 * bridge)];
      in->y_monitor[1] = g->plane_y[nearest_plane(g, -in->fe_start - 3.0 * bridge)];
    }
    in->y_monitor[2] = g->plane_y[nearest_plane(g, in->fe_start + in->hy)];
  }
  if (s) {
    tl_gouge_destroy(&g);
    return s;
  }
  *out = g;
  return TL_OK;
}

void tl_gouge_destroy(TlGouge **gp)
{
  if (!gp || !*gp) return;
  TlGouge *g = *gp;
  tl_particle_writer_destroy(&g->pw);
  tl_solid_output_destroy(&g->so);
  tl_bdm_destroy(&g->bdm);
  tl_stepper_destroy(&g->st);
  tl_mech_system_destroy(&g->linear);
  tl_solid_destroy(&g->solid);
  tl_material_destroy(&g->mat);
  tl_mesh_destroy(&g->mesh);
  tl_dem_destroy(&g->dem);
  tl_free(&g->plane_y);
  tl_free(&g->plane_ptr);
  tl_free(&g->plane_nodes);
  tl_free(&g->weights);
  tl_free(gp);
}

void tl_gouge_info(const TlGouge *g, TlGougeInfo *info) { *info = g->info; }
long tl_gouge_steps(const TlGouge *g) { return g->step; }
double tl_gouge_time(const TlGouge *g) { return g->st->t; }
void tl_gouge_times(const TlGouge *g, TlGougeTimes *t) { *t = g->times; }
void tl_gouge_report(const TlGouge *g, TlBdmReport *rep) { tl_bdm_last_report(g->bdm, rep); }

TlStatus tl_gouge_step(TlGouge *g)
{
  double t0 = tl_wtime();
  TL_CHECK(tl_dem_step(g->dem, 1));
  double t1 = tl_wtime();
  TL_CHECK(tl_stepper_step(g->st, g->p.dt));
  double t2 = tl_wtime();
  TL_CHECK(tl_bdm_correct(g->bdm, NULL));
  double t3 = tl_wtime();
  g->times.t_dem += t1 - t0;
  g->times.t_fe += t2 - t1;
  g->times.t_correct += t3 - t2;
  g->times.steps = ++g->step;
  return TL_OK;
}

void tl_gouge_planes(const TlGouge *g, double *y, double *u)
{
  for (size_t k = 0; k < g->info.n_planes; ++k) {
    if (y) y[k] = g->plane_y[k];
    double sum[3] = {0, 0, 0};
    size_t n = g->plane_ptr[k + 1] - g->plane_ptr[k];
    for (size_t i = g->plane_ptr[k]; i < g->plane_ptr[k + 1]; ++i)
      for (int c = 0; c < 3; ++c) {
        TlSparseIndex d = tl_solid_dof(g->solid, g->plane_nodes[i], c);
        sum[c] += d >= 0 ? g->st->u[d] : 0.0;
      }
    for (int c = 0; c < 3; ++c) u[3 * k + c] = sum[c] / (double)n;
  }
}

TlStatus tl_gouge_open_snapshots(TlGouge *g, const char *dir)
{
  if (!g->pw) TL_CHECK(tl_particle_writer_create(dir, "particles", &g->pw));
  if (!g->so) TL_CHECK(tl_solid_output_create(g->solid, dir, "bars", &g->so));
  return TL_OK;
}

TlStatus tl_gouge_snapshot(TlGouge *g, const char *dir)
{
  TlParticles *P = tl_dem_particles(g->dem);
  TL_CHECK(tl_gouge_open_snapshots(g, dir));
  TL_CHECK(tl_realloc(&g->weights, P->n + 1, sizeof *g->weights));
  for (size_t i = 0; i < P->n; ++i) g->weights[i] = P->weight ? P->weight[i] : 1.0;
  TlField fields[1] = {{"weight", 1, g->weights}};
  TlParticleView view = {.n = P->n, .position = P->x, .radius = P->radius, .velocity = P->v, .angular_velocity = P->w,
                         .force = P->f, .species = (const int *)P->species, .n_fields = 1, .fields = fields, .id = P->id};
  TL_CHECK(tl_particle_writer_write(g->pw, g->step, g->st->t, &view));
  TL_CHECK(tl_solid_output_write(g->so, g->step, g->st->t, g->st->u, g->st->v));
  return TL_OK;
}

/* The scene's own state: its step count (the rest is the models'). */
static TlStatus gouge_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlGouge *g = object;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "step", g->step));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_particles", (int64_t)g->info.n_particles));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_dofs", (int64_t)g->info.n_dofs));
  return TL_OK;
}

static TlStatus gouge_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlGouge *g = object;
  int64_t step = 0, np = 0, nd = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "step", &step));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_particles", &np));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_dofs", &nd));
  if (np != (int64_t)g->info.n_particles || nd != (int64_t)g->info.n_dofs)
    TL_ERROR(TL_ERR_ARG, "%s: a gouge of %lld particles and %lld FE dofs; this scene has %zu and %zu",
             tl_checkpoint_reader_path(r), (long long)np, (long long)nd, g->info.n_particles, g->info.n_dofs);
  TL_CHECK(tl_checkpoint_check_range(r, group, "step", (double)step, 0.0, 1e18));
  g->step = (long)step;
  g->times.steps = g->step;
  return TL_OK;
}

static const TlCheckpointOps gouge_checkpoint_ops = {{"checkpoint", "gouge_bridging", "the scene's step"}, gouge_save,
                                                     gouge_load};

static TlStatus make_checkpoint(TlGouge *g, TlCheckpoint **cp)
{
  TL_CHECK(tl_checkpoint_create(cp));
  TlStatus s = tl_checkpoint_add(*cp, "gouge", &gouge_checkpoint_ops, g);
  if (s == TL_OK) s = tl_checkpoint_add(*cp, "dem", &tl_dem_checkpoint_ops, g->dem);
  if (s == TL_OK) s = tl_checkpoint_add(*cp, "fem", &tl_stepper_checkpoint_ops, g->st);
  if (s == TL_OK) s = tl_checkpoint_add(*cp, "bdm", &tl_bdm_checkpoint_ops, g->bdm);
  /* The snapshot series, when open, so that a restart extends them. */
  if (s == TL_OK && g->pw) s = tl_checkpoint_add(*cp, "particle_snapshots", &tl_particle_writer_checkpoint_ops, g->pw);
  if (s == TL_OK && g->so) s = tl_checkpoint_add(*cp, "bar_snapshots", &tl_solid_output_checkpoint_ops, g->so);
  if (s) tl_checkpoint_destroy(cp);
  return s;
}

TlStatus tl_gouge_checkpoint_save(TlGouge *g, const char *path)
{
  TlCheckpoint *cp = NULL;
  TL_CHECK(make_checkpoint(g, &cp));
  TlStatus s = tl_checkpoint_save(cp, path, g->st->t, g->step);
  tl_checkpoint_destroy(&cp);
  return s;
}

TlStatus tl_gouge_checkpoint_load(TlGouge *g, const char *path)
{
  TlCheckpoint *cp = NULL;
  TL_CHECK(make_checkpoint(g, &cp));
  TlStatus s = tl_checkpoint_load(cp, path, NULL, NULL);
  tl_checkpoint_destroy(&cp);
  return s;
}
