/* Checkpoint of a DEM world: save and load of its whole state. */
#include "tl_dem_private.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include "tl_memory.h"

static TlStatus save_list(const TlContactList *L, TlCheckpointWriter *w, const char *group)
{
  size_t n = L->n == (size_t)-1 ? 0 : L->n;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n", L->n == (size_t)-1 ? -1 : (int64_t)L->n));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "history_doubles", (int64_t)L->history_doubles));
  TL_CHECK(tl_checkpoint_write_bytes(w, group, "i", n * sizeof *L->i, L->i));
  TL_CHECK(tl_checkpoint_write_bytes(w, group, "j", n * sizeof *L->j, L->j));
  TL_CHECK(tl_checkpoint_write_bytes(w, group, "law", n, L->law));
  TL_CHECK(tl_checkpoint_write_bytes(w, group, "touching", n, L->touching));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "force", 3 * n, (const double *)L->force));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "history", n * L->history_doubles, L->history));
  return TL_OK;
}

/* A count read from the file sizes allocations only once the array it
 * counts is stored with that length. */
static TlStatus check_stored_length(TlCheckpointReader *r, const char *group, const char *name, size_t expect,
                                    const char *count_name, int64_t count)
{
  size_t have = 0;
  TL_CHECK(tl_checkpoint_length(r, group, name, &have));
  if (have != expect)
    TL_ERROR(TL_ERR_FORMAT, "%s: %s/%s = %lld does not match the stored %s (%zu values, %zu expected)",
             tl_checkpoint_reader_path(r), group[0] == '/' ? group + 1 : group, count_name, (long long)count, name,
             have, expect);
  return TL_OK;
}

static TlStatus load_list(TlContactList *L, TlCheckpointReader *r, const char *group, int n_laws, int may_be_unbuilt)
{
  const char *path = tl_checkpoint_reader_path(r);
  int64_t n64 = 0, hd = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n", &n64));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "history_doubles", &hd));
  if (hd != (int64_t)L->history_doubles)
    TL_ERROR(TL_ERR_ARG, "%s: '%s' has %lld history doubles per contact; the laws of this scene keep %zu", path, group,
             (long long)hd, L->history_doubles);
  /* -1: bonds still to be built from ids; the contact list always exists */
  TL_CHECK(tl_checkpoint_check_count(r, group, "n", n64, may_be_unbuilt ? -1 : 0, UINT32_MAX));
  if (n64 < 0) {
    L->n = (size_t)-1;
    return TL_OK;
  }
  if (n64 > (int64_t)UINT32_MAX) TL_ERROR(TL_ERR_ARG, "%s: '%s' holds %lld contacts (limit %u)", path, group, (long long)n64, UINT32_MAX);
  size_t n = (size_t)n64;
  TL_CHECK(check_stored_length(r, group, "force", 3 * n, "n", n64));
  TL_CHECK(tl_contact_list_reserve(L, n));
  TL_CHECK(tl_checkpoint_read_bytes(r, group, "i", n * sizeof *L->i, L->i));
  TL_CHECK(tl_checkpoint_read_bytes(r, group, "j", n * sizeof *L->j, L->j));
  TL_CHECK(tl_checkpoint_read_bytes(r, group, "law", n, L->law));
  TL_CHECK(tl_checkpoint_read_bytes(r, group, "touching", n, L->touching));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "force", 3 * n, (double *)L->force));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "history", n * L->history_doubles, L->history));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "force", 3 * n, (const double *)L->force));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "history", n * L->history_doubles, L->history));
  for (size_t k = 0; k < n; ++k)
    if (L->touching[k] > 1)
      TL_ERROR(TL_ERR_FORMAT, "%s: '%s' contact %zu has touching flag %d (0 or 1)", path, group, k, L->touching[k]);
  for (size_t k = 0; k < n; ++k)
    if (L->law[k] >= n_laws)
      TL_ERROR(TL_ERR_ARG, "%s: '%s' contact %zu uses law %d; this scene has %d laws", path, group, k, L->law[k], n_laws);
  L->n = n;
  return TL_OK;
}

