/* The DEM world: life cycle, configuration, setup and the time-step limit. */
#include "tl_dem_private.h"

#include <math.h>
#include <omp.h>
#include <string.h>
#include "tl_log.h"
#include "tl_memory.h"

TlStatus tl_dem_create(TlDem **out)
{
  TlDem *d;
  TL_CHECK(TL_NEW(d));
  TlStatus s;
  TL_CHECK_GOTO(s, tl_particles_create(&d->P), fail);
  TL_CHECK_GOTO(s, tl_hgrid_create(&d->grid), fail);
  TL_CHECK_GOTO(s, tl_domain_init_open(&d->domain, tl_v3(0, 0, 0), tl_v3(1, 1, 1)), fail);
  d->skin_factor = 0.1;
  d->sort_every = 10;
  d->skip_fixed = 1;
  d->track_energy = 1;
  d->orientation = 1;
  d->need_rebuild = 1;
  d->dim = 3;
  d->max_initial_overlap = TL_DEM_MAX_INITIAL_OVERLAP;
  *out = d;
  return TL_OK;
fail:
  tl_dem_destroy(&d);
  return s;
}

void tl_dem_destroy(TlDem **dp)
{
  TlDem *d = *dp;
  if (!d) return;
  tl_particles_destroy(&d->P);
  tl_hgrid_destroy(&d->grid);
  for (int k = 0; k < d->n_laws; ++k) tl_contact_law_destroy(&d->laws[k]);
  for (size_t k = 0; k < d->n_walls; ++k) tl_wall_destroy(&d->walls[k]);
  tl_free(&d->walls);
  tl_free(&d->pair_laws);
  tl_free(&d->law_table);
  tl_contact_list_free(&d->list);
  tl_contact_list_free(&d->old);
  tl_contact_list_free(&d->bonds);
  tl_free(&d->bond_ids);
  tl_free(&d->chunks);
  tl_free(&d->bond_chunks);
  tl_free(&d->pairs);
  tl_free(&d->x_build);
  tl_free(&d->skip);
  tl_free(&d->perm);
  tl_free(&d->old_to_new);
  tl_free(&d->xr);
  tl_free(&d->wall_steps);
  tl_free(&d->wall_sums);
  Split *splits[2] = {&d->split_list, &d->split_bonds};
  for (int q = 0; q < 2; ++q) {
    tl_free(&splits[q]->owner);
    tl_free(&splits[q]->chunk_el);
    tl_free(&splits[q]->chunk_pw);
    for (int t = 0; t < TL_DEM_MAX_TIMED_THREADS; ++t) tl_free(&splits[q]->def[t]);
  }
  for (size_t k = 0; k < d->n_presc; ++k) {
    Prescribed *p = &d->presc[k];
    tl_free(&p->ids); tl_free(&p->idx); tl_free(&p->x0); tl_free(&p->xs); tl_free(&p->vs);
  }
  tl_free(&d->presc);
  tl_free(&d->scratch);
  tl_free(&d->cw_list);
  tl_free(&d->cw_bonds);
  tl_free(&d->cpoint);
  tl_free(&d->im_w);
  tl_free(&d->ii_w);
  tl_free(dp);
}

TlParticles *tl_dem_particles(TlDem *d) { return d->P; }
TlDomain *tl_dem_domain(TlDem *d) { return &d->domain; }
const TlHGrid *tl_dem_grid(const TlDem *d) { return d->grid; }
size_t tl_dem_n_walls(const TlDem *d) { return d->n_walls; }
TlWall *tl_dem_wall(TlDem *d, size_t k) { return k < d->n_walls ? d->walls[k] : NULL; }
double tl_dem_timestep(const TlDem *d) { return d->dt; }
double tl_dem_time(const TlDem *d) { return d->t; }
void tl_dem_set_gravity(TlDem *d, TlVec3 g) { d->gravity = g; }
void tl_dem_set_threads(TlDem *d, int threads)
{
  d->threads = threads;
  if (threads > 0) omp_set_num_threads(threads); /* walls follow the OpenMP default */
  if (d->setup_done) {
    d->nt = threads > 0 ? threads : omp_get_max_threads();
    if (d->nt > TL_DEM_MAX_TIMED_THREADS) d->nt = TL_DEM_MAX_TIMED_THREADS;
  }
}
void tl_dem_set_weight_field(TlDem *d, TlDemWeightFn fn, void *ctx)
{
  d->weight_fn = fn;
  d->weight_ctx = ctx;
}

