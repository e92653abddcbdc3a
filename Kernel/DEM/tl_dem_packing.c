/* Packing files (snapshot + cell) and the gouge law spec; see tl_dem_packing.h. */
#include "tl_dem_packing.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_hdf5_util.h"
#include "tl_memory.h"

static const TlContactValue gouge_values[] = {
    {"k_n", 36630036630.03663}, {"gamma_n", 0.2}, {"k_t", 45248868778.28054}, {"mu", 0.5}, {"dampflag", 1.0}};
const TlContactSpec tl_gouge_law_spec = {"lammps_hertz", "lammps_history", NULL, NULL, gouge_values, 5};
const TlContactSpec tl_gouge_law_frictionless_spec = {"lammps_hertz", NULL, NULL, NULL, gouge_values, 2};

static TlStatus fully_periodic(const TlDomain *D, const char *what)
{
  if (!(D->periodic[0] && D->periodic[1] && D->periodic[2]))
    TL_ERROR(TL_ERR_ARG, "%s: the domain is periodic along (%d, %d, %d); a packing needs a cell periodic in x, y and z",
             what, D->periodic[0], D->periodic[1], D->periodic[2]);
  return TL_OK;
}

TlStatus tl_dem_packing_write(TlDem *dem, TlParticleWriter *writer, int64_t step, const char **path)
{
  const TlDomain *D = tl_dem_domain(dem);
  TL_CHECK(fully_periodic(D, "tl_dem_packing_write"));
  TlParticles *P = tl_dem_particles(dem);
  TlParticleView view;
  tl_particle_view_of(P, &view);
  TL_CHECK(tl_particle_writer_write(writer, step, tl_dem_time(dem), &view));
  const char *file = tl_particle_writer_last_path(writer);
  /* the cell joins the committed snapshot: the reader of snapshots ignores it */
  hid_t id = H5Fopen(file, H5F_ACC_RDWR, H5P_DEFAULT);
  if (id < 0) TL_ERROR(TL_ERR_IO, "cannot reopen '%s' to add its cell", file);
  TlH5File f = {id, (char *)file, NULL, 0};
  const double o[3] = {D->origin.x, D->origin.y, D->origin.z};
  const hsize_t d3 = 3, d33[2] = {3, 3};
  TlStatus s = tl_h5_write(&f, "/cell/origin", H5T_NATIVE_DOUBLE, 1, &d3, o);
  if (s == TL_OK) s = tl_h5_write(&f, "/cell/h", H5T_NATIVE_DOUBLE, 2, d33, &D->h.m[0][0]);
  if (H5Fclose(id) < 0 && s == TL_OK) TL_ERROR(TL_ERR_IO, "cannot close '%s' after adding its cell", file);
  TL_CHECK(s);
  if (path) *path = file;
  return TL_OK;
}

TlStatus tl_dem_packing_write_lammps(TlDem *dem, double density, const char *path)
{
  const TlDomain *D = tl_dem_domain(dem);
  TL_CHECK(fully_periodic(D, "tl_dem_packing_write_lammps"));
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (a != b && D->h.m[a][b] != 0.0)
        TL_ERROR(TL_ERR_UNSUPPORTED, "tl_dem_packing_write_lammps: the cell is not orthogonal (h[%d][%d] = %g); only a "
                 "diagonal h is written", a, b, D->h.m[a][b]);
  if (!(density > 0.0)) TL_ERROR(TL_ERR_ARG, "tl_dem_packing_write_lammps: density %g must be positive", density);
  TlParticles *P = tl_dem_particles(dem);
  FILE *f = fopen(path, "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write '%s'", path);
  const double lo[3] = {D->origin.x, D->origin.y, D->origin.z};
  fprintf(f, "LAMMPS data file of a Talus packing (t = %.17g s)\n\n%zu atoms\n1 atom types\n\n", tl_dem_time(dem), P->n);
  const char *ax[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) fprintf(f, "%.17g %.17g %slo %shi\n", lo[k], lo[k] + D->h.m[k][k], ax[k], ax[k]);
  fprintf(f, "\nAtoms # sphere\n\n");
  for (size_t i = 0; i < P->n; ++i) {
    TlVec3 s = tl_domain_to_reduced(D, P->x[i]);
    double r[3] = {s.x - floor(s.x), s.y - floor(s.y), s.z - floor(s.z)}, x[3];
    for (int k = 0; k < 3; ++k) {
      x[k] = lo[k] + D->h.m[k][k] * r[k];
      if (!(x[k] < lo[k] + D->h.m[k][k])) x[k] = lo[k]; /* s - floor(s) rounded up to 1 */
    }
    fprintf(f, "%lld 1 %.17g %.17g %.17g %.17g %.17g\n", (long long)P->id[i] + 1, 2.0 * P->radius[i], density, x[0],
            x[1], x[2]);
  }
  fprintf(f, "\nVelocities\n\n");
  for (size_t i = 0; i < P->n; ++i) {
    const TlVec3 v = P->v[i], w = P->w ? P->w[i] : tl_v3(0, 0, 0);
    fprintf(f, "%lld %.17g %.17g %.17g %.17g %.17g %.17g\n", (long long)P->id[i] + 1, v.x, v.y, v.z, w.x, w.y, w.z);
  }
  if (fclose(f) != 0) TL_ERROR(TL_ERR_IO, "error writing '%s'", path);
  return TL_OK;
}

