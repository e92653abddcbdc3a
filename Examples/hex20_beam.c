/* The 20-node serendipity hexahedron (element_hex20.c), registered from
 * outside the library and used by name:
 *   - patch test: on a distorted mesh a uniform strain (u = A X) leaves the
 *     interior nodes in equilibrium and gives the exact stress at every
 *     Gauss point;
 *   - rigid rotation: zero stress and zero internal force;
 *   - the S1 cantilever (0.8 x 0.8 x 12 m, clamped at y = 0, tip traction
 *     in -z) solved quasi-statically, against Timoshenko and against the
 *     built-in hex27 on the same mesh, written to XDMF (Hexahedron_20) and
 *     read back (VTK node order);
 *   - a Gmsh file with one element of type 17 read back as hex20.
 * Prints `summary:` and exits non-zero when a check fails. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "examples.h"
#include "tl_element.h"
#include "tl_material.h"
#include "tl_mesh.h"
#include "tl_mesh_snapshot.h"
#include "tl_solid.h"
#include "tl_solid_output.h"
#include "tl_stepper.h"

typedef struct {
  const char *elements, *reference, *output_dir;
  long nx, ny;
  double E, nu, load;
} Params;

/* Marks the nodes on boundary faces. */
static TlStatus boundary_nodes(const TlMesh *mesh, char **on)
{
  TL_CHECK(tl_calloc(on, mesh->n_nodes, 1));
  for (size_t f = 0; f < mesh->n_boundary; ++f) {
    size_t nodes[TL_ELEMENT_MAX_FACE_NODES];
    tl_mesh_face_nodes(mesh, mesh->boundary[f], nodes, NULL);
    const TlElementType *t = mesh->blocks[mesh->boundary[f].block].type;
    for (int k = 0; k < t->face_n_nodes; ++k) (*on)[nodes[k]] = 1;
  }
  return TL_OK;
}

/* u = H X at every node of a distorted unit cube of 2 x 2 x 2 elements:
 * the largest nodal force at interior nodes and at all nodes, the largest
 * Gauss-point stress error and the largest exact stress component. */
typedef struct {
  double f_interior, f_all, stress_error, stress_scale;
} Uniform;

static TlStatus uniform_gradient(const TlElementType *type, TlMat3 H, Uniform *r)
{
  const size_t n[3] = {2, 2, 2};
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  double *u = NULL, *f = NULL, *state = NULL;
  char *on = NULL;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_mesh_create_box(type, n, lo, hi, &mesh), done);
  TL_CHECK_GOTO(s, boundary_nodes(mesh, &on), done);
  /* Interior nodes moved by up to 0.06: curved element edges, still exact
   * for a linear field (isoparametric elements interpolate X exactly). */
  srand(3);
  for (size_t a = 0; a < mesh->n_nodes; ++a)
    for (int i = 0; i < 3 && !on[a]; ++i) mesh->x[3 * a + i] += 0.06 * (2.0 * rand() / RAND_MAX - 1.0);
  TL_CHECK_GOTO(s, tl_material_create_hooke(1e8, 0.3, 1000.0, &mat), done);
  TL_CHECK_GOTO(s, tl_solid_create(mesh, &solid), done);
  TL_CHECK_GOTO(s, tl_solid_set_material(solid, NULL, mat), done);
  TL_CHECK_GOTO(s, tl_solid_setup(solid), done);
  TL_CHECK_GOTO(s, tl_calloc(&u, 3 * mesh->n_nodes, sizeof *u), done);
  TL_CHECK_GOTO(s, tl_calloc(&f, 3 * mesh->n_nodes, sizeof *f), done);
  for (size_t a = 0; a < mesh->n_nodes; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) u[3 * a + i] += H.m[i][j] * mesh->x[3 * a + j];
  TL_CHECK_GOTO(s, tl_solid_block_forces(solid, 0, u, f, 0.0, NULL, NULL), done);
  double f_in = 0.0, f_all = 0.0;
  for (size_t a = 0; a < mesh->n_nodes; ++a)
    for (int i = 0; i < 3; ++i) {
      f_all = fmax(f_all, fabs(f[3 * a + i]));
      if (!on[a]) f_in = fmax(f_in, fabs(f[3 * a + i]));
    }
  r->f_interior = f_in;
  r->f_all = f_all;
  /* The exact stress of the uniform deformation gradient ("hooke" keeps a
   * work account per point: state from zero). */
  TlMat3 F = tl_m3_add(tl_m3_identity(), H), S_exact;
  TL_CHECK_GOTO(s, tl_calloc(&state, 2 * mat->state_size + 1, sizeof *state), done);
  TL_CHECK_GOTO(s, tl_material_evaluate(mat, 1, &F, state, state + mat->state_size, &S_exact, NULL, NULL), done);
  int nq = 0, nq_mass = 0;
  TL_CHECK_GOTO(s, tl_solid_weight_points(solid, 0, &nq, &nq_mass), done);
  double err = 0.0, scale = 0.0;
  for (size_t e = 0; e < mesh->blocks[0].n_elements; ++e)
    for (int q = 0; q < nq; ++q) {
      TlMat3 Fq, Sq;
      TL_CHECK_GOTO(s, tl_solid_gauss_stress(solid, 0, e, q, u, &Fq, &Sq), done);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          err = fmax(err, fabs(Sq.m[i][j] - S_exact.m[i][j]));
          scale = fmax(scale, fabs(S_exact.m[i][j]));
        }
    }
  r->stress_error = err;
  r->stress_scale = scale;
