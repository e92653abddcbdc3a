/* Surface coupling: walls from FE faces and CG nodal forces (seeds/001 §5.1, §5.3.1). */
#include "tl_scoupling_private.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include "tl_memory.h"

void tl_scoupling_options_default(TlSCouplingOptions *o)
{
  o->width = 0.0;
  o->support = TL_SCOUPLING_SUPPORT_SURFACE;
  o->kernel = "lucy";
  o->subdivisions = 0;
}

static int same_face(TlFaceRef a, TlFaceRef b)
{
  return a.block == b.block && a.element == b.element && a.face == b.face;
}

static TlStatus build_topology(TlSCoupling *sc)
{
  const TlMesh *m = sc->mesh;
  size_t *map = NULL;
  TL_CHECK(tl_calloc(&map, m->n_nodes, sizeof *map));
  for (size_t i = 0; i < m->n_nodes; i++) map[i] = SIZE_MAX;
  TlStatus s = TL_OK;
  size_t fn[27];
  double fx[81];
  if ((s = tl_calloc(&sc->face_local, sc->n_faces * (size_t)sc->nf, sizeof *sc->face_local)) != TL_OK) goto done;
  if ((s = tl_calloc(&sc->node, sc->n_faces * (size_t)sc->nf, sizeof *sc->node)) != TL_OK) goto done;
  sc->n_local = 0;
  for (size_t f = 0; f < sc->n_faces; f++) {
    tl_mesh_face_nodes(m, sc->faces[f], fn, fx);
    for (int a = 0; a < sc->nf; a++) {
      if (map[fn[a]] == SIZE_MAX) {
        map[fn[a]] = sc->n_local;
        sc->node[sc->n_local++] = fn[a];
      }
      sc->face_local[f * (size_t)sc->nf + (size_t)a] = (int)map[fn[a]];
    }
  }
  /* SCoupling elements: distinct (block, element) owners of the faces. */
  if ((s = tl_calloc(&sc->elements, sc->n_faces, sizeof *sc->elements)) != TL_OK) goto done;
  if ((s = tl_calloc(&sc->active, sc->n_faces, sizeof *sc->active)) != TL_OK) goto done;
  if ((s = tl_calloc(&sc->active_index, sc->n_faces, sizeof *sc->active_index)) != TL_OK) goto done;
  if ((s = tl_calloc(&sc->face_element, sc->n_faces, sizeof *sc->face_element)) != TL_OK) goto done;
  if ((s = tl_calloc(&sc->elem_active, sc->n_faces, 1)) != TL_OK) goto done;
  if ((s = tl_calloc(&sc->elem_face_ptr, sc->n_faces + 1, sizeof *sc->elem_face_ptr)) != TL_OK) goto done;
  if ((s = tl_calloc(&sc->elem_face, sc->n_faces, sizeof *sc->elem_face)) != TL_OK) goto done;
  if ((s = tl_calloc(&sc->face_F, sc->n_faces * (size_t)sc->nf, sizeof *sc->face_F)) != TL_OK) goto done;
  if ((s = tl_calloc(&sc->face_touched, sc->n_faces, 1)) != TL_OK) goto done;
  if ((s = tl_calloc(&sc->touched_faces, sc->n_faces, sizeof *sc->touched_faces)) != TL_OK) goto done;
  for (size_t f = 0; f < sc->n_faces; f++) {
    size_t k = 0;
    for (; k < sc->n_elements; k++)
      if (sc->elements[k].block == sc->faces[f].block && sc->elements[k].element == sc->faces[f].element) break;
    if (k == sc->n_elements) {
      sc->elements[k] = sc->faces[f];
      sc->elements[k].face = -1;
      sc->n_elements++;
    }
    sc->face_element[f] = k;
  }
  for (size_t f = 0; f < sc->n_faces; f++) sc->elem_face_ptr[sc->face_element[f] + 1]++;
  for (size_t e = 0; e < sc->n_elements; e++) sc->elem_face_ptr[e + 1] += sc->elem_face_ptr[e];
  for (size_t f = 0; f < sc->n_faces; f++) sc->elem_face[sc->elem_face_ptr[sc->face_element[f]]++] = f;
  for (size_t e = sc->n_elements; e > 0; e--) sc->elem_face_ptr[e] = sc->elem_face_ptr[e - 1];
  sc->elem_face_ptr[0] = 0;
done:
  tl_free(&map);
  return s;
}