/* The particles' state as tl_particles_add would accept it: finite
 * positions, velocities and forces, positive radii and masses, inverse masses
 * 1/m (0 for a fixed particle), known motion codes, unique ids below next_id. */
static TlStatus check_particles(const TlParticles *P, size_t n, TlCheckpointReader *r, const char *sub)
{
  const char *path = tl_checkpoint_reader_path(r);
  TL_CHECK(tl_checkpoint_check_finite(r, sub, "x", 3 * n, (const double *)P->x));
  TL_CHECK(tl_checkpoint_check_finite(r, sub, "v", 3 * n, (const double *)P->v));
  TL_CHECK(tl_checkpoint_check_finite(r, sub, "f", 3 * n, (const double *)P->f));
  TL_CHECK(tl_checkpoint_check_positive(r, sub, "radius", n, P->radius, 0));
  TL_CHECK(tl_checkpoint_check_positive(r, sub, "mass", n, P->mass, 0));
  TL_CHECK(tl_checkpoint_check_positive(r, sub, "inv_mass", n, P->inv_mass, 1));
  for (size_t i = 0; i < n; ++i)
    if (P->inv_mass[i] != 0.0 && !(fabs(P->inv_mass[i] * P->mass[i] - 1.0) <= 1e-12))
      TL_ERROR(TL_ERR_FORMAT, "%s: particle %zu has mass %g and inverse mass %g (neither 1/m nor 0)", path, i,
               P->mass[i], P->inv_mass[i]);
  for (size_t i = 0; i < n; ++i)
    if (P->motion[i] > TL_MOTION_PRESCRIBED)
      TL_ERROR(TL_ERR_FORMAT, "%s: particle %zu has motion code %d (at most %d)", path, i, P->motion[i],
               (int)TL_MOTION_PRESCRIBED);
  for (size_t i = 0; i < n; ++i)
    if (P->id[i] < 0 || P->id[i] >= P->next_id)
      TL_ERROR(TL_ERR_FORMAT, "%s: particle %zu has id %lld outside [0, next_id = %lld)", path, i,
               (long long)P->id[i], (long long)P->next_id);
  if (P->q) {
    TL_CHECK(tl_checkpoint_check_finite(r, sub, "q", 4 * n, (const double *)P->q));
    TL_CHECK(tl_checkpoint_check_finite(r, sub, "w", 3 * n, (const double *)P->w));
    TL_CHECK(tl_checkpoint_check_finite(r, sub, "torque", 3 * n, (const double *)P->torque));
    TL_CHECK(tl_checkpoint_check_positive(r, sub, "inv_inertia", n, P->inv_inertia, 1));
  }
  if (P->f_ext) TL_CHECK(tl_checkpoint_check_finite(r, sub, "f_ext", 3 * n, (const double *)P->f_ext));
  return TL_OK;
}

/* Clocks and accumulators: a time and a step as tl_dem_set_timestep accepts
 * them (positive, finite, within the stability limit unless the scene allows
 * more), non-negative counters, finite energies. */
static TlStatus check_run_state(TlDem *d, TlCheckpointReader *r, const char *group, const double scalars[8])
{
  TL_CHECK(tl_checkpoint_check_range(r, group, "t", d->t, -1e300, 1e300));
  TL_CHECK(tl_checkpoint_check_range(r, group, "dt", d->dt, 1e-300, 1e300));
  TL_CHECK(tl_checkpoint_check_count(r, group, "steps", d->steps, 0, INT64_MAX));
  TL_CHECK(tl_checkpoint_check_count(r, group, "rebuilds", d->rebuilds, 0, INT64_MAX));
  TL_CHECK(tl_checkpoint_check_count(r, group, "need_rebuild", d->need_rebuild, 0, 1));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "skin_cut_rmin_disp2_energy", 8, scalars));
  TL_CHECK(tl_checkpoint_check_range(r, group, "skin", d->skin, 0.0, 1e300));
  TL_CHECK(tl_checkpoint_check_range(r, group, "disp2max", d->disp2max, 0.0, 1e300));
  if (d->P->n) {
    double dtc, k, m;
    TL_CHECK(tl_dem_critical_timestep(d, &dtc, &k, &m));
    if (d->dt > dtc && !d->allow_above)
      TL_ERROR(TL_ERR_FORMAT, "%s: dt = %g s exceeds the critical time step %g s of the saved particles "
               "(k_max = %g N/m, m_min = %g kg)", tl_checkpoint_reader_path(r), d->dt, dtc, k, m);
  }
  return TL_OK;
}