done:
  tl_free(&u);
  tl_free(&f);
  tl_free(&state);
  tl_free(&on);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
  return s;
}

/* Mean of u_z over the face set "ymax" (the consistent tip deflection). */
static TlStatus tip_deflection(const TlMesh *mesh, const double *u_nodes, double *w)
{
  const TlFaceSet *tip = NULL;
  TL_CHECK(tl_mesh_find_face_set(mesh, "ymax", &tip));
  double uz = 0.0, area = 0.0;
  for (size_t k = 0; k < tip->n; ++k) {
    const TlElementType *ft = mesh->blocks[tip->faces[k].block].type->face_type;
    size_t nodes[TL_ELEMENT_MAX_FACE_NODES];
    double x[TL_ELEMENT_MAX_FACE_NODES * 3], N[TL_ELEMENT_MAX_FACE_NODES];
    tl_mesh_face_nodes(mesh, tip->faces[k], nodes, x);
    TlQuadrature q;
    TL_CHECK(tl_element_quadrature(ft, 3, &q));
    for (int p = 0; p < q.n; ++p) {
      double n_dA[3];
      tl_element_face_normal(ft, 3, x, q.xi[p], n_dA);
      double dA = q.w[p] * sqrt(n_dA[0] * n_dA[0] + n_dA[1] * n_dA[1] + n_dA[2] * n_dA[2]);
      ft->eval(1, q.xi[p], N, NULL);
      for (int a = 0; a < ft->n_nodes; ++a) uz += dA * N[a] * u_nodes[3 * nodes[a] + 2];
      area += dA;
    }
  }
  *w = -uz / area;
  return TL_OK;
}

/* Reads a snapshot back: the largest distance of a VTK mid-edge node
 * (positions 8..19 of a Hexahedron_20 or _27 cell) from the midpoint of its
 * edge, over all cells. */