/* The SCoupling element type's load (§5.3.1): for every active SCoupling
 * element of the block its faces' share of the coupling load, an external
 * load on the element's nodes,
 *   R_a = f_int,a - f_ext,a - int_{Gamma_e} N_a t dA   (Eq. 15; Eq. 16 for c = 0).
 * Within an FE step the load is dead: the DEM forces of the step are fixed
 * before it and do not depend on the solid's trial state, so there is no
 * tangent term. */
static TlStatus scoupling_loads(void *ctx, TlSolid *solid, int b, double t, const double *u_nodes, double *f_nodes,
                                double c, TlSparse *K)
{
  (void)solid, (void)t, (void)u_nodes, (void)c, (void)K;
  const TlSCoupling *sc = ctx;
  if (!f_nodes) return TL_OK;
  for (size_t k = 0; k < sc->n_active; k++) {
    const size_t e = sc->active_index[k];
    if (sc->elements[e].block == b) sc->support->element_load(sc, e, f_nodes);
  }
  return TL_OK;
}

static const TlSolidWrapperOps scoupling_element_ops = {
    .header = {"solid_wrapper", "scoupling", "SCoupling element: the surface coupling's load on its elements"},
    .external = scoupling_loads,
};

/* The SCoupling element type over every block holding SCoupling elements. */
static TlStatus install_wrappers(TlSCoupling *sc)
{
  const int nb = sc->mesh->n_blocks;
  TL_CHECK(tl_calloc(&sc->wrappers, (size_t)nb, sizeof *sc->wrappers));
  for (int b = 0; b < nb; b++) {
    int holds = 0;
    for (size_t e = 0; e < sc->n_elements && !holds; e++) holds = sc->elements[e].block == b;
    if (!holds) continue;
    TL_CHECK(tl_solid_add_wrapper(sc->solid, b, &scoupling_element_ops, sc, &sc->wrappers[sc->n_wrappers]));
    sc->n_wrappers++;
  }
  return TL_OK;
}

static void remove_wrappers(TlSCoupling *sc)
{
  for (int k = 0; k < sc->n_wrappers; k++) tl_solid_remove_wrapper(sc->solid, &sc->wrappers[k]);
  sc->n_wrappers = 0;
  tl_free(&sc->wrappers);
}

/* The support strategies, by the value of TlSCouplingOptions.support. */
static const TlSCouplingSupportOps *const supports[] = {
    [TL_SCOUPLING_SUPPORT_SURFACE] = &tl_scoupling_support_surface,
    [TL_SCOUPLING_SUPPORT_ELEMENTS] = &tl_scoupling_support_elements,
};