void tl_dem_set_step_hook(TlDem *d, TlDemStepHook hook, void *ctx)
{
  d->hook = hook;
  d->hook_ctx = ctx;
}

void tl_dem_skip_fixed_pairs(TlDem *d, int skip) { d->skip_fixed = skip; d->need_rebuild = 1; }
void tl_dem_track_energy(TlDem *d, int on) { d->track_energy = on; }
void tl_dem_track_orientation(TlDem *d, int on) { d->orientation = on; }
void tl_dem_set_sort_interval(TlDem *d, int rebuilds) { d->sort_every = rebuilds < 0 ? 0 : rebuilds; }

TlStatus tl_dem_set_domain(TlDem *d, const TlDomain *domain)
{
  d->domain = *domain;
  d->need_rebuild = 1;
  return TL_OK;
}

TlStatus tl_dem_set_dimension(TlDem *d, int dim)
{
  if (dim != 2 && dim != 3) TL_ERROR(TL_ERR_ARG, "dimension %d must be 2 (disks) or 3 (spheres)", dim);
  if (d->setup_done && dim != d->dim)
    TL_ERROR(TL_ERR_STATE, "the dimension (%d) is set before tl_dem_setup; this world is set up in %d", dim, d->dim);
  d->dim = dim;
  return tl_particles_set_disks(d->P, dim == 2);
}

int tl_dem_dimension(const TlDem *d) { return d->dim; }

/* A two-dimensional world: a domain with an inert z and every particle in
 * the plane z = 0 at rest along z. */
static TlStatus check_planar_scene(const TlDem *d)
{
  const TlDomain *D = &d->domain;
  if (D->kind == TL_DOMAIN_DEFORMABLE_CELL && !D->planar)
    TL_ERROR(TL_ERR_ARG, "a 2-D world needs the planar cell (tl_domain_init_cell_2d); this deformable cell is periodic "
             "along z");
  if (D->periodic[2])
    TL_ERROR(TL_ERR_ARG, "a 2-D world's domain must not be periodic along z (periodic flags %d %d %d)", D->periodic[0],
             D->periodic[1], D->periodic[2]);
  const TlParticles *P = d->P;
  for (size_t i = 0; i < P->n; ++i)
    if (P->x[i].z != 0.0 || P->v[i].z != 0.0)
      TL_ERROR(TL_ERR_ARG, "2-D world: particle id %lld has z = %g, v_z = %g; disks lie in the plane z = 0 at rest along z",
               (long long)P->id[i], P->x[i].z, P->v[i].z);
  return TL_OK;
}

TlStatus tl_dem_set_skin(TlDem *d, double f)
{
  if (!(f >= 0.0) || !(f <= 10.0)) TL_ERROR(TL_ERR_ARG, "skin %g (fraction of the mean diameter) must be in [0, 10]", f);
  d->skin_factor = f;
  d->need_rebuild = 1;
  return TL_OK;
}

TlStatus tl_dem_add_law(TlDem *d, TlContactLaw *law, int *index)
{
  if (!law) TL_ERROR(TL_ERR_ARG, "contact law is NULL");
  if (d->n_laws >= TL_DEM_MAX_LAWS) TL_ERROR(TL_ERR_ARG, "too many contact laws (limit %d)", TL_DEM_MAX_LAWS);
  if (d->setup_done && law->history_doubles > d->hd)
    TL_ERROR(TL_ERR_STATE, "a law needing %zu history doubles cannot be added after setup (stride %zu)",
             law->history_doubles, d->hd);
  d->laws[d->n_laws] = law;
  if (index) *index = d->n_laws;
  d->n_laws++;
  return TL_OK;
}

