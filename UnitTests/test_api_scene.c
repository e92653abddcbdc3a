/* The scene conveniences of tl_api.h: what each builds, and that each
 * refusal names the offending value and leaves nothing half-built (the
 * tutorials run the successful paths end to end). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_test.h"

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);

  /* a law with its settings; a refused setting adds nothing */
  const TlSetting bad[] = {{"k_n", 1e4}, {"no_such", 1}};
  TL_TEST_STATUS(tl_api_dem_add_law(dem, "linear", "coulomb", NULL, NULL, 2, bad, NULL), TL_ERR_NOT_FOUND);
  TL_TEST_ASSERT(strstr(tl_error_message(), "no_such") != NULL, "names the setting: %s", tl_error_message());
  TL_TEST_ASSERT(tl_dem_n_laws(dem) == 0, "no law added (%d)", tl_dem_n_laws(dem));
  const TlSetting good[] = {{"k_n", 1e4}, {"mu", 0.3}};
  int index = -1;
  TL_TEST_STATUS(tl_api_dem_add_law(dem, "linear", "coulomb", NULL, NULL, 2, good, &index), TL_OK);
  double mu = 0;
  TL_TEST_STATUS(tl_contact_law_get(tl_dem_law(dem, 0), "mu", &mu), TL_OK);
  TL_TEST_ASSERT(index == 0 && mu == 0.3, "law 0 with mu 0.3 (%d, %g)", index, mu);

  /* box walls: the named faces, facing inwards; an unknown face refused */
  TL_TEST_STATUS(tl_api_dem_set_box_walls(dem, tl_v3(0, 0, 0), tl_v3(1, 2, 3), "xmax, zmin", 0), TL_OK);
  TL_TEST_ASSERT(tl_dem_n_walls(dem) == 2, "two walls (%zu)", tl_dem_n_walls(dem));
  const TlDomain *box = tl_dem_domain(dem);
  TL_TEST_ASSERT(box->h.m[0][0] == 1 && box->h.m[1][1] == 2 && box->h.m[2][2] == 3, "the box set");
  TL_TEST_STATUS(tl_api_dem_set_box_walls(dem, tl_v3(0, 0, 0), tl_v3(1, 2, 3), "ymin zfoo", 0), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "'zfoo'") != NULL, "names the face: %s", tl_error_message());
  TL_TEST_STATUS(tl_api_dem_set_box_walls(dem, tl_v3(0, 0, 0), tl_v3(1, 2, 3), "xmin", 5), TL_ERR_ARG);
  /* a grain pressed against xmax is pushed back (-x): the plane faces the inside */
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(tl_dem_particles(dem), "g", 2500, 0.05, 0.05, &sp), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.96, 1, 1.5), tl_v3(0, 0, 0), 0.05, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 1e-5, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TL_TEST_STATUS(tl_dem_compute_forces(dem), TL_OK);
  const TlParticles *P = tl_dem_particles(dem);
  TL_TEST_ASSERT(P->f[0].x < 0 && tl_dem_wall(dem, 0)->force.x > 0, "pushed inwards (%g)", P->f[0].x);

  /* a solid: an unknown clamped set refused, nothing returned */
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, (size_t[]){1, 1, 1}, (double[]){0, 0, 0}, (double[]){1, 1, 1},
                                    &mesh), TL_OK);
  TL_TEST_STATUS(tl_material_create_hooke(1e6, 0.3, 1000, &mat), TL_OK);
  TL_TEST_ASSERT(tl_api_solid_create(mesh, mat, "no_such_set", &solid) != TL_OK && solid == NULL,
                 "unknown set refused: %s", tl_error_message());
  TL_TEST_ASSERT(strstr(tl_error_message(), "no_such_set") != NULL, "names the set: %s", tl_error_message());

  /* writers: what they need */
  TlSceneWriter *w = NULL;
  TL_TEST_STATUS(tl_api_scene_writer_create(".", NULL, NULL, NULL, NULL, &w), TL_ERR_ARG);
  TL_TEST_STATUS(tl_api_solid_create(mesh, mat, "zmin", &solid), TL_OK);
  TL_TEST_STATUS(tl_api_scene_writer_create(".", NULL, solid, NULL, "s", &w), TL_ERR_ARG);
  TL_TEST_ASSERT(w == NULL, "nothing returned");
  char dir[5000];
  memset(dir, 'd', sizeof dir - 1);
  dir[sizeof dir - 1] = '\0';
  TlTimeSeries *ts = NULL;
  const TlColumn cols[] = {{"t", "s"}};
  TL_TEST_STATUS(tl_api_timeseries_create(dir, "t", 1, cols, &ts), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "of 5001 characters") && strstr(tl_error_message(), "limit 4095"), "names the limit: %s", tl_error_message());

  /* parameter tables by name */
  int n = -1;
  TL_TEST_STATUS(tl_api_type_param("stepper", "newmark", -1, &n, NULL, NULL, NULL, NULL, NULL, NULL), TL_OK);
  const char *name = NULL, *unit = NULL;
  double def = 0;
  TL_TEST_STATUS(tl_api_type_param("stepper", "newmark", 0, NULL, &name, &def, NULL, NULL, &unit, NULL), TL_OK);
  TL_TEST_ASSERT(n == 11 && !strcmp(name, "beta") && def == 0.25 && !strcmp(unit, "1"), "newmark: %d, %s", n, name);
  TL_TEST_STATUS(tl_api_type_param("stepper", "newmark", n, NULL, NULL, NULL, NULL, NULL, NULL, NULL), TL_ERR_ARG);
  TL_TEST_STATUS(tl_api_type_param("cg_kernel", "lucy", 0, NULL, &name, &def, NULL, NULL, &unit, NULL), TL_OK);
  TL_TEST_ASSERT(!strcmp(name, "width") && isnan(def) && !strcmp(unit, "m"), "lucy width in m, no default");

  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
  tl_dem_destroy(&dem);
  return tl_test_report();
}