/* The domain: finite cell vectors with det h > 0 and h_inv its inverse;
 * along periodic directions the positions inside the cell, give or take one
 * cell length (they are wrapped at each rebuild). */
static TlStatus check_domain(const TlDem *d, size_t n, TlCheckpointReader *r, const char *group, const char *sub)
{
  const TlDomain *D = &d->domain;
  const char *path = tl_checkpoint_reader_path(r);
  TL_CHECK(tl_checkpoint_check_finite(r, group, "domain_origin", 3, &D->origin.x));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "domain_h", 9, &D->h.m[0][0]));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "domain_h_inv", 9, &D->h_inv.m[0][0]));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "domain_h_dot", 9, &D->h_dot.m[0][0]));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "domain_L", 9, &D->L.m[0][0]));
  TL_CHECK(tl_checkpoint_check_count(r, group, "domain_deforming", D->deforming, 0, 1));
  TlMat3 I = tl_m3_mul(D->h, D->h_inv);
  double err = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) err = fmax(err, fabs(I.m[a][b] - (a == b)));
  if (!(tl_m3_det(D->h) > 0.0) || !(err <= 1e-9))
    TL_ERROR(TL_ERR_FORMAT, "%s: the saved cell has det h = %g and |h h_inv - I| = %g (det > 0, h_inv the inverse)",
             path, tl_m3_det(D->h), err);
  if (!D->any_periodic) return TL_OK;
  for (size_t i = 0; i < n; ++i) {
    TlVec3 s = tl_domain_to_reduced(D, d->P->x[i]);
    const double *c = &s.x;
    for (int k = 0; k < 3; ++k)
      if (D->periodic[k] && !(c[k] >= -1.0 && c[k] <= 2.0))
        TL_ERROR(TL_ERR_FORMAT, "%s: %s/x of particle %zu is %g cell lengths along periodic direction %d "
                 "(the cell is [0, 1))", path, sub, i, c[k], k);
  }
  return TL_OK;
}