TlStatus tl_scoupling_create(TlSolid *solid, size_t n_faces, const TlFaceRef *faces,
                             const TlSCouplingOptions *options, TlSCoupling **out)
{
  *out = NULL;
  if (!solid || !faces || n_faces == 0) TL_ERROR(TL_ERR_ARG, "surface coupling needs a solid and faces (got %zu faces)", n_faces);
  TlSCouplingOptions o;
  tl_scoupling_options_default(&o);
  if (options) o = *options;
  if (!(o.width >= 0.0) || !isfinite(o.width)) TL_ERROR(TL_ERR_ARG, "CG width c = %g must be finite and >= 0", o.width);
  if (o.subdivisions < 0 || o.subdivisions > 64) TL_ERROR(TL_ERR_ARG, "CG subdivisions %d outside [0, 64]", o.subdivisions);
  if (o.support < 0 || o.support >= (int)(sizeof supports / sizeof *supports))
    TL_ERROR(TL_ERR_ARG, "CG support %d is none of SURFACE (0), ELEMENTS (1)", o.support);
  const TlMesh *mesh = tl_solid_mesh(solid);
  if (mesh->dim != 3) TL_ERROR(TL_ERR_ARG, "surface coupling needs a 3-D mesh (dimension %d)", mesh->dim);
  const TlElementType *face_type = NULL;
  for (size_t f = 0; f < n_faces; f++) {
    if (faces[f].block < 0 || faces[f].block >= mesh->n_blocks) TL_ERROR(TL_ERR_ARG, "face %zu names block %d, outside [0, %d)", f, faces[f].block, mesh->n_blocks);
    const TlElementType *t = mesh->blocks[faces[f].block].type;
    if (faces[f].face < 0 || faces[f].face >= t->n_faces || faces[f].element >= mesh->blocks[faces[f].block].n_elements)
      TL_ERROR(TL_ERR_ARG, "face %zu (element %zu, face %d) out of range", f, faces[f].element, faces[f].face);
    if (!t->face_type || t->face_type->dim != 2)
      TL_ERROR(TL_ERR_UNSUPPORTED, "block '%s' (%s) has no 2-D faces to couple", mesh->blocks[faces[f].block].name, t->header.name);
    if (face_type && t->face_type != face_type)
      TL_ERROR(TL_ERR_UNSUPPORTED, "face %zu is a %s, the others %s: one face type per coupled boundary", f,
               t->face_type->header.name, face_type->header.name);
    face_type = t->face_type;
  }
  const int nf = face_type->n_nodes;
  TlSCoupling *sc;
  TL_CHECK(TL_NEW(sc));
  TlStatus s = TL_OK;
  sc->solid = solid;
  sc->mesh = mesh;
  sc->width = o.width;
  /* The Dirac limit has no kernel to normalise: always on the faces. */
  sc->support = supports[o.width > 0.0 ? o.support : TL_SCOUPLING_SUPPORT_SURFACE];
  sc->n_faces = n_faces;
  sc->nf = nf;
  if ((s = tl_calloc(&sc->faces, n_faces, sizeof *sc->faces)) != TL_OK) goto fail;
  memcpy(sc->faces, faces, n_faces * sizeof *faces);
  if ((s = build_topology(sc)) != TL_OK) goto fail;
  if ((s = tl_calloc(&sc->X0, sc->n_local, sizeof *sc->X0)) != TL_OK) goto fail;
  if ((s = tl_calloc(&sc->xs, sc->n_local, sizeof *sc->xs)) != TL_OK) goto fail;
  if ((s = tl_calloc(&sc->nodal, sc->n_local, sizeof *sc->nodal)) != TL_OK) goto fail;
  for (size_t i = 0; i < sc->n_local; i++) {
    const double *X = mesh->x + 3 * sc->node[i];
    sc->X0[i] = sc->xs[i] = tl_v3(X[0], X[1], X[2]);
  }
  /* CG quadrature sub-cells per face direction: spacing (face size / (3
   * sub)) well below the width; one for the Dirac limit. */
  int sub = o.subdivisions;
  double h = 0.0;
  const int nc = face_type->n_corners;
  for (size_t f = 0; f < n_faces; f++)
    for (int a = 0; a < nc; a++) {
      TlVec3 d = tl_v3_sub(sc->X0[sc->face_local[f * (size_t)nf + (size_t)a]],
                           sc->X0[sc->face_local[f * (size_t)nf + (size_t)((a + 1) % nc)]]);
      h = fmax(h, tl_v3_norm(d));
    }
  sc->face_size = h;
  /* The points of a face with corner nodes only are convex combinations of
   * them (non-negative shape functions); one with mid-side nodes may bulge,
   * by far less than its size. */
  sc->bulge = face_type->n_nodes == face_type->n_corners ? 0.0 : h;
  if (sub == 0) {
    sub = o.width > 0.0 ? (int)ceil(2.0 * h / o.width) : 1;
    if (sub < 1) sub = 1;
    if (sub > 16) sub = 16;
  }
  if ((s = tl_scoupling_face_type_create(face_type, sub, &sc->ft)) != TL_OK) goto fail;
  /* Wall: the face type's pieces (quadrilaterals as four triangles around
   * their centre, quadratic faces subdivided). */
  const TlSCouplingFaceType *ft = sc->ft;
  size_t n_tri = (size_t)ft->n_pieces * n_faces;
  sc->n_vertices = sc->n_local + (size_t)ft->n_extra * n_faces;
  int *tri = NULL;
  if ((s = tl_calloc(&sc->vx, 3 * sc->n_vertices, sizeof *sc->vx)) != TL_OK) goto fail;
  if ((s = tl_calloc(&sc->vv, 3 * sc->n_vertices, sizeof *sc->vv)) != TL_OK) goto fail;
  if ((s = tl_calloc(&tri, 3 * n_tri, sizeof *tri)) != TL_OK) goto fail;
  for (size_t f = 0; f < n_faces; f++) {
    const int *q = sc->face_local + f * (size_t)nf;
    for (int k = 0; k < ft->n_pieces; k++)
      for (int j = 0; j < 3; j++) {
        const int v = ft->piece[k][j];
        tri[3 * (f * (size_t)ft->n_pieces + (size_t)k) + (size_t)j] =
            v < nf ? q[v] : (int)(sc->n_local + f * (size_t)ft->n_extra + (size_t)(v - nf));
      }
  }
  if ((s = tl_scoupling_set_kinematics(sc, NULL, NULL)) != TL_OK) { tl_free(&tri); goto fail; }
  TlTriSurface *surf = NULL;
  s = tl_trisurface_create(sc->n_vertices, sc->vx, n_tri, tri, &surf);
  tl_free(&tri);
  if (s != TL_OK) goto fail;
  if ((s = tl_wall_trisurface_create(surf, &sc->wall)) != TL_OK) goto fail;
  snprintf(sc->wall->name, sizeof sc->wall->name, "scoupling");
  /* CG surface over the FE faces (Eq. 15) or the Dirac limit (Eq. 16). */
  if (o.width > 0.0) {
    if ((s = tl_cg_kernel_create(o.kernel ? o.kernel : "lucy", o.width, 3, &sc->kernel)) != TL_OK) goto fail;
  } else {
    if ((s = tl_cg_kernel_create("dirac", 0.0, 3, &sc->kernel)) != TL_OK) goto fail;
  }
  /* Faces whose nodes are their corners (bilinear quadrilaterals, linear
   * triangles) through the CG module's own quadrilateral and triangle
   * types, any other through the face type's shape functions. */
  const int corners_only = face_type->n_nodes == face_type->n_corners;
  if (corners_only && face_type->shape == TL_SHAPE_QUAD && face_type->n_corners == 4)
    s = tl_cg_surface_create_quads(sc->n_local, sc->xs, n_faces, sc->face_local, sub, &sc->cg);
  else if (corners_only && face_type->shape == TL_SHAPE_TRI && face_type->n_corners == 3)
    s = tl_cg_surface_create_triangles(sc->n_local, sc->xs, n_faces, sc->face_local, sub, &sc->cg);
  else
    s = tl_cg_surface_create_element_faces(sc->ft, sc->n_local, sc->xs, n_faces, sc->face_local, &sc->cg);
  if (s != TL_OK) goto fail;
  if ((s = sc->support->setup(sc)) != TL_OK) goto fail;
  /* The SCoupling element type on every block holding coupled faces. */
  if ((s = install_wrappers(sc)) != TL_OK) goto fail;
  *out = sc;
  return TL_OK;
fail:
  tl_scoupling_destroy(&sc);
  return tl_error_trace(s, __FILE__, __LINE__);
}