TlStatus tl_dem_set_pair_law(TlDem *d, int a, int b, int law)
{
  if (law < 0 || law >= d->n_laws) TL_ERROR(TL_ERR_ARG, "law index %d out of range (%d laws)", law, d->n_laws);
  if (a < 0 || b < 0) TL_ERROR(TL_ERR_ARG, "species %d, %d must be >= 0", a, b);
  TL_CHECK(tl_array_reserve(&d->pair_laws, &d->pair_laws_cap, d->n_pair_laws + 1, sizeof *d->pair_laws));
  d->pair_laws[d->n_pair_laws++] = (PairLaw){a, b, law};
  d->need_rebuild = 1;
  return TL_OK;
}

int tl_dem_n_laws(const TlDem *d) { return d->n_laws; }

TlContactLaw *tl_dem_law(TlDem *d, int k) { return k >= 0 && k < d->n_laws ? d->laws[k] : NULL; }

int tl_dem_pair_law(const TlDem *d, int a, int b)
{
  int law = 0;
  for (size_t k = 0; k < d->n_pair_laws; ++k) {
    PairLaw p = d->pair_laws[k];
    if ((p.a == a && p.b == b) || (p.a == b && p.b == a)) law = p.law;
  }
  return law;
}

TlStatus tl_dem_add_wall(TlDem *d, TlWall *w, int law)
{
  if (!w) TL_ERROR(TL_ERR_ARG, "wall is NULL");
  if (law < 0 || law >= d->n_laws) TL_ERROR(TL_ERR_ARG, "wall law index %d out of range (%d laws); add the law first", law, d->n_laws);
  TL_CHECK(tl_array_reserve(&d->walls, &d->walls_cap, d->n_walls + 1, sizeof *d->walls));
  w->law = law;
  d->walls[d->n_walls++] = w;
  return TL_OK;
}

TlStatus tl_dem_add_bond(TlDem *d, int64_t a, int64_t b)
{
  if (a == b) TL_ERROR(TL_ERR_ARG, "bond of particle %lld with itself", (long long)a);
  TL_CHECK(tl_array_reserve(&d->bond_ids, &d->bond_ids_cap, d->n_bond_ids + 2, sizeof *d->bond_ids));
  d->bond_ids[d->n_bond_ids++] = a;
  d->bond_ids[d->n_bond_ids++] = b;
  d->need_rebuild = 1;
  d->bonds.n = (size_t)-1; /* bond list to be rebuilt from ids */
  return TL_OK;
}

TlStatus tl_dem_prescribe(TlDem *d, size_t n, const int64_t *ids, TlPrescribedEval eval, void *ctx)
{
  if (!eval || !n) TL_ERROR(TL_ERR_ARG, "prescribed motion needs a function and at least one particle (n = %zu)", n);
  TL_CHECK(tl_array_reserve(&d->presc, &d->presc_cap, d->n_presc + 1, sizeof *d->presc));
  Prescribed *p = &d->presc[d->n_presc];
  memset(p, 0, sizeof *p);
  p->eval = eval;
  p->ctx = ctx;
  p->n = n;
  TL_CHECK(tl_calloc(&p->ids, n, sizeof *p->ids));
  TL_CHECK(tl_calloc(&p->idx, n, sizeof *p->idx));
  TL_CHECK(tl_calloc(&p->x0, n, sizeof *p->x0));
  TL_CHECK(tl_calloc(&p->xs, n, sizeof *p->xs));
  TL_CHECK(tl_calloc(&p->vs, n, sizeof *p->vs));
  d->n_presc++;
  for (size_t k = 0; k < n; ++k) {
    p->ids[k] = ids[k];
    TL_CHECK(tl_particles_find(d->P, ids[k], &p->idx[k]));
    p->x0[k] = d->P->x[p->idx[k]];
    TL_CHECK(tl_particles_set_motion(d->P, p->idx[k], TL_MOTION_PRESCRIBED));
  }
  return TL_OK;
}