static TlStatus dem_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlDem *d = object;
  const TlParticles *P = d->P;
  const size_t n = P->n;
  char sub[512];
  if (!d->setup_done) TL_ERROR(TL_ERR_STATE, "a DEM world is checkpointed after tl_dem_setup");
  /* run state */
  TL_CHECK(tl_checkpoint_write_double(w, group, "t", d->t));
  TL_CHECK(tl_checkpoint_write_double(w, group, "dt", d->dt));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "steps", d->steps));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "rebuilds", d->rebuilds));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "need_rebuild", d->need_rebuild));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_touching", (int64_t)d->n_touching));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_laws", d->n_laws));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "rotation", d->rotation));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "dimension", d->dim));
  double scalars[8] = {d->skin, d->max_cut, d->r_min, d->disp2max, d->elastic_pp, d->contact_work_pp, d->work_ext, 0.0};
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "skin_cut_rmin_disp2_energy", 8, scalars));
  /* domain */
  const TlDomain *D = &d->domain;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "domain_kind", (int64_t)D->kind));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "domain_origin", 3, &D->origin.x));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "domain_h", 9, &D->h.m[0][0]));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "domain_h_inv", 9, &D->h_inv.m[0][0]));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "domain_h_dot", 9, &D->h_dot.m[0][0]));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "domain_L", 9, &D->L.m[0][0]));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "domain_deforming", D->deforming));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "domain_planar", D->planar));
  /* particles */
  snprintf(sub, sizeof sub, "%s/particles", group ? group : "");
  TL_CHECK(tl_checkpoint_write_int64(w, sub, "n", (int64_t)n));
  TL_CHECK(tl_checkpoint_write_int64(w, sub, "next_id", P->next_id));
  TL_CHECK(tl_checkpoint_write_int64(w, sub, "n_species", (int64_t)P->n_species));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "x", 3 * n, (const double *)P->x));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "v", 3 * n, (const double *)P->v));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "f", 3 * n, (const double *)P->f));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "radius", n, P->radius));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "mass", n, P->mass));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "inv_mass", n, P->inv_mass));
  TL_CHECK(tl_checkpoint_write_bytes(w, sub, "species", n * sizeof *P->species, P->species));
  TL_CHECK(tl_checkpoint_write_bytes(w, sub, "motion", n, P->motion));
  TL_CHECK(tl_checkpoint_write_int64s(w, sub, "id", n, P->id));
  if (P->q) {
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "q", 4 * n, (const double *)P->q));
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "w", 3 * n, (const double *)P->w));
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "torque", 3 * n, (const double *)P->torque));
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "inv_inertia", n, P->inv_inertia));
  }
  if (P->f_ext) TL_CHECK(tl_checkpoint_write_doubles(w, sub, "f_ext", 3 * n, (const double *)P->f_ext));
  if (P->f_coupling)
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "f_coupling", 3 * n, (const double *)P->f_coupling));
  if (P->weight) TL_CHECK(tl_checkpoint_write_doubles(w, sub, "weight", n, P->weight));
  /* neighbour list as it stands, and its build state */
  snprintf(sub, sizeof sub, "%s/contacts", group ? group : "");
  TL_CHECK(save_list(&d->list, w, sub));
  snprintf(sub, sizeof sub, "%s/bonds", group ? group : "");
  TL_CHECK(save_list(&d->bonds, w, sub));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "x_build", 3 * n, (const double *)d->x_build));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "h_build_inv", 9, &d->h_build_inv.m[0][0]));
  /* prescribed motions: current indices and attach positions */
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_prescribed", (int64_t)d->n_presc));
  for (size_t g = 0; g < d->n_presc; ++g) {
    const Prescribed *p = &d->presc[g];
    snprintf(sub, sizeof sub, "%s/prescribed_%zu", group ? group : "", g);
    TL_CHECK(tl_checkpoint_write_int64s(w, sub, "id", p->n, p->ids));
    TL_CHECK(tl_checkpoint_write_bytes(w, sub, "index", p->n * sizeof *p->idx, p->idx));
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "x0", 3 * p->n, (const double *)p->x0));
  }
  /* walls: their own state through the hooks, and the accounting */
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_walls", (int64_t)d->n_walls));
  for (size_t k = 0; k < d->n_walls; ++k) {
    const TlWall *W = d->walls[k];
    snprintf(sub, sizeof sub, "%s/wall_%zu", group ? group : "", k);
    TL_CHECK(tl_checkpoint_write_string(w, sub, "type", W->ops->header.name));
    double acc[9] = {W->elastic_energy, W->contact_work, W->work, W->force.x, W->force.y, W->force.z,
                     W->torque.x, W->torque.y, W->torque.z};
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "accounting", 9, acc));
    TL_CHECK(tl_checkpoint_write_int64(w, sub, "n_contacts", (int64_t)W->n_contacts));
    if (!W->ops->checkpoint_size || !W->ops->checkpoint_save)
      TL_ERROR(TL_ERR_STATE, "wall '%s' (%s) has no checkpoint hooks", W->name, W->ops->header.name);
    size_t bytes = W->ops->checkpoint_size(W);
    void *buffer = NULL;
    TL_CHECK(tl_calloc(&buffer, bytes ? bytes : 1, 1));
    TlStatus s = W->ops->checkpoint_save(W, buffer, bytes);
    if (s == TL_OK) s = tl_checkpoint_write_bytes(w, sub, "state", bytes, buffer);
    tl_free(&buffer);
    TL_CHECK(s);
  }
  return TL_OK;
}