TlStatus tl_scoupling_create_boundary(TlSolid *solid, int n_excluded, const char *const *excluded,
                                      const TlSCouplingOptions *options, TlSCoupling **sc)
{
  const TlMesh *m = tl_solid_mesh(solid);
  TlFaceRef *faces = NULL;
  TL_CHECK(tl_calloc(&faces, m->n_boundary ? m->n_boundary : 1, sizeof *faces));
  size_t n = 0;
  TlStatus s = TL_OK;
  for (size_t f = 0; f < m->n_boundary; f++) {
    int skip = 0;
    for (int k = 0; k < n_excluded && !skip; k++) {
      const TlFaceSet *set;
      if ((s = tl_mesh_find_face_set(m, excluded[k], &set)) != TL_OK) goto done;
      for (size_t j = 0; j < set->n && !skip; j++) skip = same_face(set->faces[j], m->boundary[f]);
    }
    if (!skip) faces[n++] = m->boundary[f];
  }
  s = tl_scoupling_create(solid, n, faces, options, sc);
done:
  tl_free(&faces);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  return TL_OK;
}

void tl_scoupling_destroy(TlSCoupling **psc)
{
  TlSCoupling *sc = *psc;
  if (!sc) return;
  if (sc->wrappers) remove_wrappers(sc);
  if (!sc->wall_given) tl_wall_destroy(&sc->wall);
  if (sc->support) sc->support->destroy(sc);
  tl_cg_surface_destroy(&sc->cg);
  tl_scoupling_face_type_destroy(&sc->ft);
  tl_free(&sc->c_elem);
  tl_cg_kernel_destroy(&sc->kernel);
  tl_free(&sc->faces);
  tl_free(&sc->node);
  tl_free(&sc->face_local);
  tl_free(&sc->X0);
  tl_free(&sc->xs);
  tl_free(&sc->vx);
  tl_free(&sc->vv);
  tl_free(&sc->elements);
  tl_free(&sc->active);
  tl_free(&sc->active_index);
  tl_free(&sc->face_element);
  tl_free(&sc->elem_active);
  tl_free(&sc->elem_face_ptr);
  tl_free(&sc->elem_face);
  tl_free(&sc->face_F);
  tl_free(&sc->face_touched);
  tl_free(&sc->touched_faces);
  tl_free(&sc->c_face);
  tl_free(&sc->c_point);
  tl_free(&sc->c_force);
  tl_free(&sc->nodal);
  tl_free(psc);
}