static TlStatus vtk_edge_error(const char *path, double *err)
{
  static const int edge[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                  {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  TlMeshSnapshot snap;
  TL_CHECK(tl_mesh_snapshot_read(path, &snap));
  *err = 0.0;
  for (size_t b = 0; b < snap.n_blocks; ++b) {
    const TlMeshSnapshotBlock *blk = &snap.blocks[b];
    int nn = tl_cell_type_nodes(blk->type);
    for (size_t e = 0; e < blk->n_cells && nn >= 20; ++e) {
      const int *c = blk->connectivity + e * (size_t)nn;
      for (int k = 0; k < 12; ++k) {
        TlVec3 mid = tl_v3_scale(tl_v3_add(snap.reference[c[edge[k][0]]], snap.reference[c[edge[k][1]]]), 0.5);
        *err = fmax(*err, tl_v3_norm(tl_v3_sub(snap.reference[c[8 + k]], mid)));
      }
    }
  }
  tl_mesh_snapshot_free(&snap);
  return TL_OK;
}

/* The S1 beam of element type `name` under a tip traction; writes
 * <dir>/beam_<name>.xmf when dir is given, and checks its VTK node order
 * (*order_err). */
static TlStatus cantilever(const Params *p, const char *name, const char *dir, double *w, size_t *n_nodes,
                           double *order_err)
{
  const TlElementType *type = NULL;
  TL_CHECK(tl_element_type_find(name, &type));
  const double b = 0.8, h = 0.8, L = 12.0;
  const size_t n[3] = {(size_t)p->nx, (size_t)p->ny, (size_t)p->nx};
  const double lo[3] = {-0.5 * b, 0.0, -0.5 * h}, hi[3] = {0.5 * b, L, 0.5 * h};
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  TlStepper *st = NULL;
  TlSolidOutput *out = NULL;
  double *u_nodes = NULL;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_mesh_create_box(type, n, lo, hi, &mesh), done);
  TL_CHECK_GOTO(s, tl_material_create_hooke(p->E, p->nu, 1309.0, &mat), done);
  TL_CHECK_GOTO(s, tl_solid_create(mesh, &solid), done);
  TL_CHECK_GOTO(s, tl_solid_set_material(solid, NULL, mat), done);
  TL_CHECK_GOTO(s, tl_solid_fix(solid, "ymin", 7), done);
  TL_CHECK_GOTO(s, tl_solid_add_traction(solid, "ymax", tl_v3(0.0, 0.0, -p->load / (b * h)), NULL, NULL), done);
  TL_CHECK_GOTO(s, tl_solid_setup(solid), done);
  TL_CHECK_GOTO(s, tl_stepper_create("quasi_static", tl_solid_system(solid), NULL, &st), done);
  TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), done);
  TL_CHECK_GOTO(s, tl_stepper_step(st, 1.0), done);
  TL_CHECK_GOTO(s, tl_calloc(&u_nodes, 3 * mesh->n_nodes, sizeof *u_nodes), done);
  tl_solid_dofs_to_nodes(solid, st->u, u_nodes);
  TL_CHECK_GOTO(s, tip_deflection(mesh, u_nodes, w), done);
  *n_nodes = mesh->n_nodes;
  if (dir) {
    char base[128];
    snprintf(base, sizeof base, "beam_%s", name);
    TL_CHECK_GOTO(s, tl_solid_output_create(solid, dir, base, &out), done);
    TL_CHECK_GOTO(s, tl_solid_output_write(out, 0, 1.0, st->u, NULL), done);
    TL_CHECK_GOTO(s, vtk_edge_error(tl_solid_output_last_path(out), order_err), done);
  }
done:
  tl_solid_output_destroy(&out);
  tl_free(&u_nodes);
  tl_stepper_destroy(&st);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
  return s;
}

/* Writes one element of `type` (its reference element mapped onto the unit
 * cube) as a Gmsh 4.1 file with the physical volume "solid", and reads it
 * back: the reader finds the type by its Gmsh code through the registry.
 * *ok: one element of this very type, of volume 1. */