/* ------------------------------------------------------------ time step */

static double min_radius(const TlParticles *P, double *rmax, double *m_min)
{
  double r = INFINITY, R = 0.0, m = INFINITY;
  for (size_t i = 0; i < P->n; ++i) {
    r = fmin(r, P->radius[i]);
    R = fmax(R, P->radius[i]);
    if (P->motion[i] == TL_MOTION_FREE) m = fmin(m, P->mass[i]);
  }
  *rmax = R;
  *m_min = m;
  return r;
}

TlStatus tl_dem_critical_timestep(TlDem *d, double *dt_c, double *k_max_out, double *m_min_out)
{
  double rmax, m_min, rmin = min_radius(d->P, &rmax, &m_min);
  if (!d->P->n || !isfinite(m_min)) {
    *dt_c = INFINITY;
    if (k_max_out) *k_max_out = 0.0;
    if (m_min_out) *m_min_out = m_min;
    return TL_OK;
  }
  double overlap = 0.1 * rmin, k_max = 0.0, zeta = 0.0;
  for (int l = 0; l < d->n_laws; ++l) {
    const TlContactLaw *law = d->laws[l];
    double k = law->ops->max_stiffness(law, rmax, overlap);
    k_max = fmax(k_max, k);
    double c = law->ops->max_damping ? law->ops->max_damping(law, 0.5 * m_min, rmax, overlap) : 0.0;
    if (k > 0.0) zeta = fmax(zeta, c / (2.0 * sqrt(k * 0.5 * m_min)));
  }
  *dt_c = k_max > 0.0 ? 0.5 * sqrt(m_min / k_max) * (sqrt(1.0 + zeta * zeta) - zeta) : INFINITY;
  if (k_max_out) *k_max_out = k_max;
  if (m_min_out) *m_min_out = m_min;
  return TL_OK;
}

TlStatus tl_dem_set_max_initial_overlap(TlDem *d, double fraction)
{
  if (!(fraction > 0.0 && fraction <= 1.0))
    TL_ERROR(TL_ERR_ARG, "largest initial overlap %g of the smaller radius outside (0, 1]", fraction);
  d->max_initial_overlap = fraction;
  return TL_OK;
}

TlStatus tl_dem_set_timestep(TlDem *d, double dt, int allow)
{
  if (!(dt > 0.0) || !isfinite(dt)) TL_ERROR(TL_ERR_ARG, "time step %g must be positive and finite", dt);
  d->dt = dt;
  d->allow_above = allow;
  if (d->setup_done) {
    double dtc, k, m;
    TL_CHECK(tl_dem_critical_timestep(d, &dtc, &k, &m));
    if (dt > dtc && !allow)
      TL_ERROR(TL_ERR_UNSTABLE, "time step %g s exceeds the critical time step %g s (k_max = %g N/m, m_min = %g kg); "
               "reduce dt or set the override", dt, dtc, k, m);
  }
  return TL_OK;
}

/* --------------------------------------------------------------- setup */