TlStatus tl_scoupling_add_to_dem(TlSCoupling *sc, TlDem *dem, int law)
{
  if (sc->wall_given) TL_ERROR(TL_ERR_STATE, "the coupling's wall was already given to a world");
  sc->wall_given = 1;
  TL_CHECK(tl_dem_add_wall(dem, sc->wall, law));
  return TL_OK;
}

TlWall *tl_scoupling_wall(TlSCoupling *sc) { return sc->wall; }

TlStatus tl_scoupling_set_kinematics(TlSCoupling *sc, const double *u, const double *v)
{
  if (sc->support->move) sc->support->move(sc, u);
  int bad = 0;
  for (size_t i = 0; i < sc->n_local; i++) {
    const size_t n = sc->node[i];
    TlVec3 x = sc->X0[i];
    if (u) x = tl_v3_add(x, tl_v3(u[3 * n], u[3 * n + 1], u[3 * n + 2]));
    bad |= !(fabs(x.x) + fabs(x.y) + fabs(x.z) <= DBL_MAX);
    sc->xs[i] = x;
    sc->vx[3 * i] = x.x, sc->vx[3 * i + 1] = x.y, sc->vx[3 * i + 2] = x.z;
    for (int c = 0; c < 3; c++) sc->vv[3 * i + (size_t)c] = v ? v[3 * n + (size_t)c] : 0.0;
  }
  for (size_t i = 0; bad && i < sc->n_local; i++)
    if (!(isfinite(sc->xs[i].x) && isfinite(sc->xs[i].y) && isfinite(sc->xs[i].z)))
      TL_ERROR(TL_ERR_NUMERIC, "node %zu of the coupled surface has a non-finite position", sc->node[i]);
  /* Extra wall vertices (centres): interpolated with the face's shape
   * functions, positions and velocities alike. */
  const TlSCouplingFaceType *ft = sc->ft;
  if (ft && ft->n_extra) {
    const int nf = sc->nf;
    for (size_t f = 0; f < sc->n_faces; f++) {
      const int *q = sc->face_local + f * (size_t)nf;
      for (int k = 0; k < ft->n_extra; k++) {
        const size_t cv = 3 * (sc->n_local + f * (size_t)ft->n_extra + (size_t)k);
        for (int c = 0; c < 3; c++) {
          double xs = 0.0, vs = 0.0;
          for (int a = 0; a < nf; a++) {
            xs += ft->extra_N[k][a] * sc->vx[3 * (size_t)q[a] + (size_t)c];
            vs += ft->extra_N[k][a] * sc->vv[3 * (size_t)q[a] + (size_t)c];
          }
          sc->vx[cv + (size_t)c] = xs;
          sc->vv[cv + (size_t)c] = vs;
        }
      }
    }
  }
  /* The wall refreshes the geometry of the triangles near particles only. */
  if (sc->wall) TL_CHECK(tl_trisurface_move_vertices(tl_wall_trisurface_surface(sc->wall), sc->vx, sc->vv));
  /* The quadrature is recomputed only when forces are spread (and never
   * for the Dirac limit, which reads the node positions directly). */
  sc->cg_stale = 1;
  return TL_OK;
}

