/* Triangles of a Gmsh ASCII mesh (.msh 2.2 and 4.1) as a surface mesh
 * (tl_stl.h).  Node tags may be sparse; only nodes used by triangles are
 * kept, numbered in order of first use. */
#include "tl_stl.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tl_memory.h"

typedef struct {
  const char *p, *end;
  size_t line;
  const char *label;
} TlMshLexer;

static int msh_token(TlMshLexer *l, char *tok, size_t cap)
{
  while (l->p < l->end && (*l->p == ' ' || *l->p == '\t' || *l->p == '\r' || *l->p == '\n' || *l->p == '\0')) {
    if (*l->p == '\n') ++l->line;
    ++l->p;
  }
  if (l->p >= l->end) return 0;
  size_t n = 0;
  while (l->p < l->end && !(*l->p == ' ' || *l->p == '\t' || *l->p == '\r' || *l->p == '\n' || *l->p == '\0')) {
    if (n + 1 < cap) tok[n++] = *l->p;
    ++l->p;
  }
  tok[n] = '\0';
  return 1;
}

static TlStatus msh_real(TlMshLexer *l, double *v, const char *what)
{
  char tok[128], *end = NULL;
  if (!msh_token(l, tok, sizeof tok))
    TL_ERROR(TL_ERR_FORMAT, "%s: Gmsh file is truncated: %s expected at line %zu", l->label, what, l->line);
  *v = strtod(tok, &end);
  if (end == tok || *end) TL_ERROR(TL_ERR_FORMAT, "%s: line %zu: '%.40s' is not a number (%s)", l->label, l->line, tok, what);
  return TL_OK;
}

static TlStatus msh_count(TlMshLexer *l, long long lo, long long hi, long long *v, const char *what)
{
  char tok[128], *end = NULL;
  if (!msh_token(l, tok, sizeof tok))
    TL_ERROR(TL_ERR_FORMAT, "%s: Gmsh file is truncated: %s expected at line %zu", l->label, what, l->line);
  *v = strtoll(tok, &end, 10);
  if (end == tok || *end || *v < lo || *v > hi)
    TL_ERROR(TL_ERR_FORMAT, "%s: line %zu: %s '%.40s' is not an integer in [%lld, %lld]", l->label, l->line, what, tok, lo, hi);
  return TL_OK;
}

/* Advances past the line "$<section>"; 0 when absent. */
static int msh_find(TlMshLexer *l, const char *section)
{
  char tok[64];
  while (msh_token(l, tok, sizeof tok))
    if (strcmp(tok, section) == 0) return 1;
  return 0;
}

typedef struct {
  long long tag;
  TlVec3 x;
} TlMshNode;

static int node_compare(const void *a, const void *b)
{
  long long s = ((const TlMshNode *)a)->tag, t = ((const TlMshNode *)b)->tag;
  return (s > t) - (s < t);
}

enum { TL_MSH_MAX_COUNT = 100000000 }; /* a bound that keeps a corrupt count from allocating the machine */

