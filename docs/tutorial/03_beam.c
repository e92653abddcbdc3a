/* Tutorial 3: a beam under its own weight.  A steel cantilever, 2 m long
 * with a 0.1 m square section, clamped at y = 0, meshed with 27-node
 * hexahedra and solved quasi-statically under gravity.  Checks: the
 * deflection along the beam against beam theory (Euler-Bernoulli for a
 * uniform load, plus Timoshenko's shear term), and the clamp's reaction
 * against the weight.  Output: beam.xmf (ParaView: Warp By Vector with
 * "displacement"), deflection.csv (FEM and theory along the beam). */
#include "talus.h"

static TlStatus run(const char *dir, double *tip_ratio, double *worst, double *reaction_ratio)
{
  const double L = 2.0, b = 0.1, E = 2e11, rho = 7850, g = 9.81; /* m, m, Pa, kg/m^3, m/s^2 */
  TlMesh *mesh;
  TlMaterial *steel;
  TlSolid *beam;
  TL_CHECK(tl_mesh_create_box(&tl_element_hex27, (size_t[]){2, 20, 2}, (double[]){-b / 2, 0, -b / 2}, (double[]){b / 2, L, b / 2}, &mesh));
  TL_CHECK(tl_material_create_hooke(E, 0.0, rho, &steel)); /* Poisson's ratio 0: beam theory's section */
  TL_CHECK(tl_api_solid_create(mesh, steel, "ymin", &beam)); /* x, y and z of the end y = 0 clamped */
  TL_CHECK(tl_solid_add_gravity(beam, tl_v3(0, 0, -g)));
  TL_CHECK(tl_solid_setup(beam));
  TlStepper *st; /* the default options (NULL): docs/catalogue.md lists them */
  TL_CHECK(tl_stepper_create("quasi_static", tl_solid_system(beam), NULL, &st));
  TL_CHECK(tl_stepper_set_state(st, 0.0, NULL, NULL));
  TL_CHECK(tl_stepper_step(st, 1.0));

  TlSolidOutput *out;
  TL_CHECK(tl_solid_output_create(beam, dir, "beam", &out));
  TL_CHECK(tl_solid_output_write(out, 1, 1.0, st->u, NULL));
  tl_solid_output_destroy(&out);
  /* beam theory: w(y) = q y^2 (6 L^2 - 4 L y + y^2) / (24 E I) + q (L y - y^2 / 2) / (kappa G A) */
  const double q = rho * g * b * b, I = b * b * b * b / 12, kGA = 5.0 / 6.0 * E / 2 * b * b;
  const TlColumn cols[] = {{"y", "m"}, {"w_fem", "m"}, {"w_theory", "m"}};
  TlTimeSeries *ts;
  TL_CHECK(tl_api_timeseries_create(dir, "deflection", 3, cols, &ts));
  double w_tip = 0, w_tip_theory = 0;
  *worst = 0;
  for (size_t a = 0; a < mesh->n_nodes; ++a) { /* the nodes on the beam's axis */
    const double *X = mesh->x + 3 * a, y = X[1];
    if (fabs(X[0]) > 1e-12 || fabs(X[2]) > 1e-12) continue;
    TlSparseIndex d = tl_solid_dof(beam, a, 2);
    double w = d >= 0 ? -st->u[d] : 0.0;
    double w_t = q * y * y * (6 * L * L - 4 * L * y + y * y) / (24 * E * I) + q * (L * y - y * y / 2) / kGA;
    double row[3] = {y, w, w_t};
    TL_CHECK(tl_timeseries_append(ts, row));
    if (y > 0.25 * L) *worst = fmax(*worst, fabs(w / w_t - 1));
    if (fabs(y - L) < 1e-12) w_tip = w, w_tip_theory = w_t;
  }
  TL_CHECK(tl_timeseries_close(&ts));
  double *R = calloc(3 * mesh->n_nodes, sizeof *R), Rz = 0;
  TL_CHECK(tl_solid_reactions(beam, 1.0, st->u, NULL, R));
  for (size_t a = 0; a < mesh->n_nodes; ++a) Rz += R[3 * a + 2];
  free(R);
  *tip_ratio = w_tip / w_tip_theory;
  *reaction_ratio = Rz / (q * L);
  tl_stepper_destroy(&st);
  tl_solid_destroy(&beam);
  tl_material_destroy(&steel);
  tl_mesh_destroy(&mesh);
  return TL_OK;
}

int main(int argc, char **argv)
{
  double tip = NAN, worst = NAN, reaction = NAN; /* set by run */
  if (tl_initialize() || run(argc > 1 ? argv[1] : "out_beam", &tip, &worst, &reaction)) {
    fprintf(stderr, "error: %s\n", tl_error_message());
    return 1;
  }
  printf("tip deflection %.5f of beam theory's; worst ratio along the outer 3/4: 1 %+.2e; reaction %.8f of the weight\n",
         tip, worst, reaction);
  int ok = fabs(tip - 1) <= 0.002 && worst <= 0.005 && fabs(reaction - 1) <= 1e-8;
  printf("summary: tip_ratio=%.6g worst_deviation=%.3g reaction_ratio=%.10g status=%s\n", tip, worst, reaction,
         ok ? "ok" : "failed");
  return ok ? 0 : 1;
}