/* The wall's active contacts into the per-contact arrays (forces times
 * scale); their total (unscaled) into *total. */
static TlStatus collect_contacts(TlSCoupling *sc, double scale, TlVec3 *total_wall)
{
  const TlTriContactSet *set = tl_wall_trisurface_contacts(sc->wall);
  size_t n = set ? set->count : 0;
  if (n > sc->capacity) {
    size_t cap = 2 * n;
    TL_CHECK(tl_realloc(&sc->c_face, cap, sizeof *sc->c_face));
    TL_CHECK(tl_realloc(&sc->c_point, cap, sizeof *sc->c_point));
    TL_CHECK(tl_realloc(&sc->c_force, cap, sizeof *sc->c_force));
    TL_CHECK(tl_realloc(&sc->c_elem, cap, sizeof *sc->c_elem));
    sc->capacity = cap;
  }
  size_t m = 0;
  TlVec3 total = tl_v3(0, 0, 0);
  for (size_t k = 0; k < n; k++) {
    const TlTriContactRecord *r = &set->c[k];
    if (!r->active) continue;
    sc->c_face[m] = (size_t)r->triangle / (size_t)sc->ft->n_pieces;
    sc->c_elem[m] = sc->face_element[sc->c_face[m]];
    sc->c_point[m] = r->point;
    sc->c_force[m] = scale == 1.0 ? r->force : tl_v3_scale(r->force, scale);
    total = tl_v3_add(total, r->force);
    m++;
  }
  sc->n_contacts = m;
  if (total_wall) *total_wall = total;
  /* The quadrature of the faces within reach of the contacts only: those
   * whose nodes' box, grown by the bulge, lies within c of a contact (the
   * others' points are beyond the kernel's support). */
  if (m && sc->cg_stale && sc->width > 0.0)
    TL_CHECK(tl_cg_surface_update_near(sc->cg_support, m, sc->c_point, sc->width + sc->bulge));
  if (m) sc->cg_stale = 0;
  return TL_OK;
}

/* Step 1 of §5.3.1: the owner of a face (or an element) the forces
 * reached becomes active, in the order first reached. */
void tl_scoupling_activate_element(TlSCoupling *sc, size_t e)
{
  if (sc->elem_active[e]) return;
  sc->elem_active[e] = 1;
  sc->active_index[sc->n_active] = e;
  sc->active[sc->n_active++] = sc->elements[e];
}

TlStatus tl_scoupling_accumulate_forces(TlSCoupling *sc, double scale, TlVec3 *total_wall)
{
  if (!isfinite(scale)) TL_ERROR(TL_ERR_ARG, "coupling force scale %g is not finite", scale);
  TL_CHECK(collect_contacts(sc, scale, total_wall));
  if (sc->n_contacts == 0) return TL_OK;
  return sc->support->spread(sc);
}

void tl_scoupling_clear_forces(TlSCoupling *sc)
{
  const TlSCouplingForceSet fs = sc->support->forces(sc);
  const size_t per = (size_t)fs.per_item;
  for (size_t t = 0; t < *fs.n_touched; t++) {
    const size_t k = fs.list[t];
    memset(fs.F + k * per, 0, per * sizeof *fs.F);
    fs.touched[k] = 0;
  }
  *fs.n_touched = 0;
  for (size_t k = 0; k < sc->n_active; k++) sc->elem_active[sc->active_index[k]] = 0;
  sc->n_active = 0;
}