TlStatus tl_dem_packing_read(const char *path, TlParticleSnapshot *snapshot, TlVec3 *origin, TlMat3 *h)
{
  TL_CHECK(tl_particle_snapshot_read(path, snapshot));
  TlH5File f;
  TlStatus s = tl_h5_open(path, &f);
  if (s == TL_OK) {
    double o[3];
    const hsize_t d3 = 3, d33[2] = {3, 3};
    if (!tl_h5_exists(&f, "/cell/h") || !tl_h5_exists(&f, "/cell/origin"))
      s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                       "'%s' has no /cell/h and /cell/origin: a particle snapshot, not a packing", path);
    if (s == TL_OK) s = tl_h5_read(&f, "/cell/origin", H5T_NATIVE_DOUBLE, 1, &d3, o);
    if (s == TL_OK) s = tl_h5_read(&f, "/cell/h", H5T_NATIVE_DOUBLE, 2, d33, &h->m[0][0]);
    *origin = tl_v3(o[0], o[1], o[2]);
    tl_h5_close(&f);
  }
  if (s != TL_OK) {
    tl_particle_snapshot_free(snapshot);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
}

TlStatus tl_dem_packing_load(TlDem *dem, const char *path, double density, int *species)
{
  if (!(density > 0.0) || !isfinite(density))
    TL_ERROR(TL_ERR_ARG, "tl_dem_packing_load: density %g kg/m^3 must be positive and finite", density);
  TlParticles *P = tl_dem_particles(dem);
  if (P->n != 0) TL_ERROR(TL_ERR_STATE, "tl_dem_packing_load: the world already holds %zu particles", P->n);
  TlParticleSnapshot snap;
  TlVec3 o;
  TlMat3 h;
  TL_CHECK(tl_dem_packing_read(path, &snap, &o, &h));
  TlStatus s = TL_OK;
  TlDomain dom;
  double rmin = INFINITY, rmax = 0.0;
  for (size_t i = 0; i < snap.n; ++i) rmin = fmin(rmin, snap.radius[i]), rmax = fmax(rmax, snap.radius[i]);
  if (snap.n == 0) s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "'%s' holds no particle", path);
  if (s == TL_OK) s = tl_domain_init_cell(&dom, o, h);
  if (s == TL_OK) s = tl_dem_set_domain(dem, &dom);
  int sp = -1;
  if (s == TL_OK) s = tl_particles_add_species(P, "gouge", density, rmin, rmax, &sp);
  if (s == TL_OK) s = tl_particles_reserve(P, snap.n);
  for (size_t i = 0; i < snap.n && s == TL_OK; ++i)
    s = tl_dem_add_particle(dem, snap.position[i], snap.velocity ? snap.velocity[i] : tl_v3(0, 0, 0), snap.radius[i],
                            sp, NULL);
  if (s == TL_OK && snap.angular_velocity) {
    s = tl_particles_enable_rotation(P);
    for (size_t i = 0; i < snap.n && s == TL_OK; ++i) P->w[P->n - snap.n + i] = snap.angular_velocity[i];
  }
  tl_particle_snapshot_free(&snap);
  TL_CHECK(s);
  if (species) *species = sp;
  return TL_OK;
}
