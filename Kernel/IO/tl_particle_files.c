#include "tl_particle_files.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_lammps_data.h"
#include "tl_log.h"
#include "tl_particle_snapshot.h"

/* The species of particle i: the given one, or the file's (0-based). */
static TlStatus tl_pf_species(const TlParticles *P, const char *path, size_t i, int given, long from_file,
                              const char *what, int *species)
{
  long s = given >= 0 ? given : from_file;
  if (s < 0 || (size_t)s >= P->n_species)
    TL_ERROR(TL_ERR_ARG, "'%s', particle %zu: %s %ld is not a species of the world (it has %zu; add species, or "
             "give one species for every particle)", path, i + 1, what, given >= 0 ? (long)given : from_file,
             P->n_species);
  *species = (int)s;
  return TL_OK;
}

static TlStatus tl_pf_lammps(TlDem *dem, const char *path, int species, size_t *n_added)
{
  TlLammpsData *d = NULL;
  TL_CHECK(tl_lammps_data_read(path, &d));
  TlParticles *P = tl_dem_particles(dem);
  TlStatus s = TL_OK;
  size_t density_off = 0, spinning = 0;
  for (size_t i = 0; i < d->n && s == TL_OK; ++i) {
    int sp = 0;
    s = tl_pf_species(P, path, i, species, (long)d->type[i] - 1, species >= 0 ? "species" : "atom type - 1", &sp);
    if (s != TL_OK) break;
    double rho = P->species_table[sp].density;
    if (!(fabs(d->density[i] - rho) <= 1e-9 * rho)) density_off++;
    if (d->omega[i].x != 0.0 || d->omega[i].y != 0.0 || d->omega[i].z != 0.0) spinning++;
    s = tl_dem_add_particle(dem, d->x[i], d->v[i], 0.5 * d->diameter[i], sp, NULL);
    if (s == TL_OK) ++*n_added;
  }
  if (s == TL_OK && density_off)
    tl_warn("'%s': %zu of %zu atoms have a density other than their species' (the species' density gives the mass)",
            path, density_off, d->n);
  if (s == TL_OK && spinning)
    tl_warn("'%s': the spins of %zu atoms are not applied (particles start without rotation)", path, spinning);
  tl_lammps_data_destroy(&d);
  return s;
}

static TlStatus tl_pf_snapshot(TlDem *dem, const char *path, int species, size_t *n_added)
{
  TlParticleSnapshot snap;
  TL_CHECK(tl_particle_snapshot_read(path, &snap));
  TlParticles *P = tl_dem_particles(dem);
  TlStatus s = TL_OK;
  if (species < 0 && !snap.species)
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                     "'%s' stores no species: give the species of its particles", path);
  size_t spinning = 0;
  for (size_t i = 0; i < snap.n && s == TL_OK; ++i) {
    int sp = 0;
    s = tl_pf_species(P, path, i, species, snap.species ? snap.species[i] : -1, "species", &sp);
    if (s != TL_OK) break;
    if (snap.angular_velocity) {
      TlVec3 w = snap.angular_velocity[i];
      if (w.x != 0.0 || w.y != 0.0 || w.z != 0.0) spinning++;
    }
    TlVec3 v = snap.velocity ? snap.velocity[i] : tl_v3(0, 0, 0);
    s = tl_dem_add_particle(dem, snap.position[i], v, snap.radius[i], sp, NULL);
    if (s == TL_OK) ++*n_added;
  }
  if (s == TL_OK && spinning)
    tl_warn("'%s': the spins of %zu particles are not applied (particles start without rotation)", path, spinning);
  tl_particle_snapshot_free(&snap);
  return s;
}

TlStatus tl_dem_add_particles_from_file(TlDem *dem, const char *path, int species, size_t *n_added)
{
  size_t added = 0;
  if (n_added) *n_added = 0;
  if (!dem || !path) TL_ERROR(TL_ERR_ARG, "tl_dem_add_particles_from_file: NULL %s", dem ? "path" : "world");
  FILE *f = fopen(path, "rb");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot open particle file '%s': %s", path, strerror(errno));
  unsigned char head[8] = {0};
  size_t got = fread(head, 1, sizeof head, f);
  fclose(f);
  static const unsigned char hdf5[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  TlStatus s = got == 8 && memcmp(head, hdf5, 8) == 0 ? tl_pf_snapshot(dem, path, species, &added)
                                                        : tl_pf_lammps(dem, path, species, &added);
  if (n_added) *n_added = added;
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  return TL_OK;
}
