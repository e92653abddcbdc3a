/* Particle arrays, the world's box, wall accounts and surface arrays for
 * bindings (tl_api.h). */
#include "tl_api.h"

#include <string.h>

TlStatus tl_api_particles_field(TlParticles *p, const char *name, void **data, size_t *n, int *components,
                                int *scalar)
{
  struct {
    const char *name;
    void *data;
    int components, scalar;
    const char *allocated_by;
  } fields[] = {
      {"x", p->x, 3, TL_API_FLOAT64, NULL},
      {"v", p->v, 3, TL_API_FLOAT64, NULL},
      {"f", p->f, 3, TL_API_FLOAT64, NULL},
      {"radius", p->radius, 1, TL_API_FLOAT64, NULL},
      {"mass", p->mass, 1, TL_API_FLOAT64, NULL},
      {"inv_mass", p->inv_mass, 1, TL_API_FLOAT64, NULL},
      {"species", p->species, 1, TL_API_INT32, NULL},
      {"motion", p->motion, 1, TL_API_UINT8, NULL},
      {"id", p->id, 1, TL_API_INT64, NULL},
      {"q", p->q, 4, TL_API_FLOAT64, "tl_particles_enable_rotation (or a law that needs rotation at set-up)"},
      {"w", p->w, 3, TL_API_FLOAT64, "tl_particles_enable_rotation (or a law that needs rotation at set-up)"},
      {"torque", p->torque, 3, TL_API_FLOAT64, "tl_particles_enable_rotation (or a law that needs rotation at set-up)"},
      {"inv_inertia", p->inv_inertia, 1, TL_API_FLOAT64,
       "tl_particles_enable_rotation (or a law that needs rotation at set-up)"},
      {"f_ext", p->f_ext, 3, TL_API_FLOAT64, "tl_particles_enable_external_force"},
      {"f_coupling", p->f_coupling, 3, TL_API_FLOAT64, "tl_particles_enable_coupling_force"},
      {"weight", p->weight, 1, TL_API_FLOAT64, "tl_particles_enable_weights"},
  };
  const size_t nf = sizeof fields / sizeof fields[0];
  for (size_t k = 0; k < nf; ++k) {
    if (!name || strcmp(fields[k].name, name)) continue;
    /* An empty store may hold no array yet: that is an empty field. */
    if (!fields[k].data && fields[k].allocated_by && p->n > 0)
      TL_ERROR(TL_ERR_STATE, "particle field '%s' is not allocated: it exists after %s", name, fields[k].allocated_by);
    *data = fields[k].data;
    *n = p->n;
    *components = fields[k].components;
    *scalar = fields[k].scalar;
    return TL_OK;
  }
  TL_ERROR(TL_ERR_NOT_FOUND,
           "no particle field '%s' (fields: x, v, f, radius, mass, inv_mass, species, motion, id, q, w, torque, "
           "inv_inertia, f_ext, f_coupling, weight)", name ? name : "(null)");
}

void tl_api_particles_size(const TlParticles *p, size_t *n, size_t *capacity)
{
  *n = p->n;
  *capacity = p->capacity;
}

TlStatus tl_api_dem_set_box(TlDem *dem, const double lo[3], const double hi[3], const int periodic[3])
{
  TlDomain d;
  const TlVec3 a = {lo[0], lo[1], lo[2]}, b = {hi[0], hi[1], hi[2]};
  if (periodic && (periodic[0] || periodic[1] || periodic[2])) TL_CHECK(tl_domain_init_periodic_box(&d, a, b, periodic));
  else TL_CHECK(tl_domain_init_open(&d, a, b));
  TL_CHECK(tl_dem_set_domain(dem, &d));
  return TL_OK;
}

void tl_api_wall_account(const TlWall *w, double force[3], double torque[3], size_t *n_contacts,
                         double *elastic_energy, double *work)
{
  force[0] = w->force.x, force[1] = w->force.y, force[2] = w->force.z;
  torque[0] = w->torque.x, torque[1] = w->torque.y, torque[2] = w->torque.z;
  *n_contacts = w->n_contacts;
  *elastic_energy = w->elastic_energy;
  *work = w->work;
}

const char *tl_api_wall_type(const TlWall *w) { return w->ops->header.name; }

void tl_api_trisurface_arrays(TlTriSurface *s, double **x, double **v, size_t *n_vertices, int **tri,
                              size_t *n_triangles)
{
  *x = (double *)s->x; /* TlVec3 is three doubles */
  *v = (double *)s->v;
  *n_vertices = s->n_vertices;
  *tri = s->tri;
  *n_triangles = s->n_triangles;
}

TlStatus tl_api_particle_writer_write_dem(TlParticleWriter *writer, TlDem *dem, int64_t step)
{
  TlParticles *P = tl_dem_particles(dem);
  if (step < 0) {
    TlDemStats st;
    tl_dem_stats(dem, &st);
    step = st.steps;
  }
  TlParticleView view;
  tl_particle_view_of(P, &view); /* every allocated array, ids and species */
  TL_CHECK(tl_particle_writer_write(writer, step, tl_dem_time(dem), &view));
  return TL_OK;
}

typedef struct {
  size_t max, count;
  int64_t *i, *j;
  double *force, *branch, *point;
} ContactArrays;

static void put3(double *a, size_t k, TlVec3 v)
{
  if (!a) return;
  a[3 * k] = v.x, a[3 * k + 1] = v.y, a[3 * k + 2] = v.z;
}

static void collect_contact(void *ctx, size_t i, size_t j, TlVec3 force, TlVec3 branch, TlVec3 point)
{
  ContactArrays *c = ctx;
  const size_t k = c->count++;
  if (k >= c->max) return;
  if (c->i) c->i[k] = (int64_t)i;
  if (c->j) c->j[k] = (int64_t)j;
  put3(c->force, k, force);
  put3(c->branch, k, branch);
  put3(c->point, k, point);
}

TlStatus tl_api_dem_contacts(TlDem *dem, size_t max, size_t *count, int64_t *i, int64_t *j, double *force,
                             double *branch, double *point)
{
  ContactArrays c = {max, 0, i, j, force, branch, point};
  TL_CHECK(tl_dem_visit_contacts(dem, collect_contact, &c));
  *count = c.count;
  return TL_OK;
}