static TlStatus gmsh_round_trip(const TlElementType *type, const char *dir, int *ok)
{
  char path[4200];
  snprintf(path, sizeof path, "%s/one_%s.msh", dir, type->header.name);
  FILE *f = fopen(path, "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write '%s'", path);
  int nn = type->n_nodes;
  fprintf(f, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"solid\"\n$EndPhysicalNames\n");
  fprintf(f, "$Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 1 0\n$EndEntities\n");
  fprintf(f, "$Nodes\n1 %d 1 %d\n3 1 0 %d\n", nn, nn, nn);
  for (int a = 0; a < nn; ++a) fprintf(f, "%d\n", a + 1);
  for (int a = 0; a < nn; ++a)
    fprintf(f, "%.17g %.17g %.17g\n", 0.5 * (1 + type->ref_coords[3 * a]), 0.5 * (1 + type->ref_coords[3 * a + 1]),
            0.5 * (1 + type->ref_coords[3 * a + 2]));
  fprintf(f, "$EndNodes\n$Elements\n1 1 1 1\n3 1 %d 1\n1", type->gmsh_type);
  for (int a = 0; a < nn; ++a) fprintf(f, " %d", a + 1);
  fprintf(f, "\n$EndElements\n");
  fclose(f);
  TlMesh *mesh = NULL;
  TL_CHECK(tl_mesh_read_gmsh(path, &mesh));
  *ok = mesh->n_blocks == 1 && mesh->blocks[0].type == type && mesh->blocks[0].n_elements == 1 &&
        fabs(tl_mesh_volume(mesh) - 1.0) < 1e-14;
  tl_mesh_destroy(&mesh);
  return TL_OK;
}