TlStatus tl_gmsh_surface_read_memory(const void *data, size_t size, const char *label, TlSurfaceMesh **m)
{
  if (!m) TL_ERROR(TL_ERR_ARG, "tl_gmsh_surface_read_memory: NULL output");
  *m = NULL;
  if (!label) label = "Gmsh mesh";
  TlMshLexer l = {data, (const char *)data + size, 1, label};
  TlStatus status = TL_OK;
  TlMshNode *node = NULL;
  long long *tri = NULL; /* node tags, 3 per triangle */
  size_t n_nodes = 0, n_tri = 0, tri_cap = 0;
  int *used = NULL;
  double *x = NULL;
  int *idx = NULL;
  char tok[64];
  double version;
  long long ftype, dsize;
  if (!msh_find(&l, "$MeshFormat")) TL_ERROR(TL_ERR_FORMAT, "%s: no $MeshFormat section: not a Gmsh mesh", label);
  TL_CHECK(msh_real(&l, &version, "format version"));
  TL_CHECK(msh_count(&l, 0, 1, &ftype, "file type"));
  TL_CHECK(msh_count(&l, 0, 16, &dsize, "data size"));
  if (ftype != 0) TL_ERROR(TL_ERR_UNSUPPORTED, "%s: binary Gmsh files are not read: save as ASCII (-format msh41 or msh22)", label);
  int v4 = version >= 4.0 && version < 5.0, v2 = version >= 2.0 && version < 3.0;
  if (!v4 && !v2) TL_ERROR(TL_ERR_UNSUPPORTED, "%s: Gmsh format %g: versions 2.2 and 4.1 are read", label, version);

  if (!msh_find(&l, "$Nodes")) TL_ERROR(TL_ERR_FORMAT, "%s: no $Nodes section", label);
  if (v4) {
    long long blocks, total, lo, hi;
    TL_CHECK(msh_count(&l, 0, TL_MSH_MAX_COUNT, &blocks, "number of node blocks"));
    TL_CHECK(msh_count(&l, 0, TL_MSH_MAX_COUNT, &total, "number of nodes"));
    TL_CHECK(msh_count(&l, 0, INT64_MAX, &lo, "smallest node tag"));
    TL_CHECK(msh_count(&l, 0, INT64_MAX, &hi, "largest node tag"));
    TL_CHECK(tl_calloc(&node, (size_t)total + 1, sizeof *node));
    for (long long b = 0; b < blocks; ++b) {
      long long dim, ent, param, count;
      TL_CHECK_GOTO(status, msh_count(&l, 0, 3, &dim, "entity dimension"), done);
      TL_CHECK_GOTO(status, msh_count(&l, INT32_MIN, INT32_MAX, &ent, "entity tag"), done);
      TL_CHECK_GOTO(status, msh_count(&l, 0, 1, &param, "parametric flag"), done);
      TL_CHECK_GOTO(status, msh_count(&l, 0, total - (long long)n_nodes, &count, "nodes in block"), done);
      for (long long k = 0; k < count; ++k)
        TL_CHECK_GOTO(status, msh_count(&l, 1, INT64_MAX, &node[n_nodes + (size_t)k].tag, "node tag"), done);
      for (long long k = 0; k < count; ++k) {
        TlVec3 *p = &node[n_nodes + (size_t)k].x;
        TL_CHECK_GOTO(status, msh_real(&l, &p->x, "node coordinate"), done);
        TL_CHECK_GOTO(status, msh_real(&l, &p->y, "node coordinate"), done);
        TL_CHECK_GOTO(status, msh_real(&l, &p->z, "node coordinate"), done);
        for (long long u = 0; u < param * dim; ++u) {
          double skip;
          TL_CHECK_GOTO(status, msh_real(&l, &skip, "parametric coordinate"), done);
        }
      }
      n_nodes += (size_t)count;
    }
  } else {
    long long total;
    TL_CHECK(msh_count(&l, 0, TL_MSH_MAX_COUNT, &total, "number of nodes"));
    TL_CHECK(tl_calloc(&node, (size_t)total + 1, sizeof *node));
    for (; n_nodes < (size_t)total; ++n_nodes) {
      TL_CHECK_GOTO(status, msh_count(&l, 1, INT64_MAX, &node[n_nodes].tag, "node tag"), done);
      TL_CHECK_GOTO(status, msh_real(&l, &node[n_nodes].x.x, "node coordinate"), done);
      TL_CHECK_GOTO(status, msh_real(&l, &node[n_nodes].x.y, "node coordinate"), done);
      TL_CHECK_GOTO(status, msh_real(&l, &node[n_nodes].x.z, "node coordinate"), done);
    }
  }
  qsort(node, n_nodes, sizeof *node, node_compare);
  for (size_t i = 1; i < n_nodes; ++i)
    if (node[i].tag == node[i - 1].tag) {
      status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: node tag %lld appears twice", label, node[i].tag);
      goto done;
    }

  if (!msh_find(&l, "$Elements")) {
    status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: no $Elements section", label);
    goto done;
  }
  /* nodes per element type, for skipping types that are not triangles
   * (2: 3-node triangle, 9: 6-node triangle; others skipped) */
  static const int type_nodes[32] = {0, 2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, 27, 18, 14, 1, 8, 20, 15, 13,
                                     9, 10, 12, 15, 15, 21, 4, 5, 6, 20, 35, 56};
  long long blocks = 1, total;
  if (v4) {
    long long lo, hi;
    TL_CHECK_GOTO(status, msh_count(&l, 0, TL_MSH_MAX_COUNT, &blocks, "number of element blocks"), done);
    TL_CHECK_GOTO(status, msh_count(&l, 0, TL_MSH_MAX_COUNT, &total, "number of elements"), done);
    TL_CHECK_GOTO(status, msh_count(&l, 0, INT64_MAX, &lo, "smallest element tag"), done);
    TL_CHECK_GOTO(status, msh_count(&l, 0, INT64_MAX, &hi, "largest element tag"), done);
  } else {
    TL_CHECK_GOTO(status, msh_count(&l, 0, TL_MSH_MAX_COUNT, &total, "number of elements"), done);
  }
  size_t seen = 0;
  for (long long b = 0; b < blocks; ++b) {
    long long type = 0, count = total;
    if (v4) {
      long long dim, ent;
      TL_CHECK_GOTO(status, msh_count(&l, 0, 3, &dim, "entity dimension"), done);
      TL_CHECK_GOTO(status, msh_count(&l, INT32_MIN, INT32_MAX, &ent, "entity tag"), done);
      TL_CHECK_GOTO(status, msh_count(&l, 1, 31, &type, "element type"), done);
      TL_CHECK_GOTO(status, msh_count(&l, 0, total - (long long)seen, &count, "elements in block"), done);
    }
    for (long long k = 0; k < count; ++k) {
      long long tag, nn, tags = 0;
      TL_CHECK_GOTO(status, msh_count(&l, 1, INT64_MAX, &tag, "element tag"), done);
      if (!v4) {
        TL_CHECK_GOTO(status, msh_count(&l, 1, 31, &type, "element type"), done);
        TL_CHECK_GOTO(status, msh_count(&l, 0, 64, &tags, "number of element tags"), done);
        for (long long u = 0; u < tags; ++u) {
          long long skip;
          TL_CHECK_GOTO(status, msh_count(&l, INT64_MIN, INT64_MAX, &skip, "element tag"), done);
        }
      }
      nn = type_nodes[type];
      if (nn == 0) {
        status = tl_error_set(TL_ERR_UNSUPPORTED, __FILE__, __LINE__, "%s: element %lld has unknown type %lld", label, tag, type);
        goto done;
      }
      long long t3[3] = {0, 0, 0};
      for (long long u = 0; u < nn; ++u) {
        long long nt;
        TL_CHECK_GOTO(status, msh_count(&l, 1, INT64_MAX, &nt, "element node"), done);
        if (u < 3) t3[u] = nt;
      }
      if (type == 2 || type == 9) {
        if (n_tri == tri_cap) {
          tri_cap = tri_cap ? 2 * tri_cap : 256;
          TL_CHECK_GOTO(status, tl_realloc(&tri, 3 * tri_cap, sizeof *tri), done);
        }
        memcpy(tri + 3 * n_tri, t3, sizeof t3);
        ++n_tri;
      }
    }
    seen += (size_t)count;
  }
  if (!msh_token(&l, tok, sizeof tok) || strcmp(tok, "$EndElements") != 0) {
    status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: $EndElements expected at line %zu", label, l.line);
    goto done;
  }
  if (n_tri == 0) {
    status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: the mesh has no triangle (element types 2 or 9)", label);
    goto done;
  }
  if (n_tri > (size_t)INT32_MAX / 3) {
    status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: %zu triangles, the limit is %d", label, n_tri, INT32_MAX / 3);
    goto done;
  }
  /* keep the nodes the triangles use */
  TL_CHECK_GOTO(status, tl_calloc(&used, n_nodes + 1, sizeof *used), done);
  TL_CHECK_GOTO(status, tl_calloc(&idx, 3 * n_tri, sizeof *idx), done);
  TL_CHECK_GOTO(status, tl_calloc(&x, 3 * (3 * n_tri < n_nodes ? 3 * n_tri : n_nodes) + 3, sizeof *x), done);
  for (size_t i = 0; i < n_nodes; ++i) used[i] = -1;
  size_t nv = 0;
  for (size_t t = 0; t < n_tri; ++t)
    for (int k = 0; k < 3; ++k) {
      TlMshNode key = {tri[3 * t + (size_t)k], {0, 0, 0}};
      TlMshNode *hit = bsearch(&key, node, n_nodes, sizeof *node, node_compare);
      if (!hit) {
        status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: triangle %zu uses node %lld, which is not in $Nodes",
                              label, t, key.tag);
        goto done;
      }
      size_t i = (size_t)(hit - node);
      if (used[i] < 0) {
        if (!tl_v3_isfinite(hit->x)) {
          status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                                "%s: triangle %zu, node %lld has a non-finite coordinate (%g, %g, %g)", label, t,
                                hit->tag, hit->x.x, hit->x.y, hit->x.z);
          goto done;
        }
        used[i] = (int)nv;
        x[3 * nv] = hit->x.x, x[3 * nv + 1] = hit->x.y, x[3 * nv + 2] = hit->x.z;
        ++nv;
      }
      idx[3 * t + (size_t)k] = used[i];
    }
  TL_CHECK_GOTO(status, tl_surface_mesh_create(nv, x, n_tri, idx, m), done);
done:
  tl_free(&node);
  tl_free(&tri);
  tl_free(&used);
  tl_free(&x);
  tl_free(&idx);
  return status;
}