TlStatus tl_dem_setup(TlDem *d)
{
  TlParticles *P = d->P;
  if (d->n_laws == 0) TL_ERROR(TL_ERR_STATE, "the scene has no contact law; add one with tl_dem_add_law");
  if (!(d->dt > 0.0)) TL_ERROR(TL_ERR_STATE, "no time step set; call tl_dem_set_timestep");
  if (d->dim == 2) TL_CHECK(check_planar_scene(d));
  for (size_t s = 0; s < P->n_species; ++s)
    if (!(P->species_table[s].density > 0.0))
      TL_ERROR(TL_ERR_ARG, "species %zu has density %g; it must be positive", s, P->species_table[s].density);
  size_t hd = 0;
  int rot = 0;
  for (int l = 0; l < d->n_laws; ++l) {
    if (d->laws[l]->history_doubles > hd) hd = d->laws[l]->history_doubles;
    rot |= d->laws[l]->needs_rotation;
  }
  d->hd = hd;
  TL_CHECK(tl_contact_list_init(&d->list, hd));
  TL_CHECK(tl_contact_list_init(&d->old, hd));
  TL_CHECK(tl_contact_list_init(&d->bonds, hd));
  if (d->n_bond_ids) d->bonds.n = (size_t)-1;
  if (rot) TL_CHECK(tl_particles_enable_rotation(P));
  d->rotation = rot;
  d->nt = d->threads > 0 ? d->threads : omp_get_max_threads();
  if (d->nt < 1) d->nt = 1;
  if (d->nt > TL_DEM_MAX_TIMED_THREADS) d->nt = TL_DEM_MAX_TIMED_THREADS; /* owners are bytes */
  TL_CHECK(tl_dem_build_law_table(d));
  /* skin from the mean diameter */
  double mean = 0.0;
  for (size_t i = 0; i < P->n; ++i) {
    if (!(P->radius[i] > 0.0)) TL_ERROR(TL_ERR_ARG, "particle %zu has radius %g; it must be positive", i, P->radius[i]);
    if (!tl_v3_isfinite(P->x[i]) || !tl_v3_isfinite(P->v[i]))
      TL_ERROR(TL_ERR_ARG, "particle %zu (id %lld) has a non-finite position or velocity", i, (long long)P->id[i]);
    mean += 2.0 * P->radius[i];
  }
  mean = P->n ? mean / (double)P->n : 1.0;
  d->skin = d->skin_factor * mean;
  double rmax;
  double m_min;
  d->r_min = min_radius(P, &rmax, &m_min);
  d->max_cut = 2.0 * rmax + d->skin;
  /* time step */
  double dtc, k, m;
  TL_CHECK(tl_dem_critical_timestep(d, &dtc, &k, &m));
  if (d->dt > dtc) {
    if (!d->allow_above)
      TL_ERROR(TL_ERR_UNSTABLE, "time step %g s exceeds the critical time step %g s (k_max = %g N/m, m_min = %g kg); "
               "reduce dt or set the override", d->dt, dtc, k, m);
    tl_warn("time step %g s is above the critical time step %g s (k_max = %g N/m, m_min = %g kg): override in force",
            d->dt, dtc, k, m);
  }
  d->setup_done = 1;
  d->need_rebuild = 1;
  TL_CHECK(tl_dem_rebuild(d));
  /* Large initial overlaps are a broken scene, not a stiff one: released,
   * they explode (an S1 pair overlapping by 0.6 of a radius gains 25 kJ
   * against the scene's 0.87 J). */
  for (size_t q = 0; q < d->list.n; ++q) {
    uint32_t i = d->list.i[q], j = d->list.j[q];
    TlVec3 b = tl_domain_branch(&d->domain, P->x[i], P->x[j]);
    double ov = P->radius[i] + P->radius[j] - tl_v3_norm(b);
    double rs = fmin(P->radius[i], P->radius[j]);
    if (ov > d->max_initial_overlap * rs)
      TL_ERROR(TL_ERR_ARG,
               "particles id %lld and id %lld overlap by %g m at the start, %.3g of the smaller radius %g m, beyond "
               "the limit %g of it (tl_dem_set_max_initial_overlap)",
               (long long)P->id[i], (long long)P->id[j], ov, ov / rs, rs, d->max_initial_overlap);
  }
  /* The first evaluation is of one instant: no time passes, so the laws'
   * incremental histories (a tangential spring) must not advance over it; the
   * laws see dt = 0.  LAMMPS's setup does the same (no shear update while
   * update->setupflag), and only then do runs that start with contacts agree. */
  const double dt = d->dt;
  d->dt = 0.0;
  TlStatus first = tl_dem_eval_forces(d);
  d->dt = dt;
  TL_CHECK(first);
  d->contact_work_pp = d->elastic_pp; /* stored energy at start counts as work done on contacts */
  for (size_t w = 0; w < d->n_walls; ++w) d->walls[w]->contact_work = d->walls[w]->elastic_energy;
  return TL_OK;
}