/* Whether the file at path contains text. */
static int file_contains(const char *path, const char *text)
{
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  char buf[1 << 16];
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  fclose(f);
  buf[n] = '\0';
  return strstr(buf, text) != NULL;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o = NULL;
  Params p;
  char *dir = NULL;
  TL_CHECK(tl_initialize());
  TL_CHECK(example_hex20_register());
  TL_CHECK(tl_options_create(argc, argv,
                             "A 20-node serendipity hexahedron defined outside the library: patch test, rigid "
                             "rotation, the S1 cantilever against Timoshenko and hex27, XDMF output.",
                             &o));
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-elements", "hex20", "element type under test (by name)", &p.elements), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-reference", "hex27", "element type of the reference beam", &p.reference), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nx", 2, 1, 20, "cells across the beam (x and z)", &p.nx), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-ny", 20, 1, 400, "cells along the beam", &p.ny), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-E", 1e8, 1.0, 1e13, "Pa", "Young's modulus", &p.E), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-nu", 0.0, 0.0, 0.49, "", "Poisson's ratio", &p.nu), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-load", 1644.0, 0.0, 1e7, "N", "tip load", &p.load), done);
  TL_CHECK_GOTO(s, tl_output_dir(o, &dir), done);
  if ((s = tl_options_finish(o, stdout)) != TL_OK) goto done;
  double t0 = tl_wtime();
  const TlElementType *type = NULL;
  TL_CHECK_GOTO(s, tl_element_type_find(p.elements, &type), done);

  /* Patch test on a distorted mesh, and a rigid rotation (0.7 rad about (1, 2, 3)). */
  TlMat3 A = {{{0.01, 0.002, -0.003}, {0.001, -0.004, 0.002}, {0.0025, 0.0, 0.006}}};
  Uniform patch, rot;
  TL_CHECK_GOTO(s, uniform_gradient(type, A, &patch), done);
  double patch_force = patch.f_interior / patch.f_all, patch_stress = patch.stress_error / patch.stress_scale;
  double ax[3] = {1, 2, 3}, an = sqrt(14.0), th = 0.7, c = cos(th), sn = sin(th);
  TlMat3 R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double k = (i == j) * c + (1 - c) * ax[i] * ax[j] / (an * an);
      int e = 3 - i - j; /* the third index when i != j */
      if (i != j) k += ((j == (i + 1) % 3) ? -1.0 : 1.0) * sn * ax[e] / an;
      R.m[i][j] = k - (i == j);
    }
  TL_CHECK_GOTO(s, uniform_gradient(type, R, &rot), done);
  /* The exact stress and force are zero: relative to E and to E times the
   * area of an element face. */
  double rot_rel = (rot.stress_error + rot.stress_scale) / 1e8, rot_force = rot.f_all / (1e8 * 0.25);

  /* The cantilever: the type under test and the reference type by name. */
  const double b = 0.8, h = 0.8, L = 12.0, I = b * h * h * h / 12.0, G = p.E / (2.0 * (1.0 + p.nu));
  const double kappa = 10.0 * (1.0 + p.nu) / (12.0 + 11.0 * p.nu);
  const double w_timo = p.load * L * L * L / (3.0 * p.E * I) + p.load * L / (kappa * G * b * h);
  double w = 0, w_ref = 0;
  size_t nodes = 0, nodes_ref = 0;
  double order_err = 1.0;
  TL_CHECK_GOTO(s, cantilever(&p, p.elements, dir, &w, &nodes, &order_err), done);
  TL_CHECK_GOTO(s, cantilever(&p, p.reference, NULL, &w_ref, &nodes_ref, NULL), done);
  double err_timo = (w - w_timo) / w_timo, err_ref = (w - w_ref) / w_ref;
  int gmsh_ok = 0;
  TL_CHECK_GOTO(s, gmsh_round_trip(type, dir, &gmsh_ok), done);
  char xmf[4200];
  snprintf(xmf, sizeof xmf, "%s/beam_%s.xmf", dir, p.elements);
  int xdmf_ok = file_contains(xmf, tl_cell_type_xdmf(type->output ? type->output->cell : TL_CELL_HEX8));

  printf("patch test (%s, distorted 2x2x2): interior force / boundary force %.2e, stress error %.2e of %.3g Pa\n",
         p.elements, patch_force, patch_stress, patch.stress_scale);
  printf("rigid rotation: |f| / (E h^2) %.2e, |S| / E %.2e\n", rot_force, rot_rel);
  printf("cantilever %ldx%ldx%ld: %s tip %.6f m (%zu nodes), %s %.6f m (%zu nodes), Timoshenko %.6f m\n", p.nx,
         p.ny, p.nx, p.elements, w, nodes, p.reference, w_ref, nodes_ref, w_timo);
  printf("  error vs Timoshenko %+.3f %%, vs %s %+.3f %%; XDMF %s (%s), VTK mid-edge nodes off their edges by %.1e m\n",
         100 * err_timo, p.reference, 100 * err_ref, xmf, xdmf_ok ? tl_cell_type_xdmf(type->output->cell) : "topology missing",
         order_err);
  printf("Gmsh file with one element of code %d read back as %s: %s\n", type->gmsh_type, p.elements,
         gmsh_ok ? "yes" : "NO");
  int ok = patch_force < 1e-10 && patch_stress < 1e-10 && rot_rel < 1e-12 && rot_force < 1e-12 && fabs(err_timo) < 0.01 &&
           fabs(err_ref) < 0.005 && xdmf_ok && order_err < 1e-12 && gmsh_ok;
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_string(&sum, "elements", p.elements);
  tl_summary_real(&sum, "patch_force", patch_force);
  tl_summary_real(&sum, "patch_stress", patch_stress);
  tl_summary_real(&sum, "rotation_stress", rot_rel);
  tl_summary_real(&sum, "rotation_force", rot_force);
  tl_summary_real(&sum, "tip", w);
  tl_summary_real(&sum, "err_timoshenko", err_timo);
  tl_summary_real(&sum, "err_reference", err_ref);
  tl_summary_int(&sum, "xdmf", xdmf_ok);
  tl_summary_real(&sum, "vtk_order", order_err);
  tl_summary_int(&sum, "gmsh", gmsh_ok);
  tl_summary_string(&sum, "check", ok ? "pass" : "fail");
  tl_summary_real(&sum, "wall", tl_wtime() - t0);
  s = tl_summary_print(&sum, stdout);
  if (!ok) s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__, "hex20 example: a check failed (see above)");
done:
  tl_free(&dir);
  tl_options_destroy(&o);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