void tl_scoupling_add_item(const TlSCouplingForceSet *fs, size_t k, double *f_nodes)
{
  const size_t per = (size_t)fs->per_item;
  const int *q = fs->local + k * per;
  const TlVec3 *F = fs->F + k * per;
  for (size_t a = 0; a < per; a++) {
    double *f = f_nodes + 3 * fs->node[q[a]];
    f[0] += F[a].x;
    f[1] += F[a].y;
    f[2] += F[a].z;
  }
}

void tl_scoupling_activate_touched(TlSCoupling *sc, const TlSCouplingForceSet *fs, size_t n0)
{
  for (size_t t = n0; t < *fs->n_touched; t++) {
    const size_t k = fs->list[t];
    tl_scoupling_activate_element(sc, fs->owner ? fs->owner[k] : k);
  }
}

void tl_scoupling_assemble_forces(const TlSCoupling *sc, double *f_nodes)
{
  const TlSCouplingForceSet fs = sc->support->forces(sc);
  for (size_t t = 0; t < *fs.n_touched; t++) tl_scoupling_add_item(&fs, fs.list[t], f_nodes);
}

size_t tl_scoupling_n_faces(const TlSCoupling *sc) { return sc->n_faces; }
const TlFaceRef *tl_scoupling_faces(const TlSCoupling *sc) { return sc->faces; }
int tl_scoupling_nodes_per_face(const TlSCoupling *sc) { return sc->nf; }
const TlVec3 *tl_scoupling_face_forces(const TlSCoupling *sc) { return sc->face_F; }
size_t tl_scoupling_n_touched_faces(const TlSCoupling *sc) { return sc->n_touched; }
const size_t *tl_scoupling_touched_faces(const TlSCoupling *sc) { return sc->touched_faces; }

TlStatus tl_scoupling_add_nodal_forces(TlSCoupling *sc, double scale, double *f_nodes, TlVec3 *total_wall)
{
  TL_CHECK(collect_contacts(sc, 1.0, total_wall));
  const size_t m = sc->n_contacts;
  if (m == 0) return TL_OK;
  memset(sc->nodal, 0, sc->n_local * sizeof *sc->nodal);
  TL_CHECK(tl_cg_surface_nodal_forces(sc->cg, sc->kernel, m, sc->c_face, sc->c_point, sc->c_force, sc->nodal));
  for (size_t i = 0; i < sc->n_local; i++) {
    double *f = f_nodes + 3 * sc->node[i];
    f[0] += scale * sc->nodal[i].x;
    f[1] += scale * sc->nodal[i].y;
    f[2] += scale * sc->nodal[i].z;
  }
  return TL_OK;
}

static TlStatus save_force_set(const TlSCouplingForceSet *fs, TlCheckpointWriter *w, const char *group, const char *prefix)
{
  char name[128];
  int64_t *list = NULL;
  TL_CHECK(tl_calloc(&list, *fs->n_touched ? *fs->n_touched : 1, sizeof *list));
  for (size_t t = 0; t < *fs->n_touched; t++) list[t] = (int64_t)fs->list[t];
  snprintf(name, sizeof name, "%stouched_%ss", prefix, fs->item);
  TlStatus s = tl_checkpoint_write_int64s(w, group, name, *fs->n_touched, list);
  tl_free(&list);
  TL_CHECK(s);
  snprintf(name, sizeof name, "%s%s_forces", prefix, fs->item);
  TL_CHECK(tl_checkpoint_write_doubles(w, group, name, 3 * fs->n_items * (size_t)fs->per_item, (const double *)fs->F));
  return TL_OK;
}