static TlStatus dem_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlDem *d = object;
  TlParticles *P = d->P;
  const char *path = tl_checkpoint_reader_path(r);
  char sub[512];
  if (!d->setup_done) TL_ERROR(TL_ERR_STATE, "%s: load into a DEM world after tl_dem_setup (built as the saved one)", path);
  int64_t v = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_laws", &v));
  if (v != d->n_laws) TL_ERROR(TL_ERR_ARG, "%s: the saved scene has %lld contact laws; this one %d", path, (long long)v, d->n_laws);
  TL_CHECK(tl_checkpoint_read_int64(r, group, "rotation", &v));
  if (v != d->rotation)
    TL_ERROR(TL_ERR_ARG, "%s: the saved scene %s rotation; this one %s", path, v ? "has" : "has no", d->rotation ? "has" : "has none");
  /* the dimension: checkpoints written before the 2-D mode are of 3-D worlds */
  v = 3;
  if (tl_checkpoint_has(r, group, "dimension")) TL_CHECK(tl_checkpoint_read_int64(r, group, "dimension", &v));
  if (v != d->dim)
    TL_ERROR(TL_ERR_ARG, "%s: the saved world is %lld-dimensional; this one %d (tl_dem_set_dimension)", path,
             (long long)v, d->dim);
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_walls", &v));
  if (v != (int64_t)d->n_walls) TL_ERROR(TL_ERR_ARG, "%s: the saved scene has %lld walls; this one %zu", path, (long long)v, d->n_walls);
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_prescribed", &v));
  if (v != (int64_t)d->n_presc)
    TL_ERROR(TL_ERR_ARG, "%s: the saved scene has %lld prescribed-motion groups; this one %zu", path, (long long)v, d->n_presc);
  /* particles */
  snprintf(sub, sizeof sub, "%s/particles", group ? group : "");
  int64_t n64 = 0, ns = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, sub, "n", &n64));
  TL_CHECK(tl_checkpoint_read_int64(r, sub, "n_species", &ns));
  if (ns != (int64_t)P->n_species)
    TL_ERROR(TL_ERR_ARG, "%s: the saved scene has %lld species; this one %zu", path, (long long)ns, P->n_species);
  if (n64 < 0 || n64 > (int64_t)UINT32_MAX) TL_ERROR(TL_ERR_ARG, "%s: particle count %lld out of range [0, %u]", path, (long long)n64, UINT32_MAX);
  const size_t n = (size_t)n64;
  if (P->q && !tl_checkpoint_has(r, sub, "q")) TL_ERROR(TL_ERR_ARG, "%s: no rotational state saved; this scene rotates", path);
  if (P->f_ext && !tl_checkpoint_has(r, sub, "f_ext")) TL_ERROR(TL_ERR_ARG, "%s: no external forces saved; this scene has them", path);
  if (!P->f_ext && tl_checkpoint_has(r, sub, "f_ext")) TL_CHECK(tl_particles_enable_external_force(P));
  if (tl_checkpoint_has(r, sub, "f_coupling")) TL_CHECK(tl_particles_enable_coupling_force(P));
  if (tl_checkpoint_has(r, sub, "weight")) TL_CHECK(tl_particles_enable_weights(P));
  TL_CHECK(check_stored_length(r, sub, "x", 3 * n, "n", n64));
  TL_CHECK(tl_particles_reserve(P, n));
  TL_CHECK(tl_checkpoint_read_int64(r, sub, "next_id", &P->next_id));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "x", 3 * n, (double *)P->x));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "v", 3 * n, (double *)P->v));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "f", 3 * n, (double *)P->f));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "radius", n, P->radius));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "mass", n, P->mass));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "inv_mass", n, P->inv_mass));
  TL_CHECK(tl_checkpoint_read_bytes(r, sub, "species", n * sizeof *P->species, P->species));
  TL_CHECK(tl_checkpoint_read_bytes(r, sub, "motion", n, P->motion));
  TL_CHECK(tl_checkpoint_read_int64s(r, sub, "id", n, P->id));
  if (P->q) {
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "q", 4 * n, (double *)P->q));
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "w", 3 * n, (double *)P->w));
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "torque", 3 * n, (double *)P->torque));
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "inv_inertia", n, P->inv_inertia));
  }
  if (P->f_ext) TL_CHECK(tl_checkpoint_read_doubles(r, sub, "f_ext", 3 * n, (double *)P->f_ext));
  if (P->f_coupling && tl_checkpoint_has(r, sub, "f_coupling"))
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "f_coupling", 3 * n, (double *)P->f_coupling));
  if (P->weight && tl_checkpoint_has(r, sub, "weight"))
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "weight", n, P->weight));
  TL_CHECK(check_particles(P, n, r, sub));
  if (d->dim == 2)
    for (size_t i = 0; i < n; ++i)
      if (P->x[i].z != 0.0 || P->v[i].z != 0.0)
        TL_ERROR(TL_ERR_FORMAT, "%s: 2-D world: particle %zu has z = %g, v_z = %g (disks lie in the plane z = 0)", path, i,
                 P->x[i].z, P->v[i].z);
  for (size_t i = 0; i < n; ++i)
    if (P->species[i] < 0 || (size_t)P->species[i] >= P->n_species)
      TL_ERROR(TL_ERR_ARG, "%s: particle %zu has species %d; this scene has %zu", path, i, P->species[i], P->n_species);
  P->n = n;
  /* run state */
  TL_CHECK(tl_checkpoint_read_double(r, group, "t", &d->t));
  TL_CHECK(tl_checkpoint_read_double(r, group, "dt", &d->dt));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "steps", &v));
  d->steps = (long)v;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "rebuilds", &v));
  d->rebuilds = (long)v;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "need_rebuild", &v));
  d->need_rebuild = (int)v;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_touching", &v));
  TL_CHECK(tl_checkpoint_check_count(r, group, "n_touching", v, 0, UINT32_MAX));
  d->n_touching = (size_t)v;
  double scalars[8];
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "skin_cut_rmin_disp2_energy", 8, scalars));
  d->skin = scalars[0];
  d->max_cut = scalars[1];
  d->r_min = scalars[2];
  d->disp2max = scalars[3];
  d->elastic_pp = scalars[4];
  d->contact_work_pp = scalars[5];
  d->work_ext = scalars[6];
  TL_CHECK(check_run_state(d, r, group, scalars));
  /* domain */
  TlDomain *D = &d->domain;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "domain_kind", &v));
  if (v != (int64_t)D->kind) TL_ERROR(TL_ERR_ARG, "%s: the saved domain is of kind %lld; this one %d", path, (long long)v, (int)D->kind);
  v = 0;
  if (tl_checkpoint_has(r, group, "domain_planar")) TL_CHECK(tl_checkpoint_read_int64(r, group, "domain_planar", &v));
  if (v != D->planar)
    TL_ERROR(TL_ERR_ARG, "%s: the saved domain %s planar; this one %s", path, v ? "is" : "is not", D->planar ? "is" : "is not");
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "domain_origin", 3, &D->origin.x));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "domain_h", 9, &D->h.m[0][0]));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "domain_h_inv", 9, &D->h_inv.m[0][0]));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "domain_h_dot", 9, &D->h_dot.m[0][0]));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "domain_L", 9, &D->L.m[0][0]));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "domain_deforming", &v));
  D->deforming = (int)v;
  TL_CHECK(check_domain(d, n, r, group, sub));
  /* neighbour list */
  snprintf(sub, sizeof sub, "%s/contacts", group ? group : "");
  TL_CHECK(load_list(&d->list, r, sub, d->n_laws, 0));
  snprintf(sub, sizeof sub, "%s/bonds", group ? group : "");
  TL_CHECK(load_list(&d->bonds, r, sub, d->n_laws, 1));
  TlContactList *lists[2] = {&d->list, &d->bonds};
  for (int q = 0; q < 2; ++q)
    if (lists[q]->n != (size_t)-1)
      for (size_t k = 0; k < lists[q]->n; ++k)
        if (lists[q]->i[k] >= n || lists[q]->j[k] >= n)
          TL_ERROR(TL_ERR_ARG, "%s: contact %zu joins particles %u and %u; there are %zu", path, k, lists[q]->i[k],
                   lists[q]->j[k], n);
  TL_CHECK(tl_dem_make_chunks(&d->list, &d->chunks, &d->chunks_cap, &d->n_chunks));
  d->list_version++;
  if (d->bonds.n != (size_t)-1) {
    if (d->bonds.n) TL_CHECK(tl_contact_list_index(&d->bonds, 0));
    TL_CHECK(tl_dem_make_chunks(&d->bonds, &d->bond_chunks, &d->bond_chunks_cap, &d->n_bond_chunks));
  }
  if (n > d->x_build_cap) {
    TL_CHECK(tl_realloc(&d->x_build, n + n / 2 + 16, sizeof *d->x_build));
    d->x_build_cap = n + n / 2 + 16;
  }
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "x_build", 3 * n, (double *)d->x_build));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "h_build_inv", 9, &d->h_build_inv.m[0][0]));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "x_build", 3 * n, (const double *)d->x_build));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "h_build_inv", 9, &d->h_build_inv.m[0][0]));
  /* the grid walls query between rebuilds: from the build positions */
  TL_CHECK(tl_hgrid_build(d->grid, &d->domain, n, d->x_build, P->radius, d->skin));
  /* prescribed motions */
  for (size_t g = 0; g < d->n_presc; ++g) {
    Prescribed *p = &d->presc[g];
    snprintf(sub, sizeof sub, "%s/prescribed_%zu", group ? group : "", g);
    size_t m = 0;
    TL_CHECK(tl_checkpoint_length(r, sub, "id", &m));
    if (m != p->n)
      TL_ERROR(TL_ERR_ARG, "%s: prescribed group %zu has %zu particles saved; this one %zu", path, g, m, p->n);
    TL_CHECK(tl_checkpoint_read_int64s(r, sub, "id", p->n, p->ids));
    TL_CHECK(tl_checkpoint_read_bytes(r, sub, "index", p->n * sizeof *p->idx, p->idx));
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "x0", 3 * p->n, (double *)p->x0));
    TL_CHECK(tl_checkpoint_check_finite(r, sub, "x0", 3 * p->n, (const double *)p->x0));
    for (size_t k = 0; k < p->n; ++k)
      if (p->idx[k] >= n || P->id[p->idx[k]] != p->ids[k])
        TL_ERROR(TL_ERR_ARG, "%s: prescribed particle id %lld is not at its saved index %zu", path, (long long)p->ids[k], p->idx[k]);
  }
  /* walls */
  for (size_t k = 0; k < d->n_walls; ++k) {
    TlWall *W = d->walls[k];
    snprintf(sub, sizeof sub, "%s/wall_%zu", group ? group : "", k);
    char *type = NULL;
    TL_CHECK(tl_checkpoint_read_string(r, sub, "type", &type));
    int same = strcmp(type, W->ops->header.name) == 0;
    tl_free(&type);
    if (!same) TL_ERROR(TL_ERR_ARG, "%s: wall %zu was saved as another type than '%s'", path, k, W->ops->header.name);
    if (!W->ops->checkpoint_load) TL_ERROR(TL_ERR_STATE, "wall '%s' (%s) has no checkpoint hooks", W->name, W->ops->header.name);
    double acc[9];
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "accounting", 9, acc));
    W->elastic_energy = acc[0];
    W->contact_work = acc[1];
    W->work = acc[2];
    W->force = tl_v3(acc[3], acc[4], acc[5]);
    W->torque = tl_v3(acc[6], acc[7], acc[8]);
    TL_CHECK(tl_checkpoint_check_finite(r, sub, "accounting", 9, acc));
    TL_CHECK(tl_checkpoint_read_int64(r, sub, "n_contacts", &v));
    TL_CHECK(tl_checkpoint_check_count(r, sub, "n_contacts", v, 0, INT64_MAX));
    W->n_contacts = (size_t)v;
    size_t bytes = 0;
    TL_CHECK(tl_checkpoint_length(r, sub, "state", &bytes));
    void *buffer = NULL;
    TL_CHECK(tl_calloc(&buffer, bytes ? bytes : 1, 1));
    TlStatus s = tl_checkpoint_read_bytes(r, sub, "state", bytes, buffer);
    if (s == TL_OK) s = W->ops->checkpoint_load(W, buffer, bytes);
    tl_free(&buffer);
    TL_CHECK(s);
  }
  return TL_OK;
}

const TlCheckpointOps tl_dem_checkpoint_ops = {
    .header = {"checkpoint", "dem_v1",
               "DEM world: particles, contact list with histories, neighbour-list build state, domain, clocks, "
               "energy accumulators, prescribed motions and walls"},
    .save = dem_save,
    .load = dem_load,
};