/* Into a cleared set: the same items, in the same order, and their forces. */
static TlStatus load_force_set(const TlSCouplingForceSet *fs, TlCheckpointReader *r, const char *group, const char *prefix)
{
  char name[128];
  size_t n = 0;
  snprintf(name, sizeof name, "%s%s_forces", prefix, fs->item);
  TL_CHECK(tl_checkpoint_length(r, group, name, &n));
  if (n != 3 * fs->n_items * (size_t)fs->per_item)
    TL_ERROR(TL_ERR_ARG, "checkpoint holds %zu per-%s force components in %s, this coupling has %zu %ss x %d nodes x 3", n,
             fs->item, name, fs->n_items, fs->item, fs->per_item);
  snprintf(name, sizeof name, "%stouched_%ss", prefix, fs->item);
  TL_CHECK(tl_checkpoint_length(r, group, name, &n));
  if (n > fs->n_items)
    TL_ERROR(TL_ERR_ARG, "checkpoint lists %zu touched %ss in %s, this coupling has %zu", n, fs->item, name, fs->n_items);
  int64_t *list = NULL;
  TL_CHECK(tl_calloc(&list, n ? n : 1, sizeof *list));
  TlStatus s = tl_checkpoint_read_int64s(r, group, name, n, list);
  for (size_t t = 0; s == TL_OK && t < n; t++)
    if (list[t] < 0 || (uint64_t)list[t] >= fs->n_items)
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "checkpoint names touched %s %lld in %s, outside [0, %zu)", fs->item,
                       (long long)list[t], name, fs->n_items);
  for (size_t t = 0; s == TL_OK && t < n; t++) {
    const size_t k = (size_t)list[t];
    if (fs->touched[k]) continue;
    fs->touched[k] = 1;
    fs->list[(*fs->n_touched)++] = k;
  }
  tl_free(&list);
  TL_CHECK(s);
  snprintf(name, sizeof name, "%s%s_forces", prefix, fs->item);
  TL_CHECK(tl_checkpoint_read_doubles(r, group, name, 3 * fs->n_items * (size_t)fs->per_item, (double *)fs->F));
  return TL_OK;
}

TlStatus tl_scoupling_save_forces(const TlSCoupling *sc, TlCheckpointWriter *w, const char *group, const char *prefix)
{
  char name[128];
  snprintf(name, sizeof name, "%scg_support", prefix);
  TL_CHECK(tl_checkpoint_write_int64(w, group, name, sc->support->id));
  const TlSCouplingForceSet fs = sc->support->forces(sc);
  return save_force_set(&fs, w, group, prefix);
}

TlStatus tl_scoupling_load_forces(TlSCoupling *sc, TlCheckpointReader *r, const char *group, const char *prefix)
{
  char name[128];
  int64_t support = 0;
  snprintf(name, sizeof name, "%scg_support", prefix);
  TL_CHECK(tl_checkpoint_read_int64(r, group, name, &support));
  if (support != sc->support->id)
    TL_ERROR(TL_ERR_ARG, "checkpoint was written with CG support %lld (0 surface, 1 elements), this coupling has %d (%s)",
             (long long)support, sc->support->id, sc->support->header.name);
  /* The same faces (elements), active elements and order as when saved. */
  tl_scoupling_clear_forces(sc);
  const TlSCouplingForceSet fs = sc->support->forces(sc);
  TL_CHECK(load_force_set(&fs, r, group, prefix));
  tl_scoupling_activate_touched(sc, &fs, 0);
  return TL_OK;
}

size_t tl_scoupling_n_elements(const TlSCoupling *sc) { return sc->n_elements; }
size_t tl_scoupling_n_active_elements(const TlSCoupling *sc) { return sc->n_active; }
const TlFaceRef *tl_scoupling_elements(const TlSCoupling *sc) { return sc->elements; }
const TlFaceRef *tl_scoupling_active_elements(const TlSCoupling *sc) { return sc->active; }
size_t tl_scoupling_n_contacts(const TlSCoupling *sc) { return sc->n_contacts; }
double tl_scoupling_width(const TlSCoupling *sc) { return sc->width; }
TlSolid *tl_scoupling_solid(const TlSCoupling *sc) { return sc->solid; }
const TlCGSurface *tl_scoupling_cg_surface(const TlSCoupling *sc) { return sc->cg_support; }
