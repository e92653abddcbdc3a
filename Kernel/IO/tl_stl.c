/* STL reading and writing (tl_stl.h). */
#include "tl_stl.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tl_memory.h"

TlStatus tl_surface_mesh_create(size_t n_vertices, const double *x, size_t n_triangles, const int *tri,
                                TlSurfaceMesh **m)
{
  if (!m) TL_ERROR(TL_ERR_ARG, "tl_surface_mesh_create: NULL output");
  *m = NULL;
  if ((n_vertices && !x) || (n_triangles && !tri))
    TL_ERROR(TL_ERR_ARG, "tl_surface_mesh_create: NULL arrays for %zu vertices, %zu triangles", n_vertices,
             n_triangles);
  if (n_vertices > (size_t)INT32_MAX)
    TL_ERROR(TL_ERR_ARG, "surface of %zu vertices: the limit is %d", n_vertices, INT32_MAX);
  for (size_t t = 0; t < n_triangles; ++t)
    for (int k = 0; k < 3; ++k)
      if (tri[3 * t + k] < 0 || (size_t)tri[3 * t + k] >= n_vertices)
        TL_ERROR(TL_ERR_ARG, "triangle %zu: vertex index %d outside [0, %zu)", t, tri[3 * t + k], n_vertices);
  TlSurfaceMesh *s = NULL;
  TL_CHECK(TL_NEW(s));
  TlStatus status = TL_OK;
  TL_CHECK_GOTO(status, tl_calloc(&s->x, n_vertices + 1, sizeof *s->x), fail);
  TL_CHECK_GOTO(status, tl_calloc(&s->tri, n_triangles + 1, sizeof *s->tri), fail);
  for (size_t i = 0; i < n_vertices; ++i) s->x[i] = tl_v3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
  for (size_t t = 0; t < n_triangles; ++t)
    for (int k = 0; k < 3; ++k) s->tri[t][k] = tri[3 * t + k];
  s->n_vertices = n_vertices;
  s->n_triangles = n_triangles;
  *m = s;
  return TL_OK;
fail:
  tl_surface_mesh_destroy(&s);
  return status;
}

void tl_surface_mesh_destroy(TlSurfaceMesh **m)
{
  if (!m || !*m) return;
  tl_free(&(*m)->x);
  tl_free(&(*m)->tri);
  tl_free(m);
}

TlStatus tl_surface_mesh_transform(TlSurfaceMesh *m, double scale, TlMat3 R, TlVec3 shift)
{
  if (!m) TL_ERROR(TL_ERR_ARG, "tl_surface_mesh_transform: NULL mesh");
  if (!(scale > 0.0) || !isfinite(scale)) TL_ERROR(TL_ERR_ARG, "surface scale %g must be positive and finite", scale);
  if (!tl_v3_isfinite(shift)) TL_ERROR(TL_ERR_ARG, "surface shift (%g, %g, %g) is not finite", shift.x, shift.y, shift.z);
  TlMat3 rtr = tl_m3_mul(tl_m3_transpose(R), R);
  double off = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) off = fmax(off, fabs(rtr.m[i][j] - (i == j)));
  double det = tl_m3_det(R);
  if (!(off <= 1e-9) || !(fabs(det - 1.0) <= 1e-9))
    TL_ERROR(TL_ERR_ARG, "surface rotation is not a rotation: |R^T R - I| = %g, det R = %g (limits 1e-9, 1 +- 1e-9)",
             off, det);
  for (size_t i = 0; i < m->n_vertices; ++i) m->x[i] = tl_v3_add(tl_m3_mulv(R, tl_v3_scale(m->x[i], scale)), shift);
  return TL_OK;
}

void tl_surface_mesh_flip(TlSurfaceMesh *m)
{
  for (size_t t = 0; t < m->n_triangles; ++t) {
    int a = m->tri[t][1];
    m->tri[t][1] = m->tri[t][2];
    m->tri[t][2] = a;
  }
}

/* ------------------------------------------------------------ reading */

/* Corners are collected facet by facet (3 per facet), then joined. */
typedef struct {
  TlVec3 *corner;
  size_t n, cap;
} TlCorners;

static TlStatus corners_push(TlCorners *c, TlVec3 p)
{
  if (c->n == c->cap) {
    size_t cap = c->cap ? 2 * c->cap : 768;
    TL_CHECK(tl_realloc(&c->corner, cap, sizeof *c->corner));
    c->cap = cap;
  }
  c->corner[c->n++] = p;
  return TL_OK;
}

/* A corner with its index, sorted by coordinates then index (qsort has no
 * context argument: the key carries what the comparison needs, so that
 * readers may run in several threads at once). */
typedef struct {
  TlVec3 x;
  size_t i;
} TlCornerKey;

static int corner_same(const TlCornerKey *a, const TlCornerKey *b)
{
  return a->x.x == b->x.x && a->x.y == b->x.y && a->x.z == b->x.z;
}

static int corner_compare(const void *pa, const void *pb)
{
  const TlCornerKey *a = pa, *b = pb;
  if (a->x.x != b->x.x) return a->x.x < b->x.x ? -1 : 1;
  if (a->x.y != b->x.y) return a->x.y < b->x.y ? -1 : 1;
  if (a->x.z != b->x.z) return a->x.z < b->x.z ? -1 : 1;
  return (a->i > b->i) - (a->i < b->i);
}

/* Joins corners with equal coordinates into vertices (in order of first
 * appearance) and builds the mesh: facet k becomes triangle k. */
static TlStatus corners_to_mesh(const TlCorners *c, const char *name, TlSurfaceMesh **m)
{
  size_t n = c->n, nt = n / 3;
  size_t *order = NULL, *vertex_of = NULL;
  TlCornerKey *key = NULL;
  TlSurfaceMesh *s = NULL;
  TlStatus status = TL_OK;
  if (n > (size_t)INT32_MAX) TL_ERROR(TL_ERR_FORMAT, "%s: %zu facets, the limit is %d", name, nt, INT32_MAX / 3);
  TL_CHECK_GOTO(status, tl_calloc(&order, n + 1, sizeof *order), done);
  TL_CHECK_GOTO(status, tl_calloc(&vertex_of, n + 1, sizeof *vertex_of), done);
  TL_CHECK_GOTO(status, tl_calloc(&key, n + 1, sizeof *key), done);
  for (size_t i = 0; i < n; ++i) key[i] = (TlCornerKey){c->corner[i], i};
  qsort(key, n, sizeof *key, corner_compare);
  /* the representative of each class is its first corner (smallest index) */
  for (size_t i = 0; i < n;) {
    size_t j = i + 1;
    while (j < n && corner_same(&key[i], &key[j])) ++j;
    for (size_t k = i; k < j; ++k) vertex_of[key[k].i] = key[i].i;
    i = j;
  }
  tl_free(&key);
  TL_CHECK_GOTO(status, TL_NEW(s), done);
  TL_CHECK_GOTO(status, tl_calloc(&s->x, n + 1, sizeof *s->x), done);
  TL_CHECK_GOTO(status, tl_calloc(&s->tri, nt + 1, sizeof *s->tri), done);
  /* number the representatives in order of appearance (order[] reused) */
  size_t nv = 0;
  for (size_t i = 0; i < n; ++i)
    if (vertex_of[i] == i) {
      order[i] = nv;
      s->x[nv++] = c->corner[i];
    }
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) s->tri[t][k] = (int)order[vertex_of[3 * t + (size_t)k]];
  s->n_vertices = nv;
  s->n_triangles = nt;
  snprintf(s->name, sizeof s->name, "%s", name);
  *m = s;
  s = NULL;
done:
  tl_surface_mesh_destroy(&s);
  tl_free(&order);
  tl_free(&vertex_of);
  tl_free(&key);
  return status;
}

static TlStatus read_file(const char *path, char **data, size_t *size)
{
  *data = NULL;
  *size = 0;
  FILE *f = fopen(path, "rb");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot open surface file '%s': %s", path, strerror(errno));
  TlStatus status = TL_OK;
  size_t cap = 1 << 16, n = 0;
  char *buf = NULL;
  TL_CHECK_GOTO(status, tl_calloc(&buf, cap + 1, 1), done);
  for (;;) {
    size_t got = fread(buf + n, 1, cap - n, f);
    n += got;
    if (n < cap) break;
    cap *= 2;
    TL_CHECK_GOTO(status, tl_realloc(&buf, cap + 1, 1), done);
  }
  if (ferror(f)) {
    status = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "error reading surface file '%s'", path);
    goto done;
  }
  buf[n] = '\0';
  *data = buf;
  *size = n;
  buf = NULL;
done:
  tl_free(&buf);
  fclose(f);
  return status;
}

static uint32_t le32(const unsigned char *p)
{
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float lefloat(const unsigned char *p)
{
  uint32_t u = le32(p);
  float f;
  memcpy(&f, &u, sizeof f);
  return f;
}

static TlStatus stl_read_binary(const unsigned char *d, size_t size, const char *label, TlSurfaceMesh **m)
{
  if (size < 84)
    TL_ERROR(TL_ERR_FORMAT, "%s: binary STL of %zu bytes is truncated: the header and facet count take 84", label,
             size);
  size_t n = le32(d + 80);
  size_t have = (size - 84) / 50;
  if (have < n)
    TL_ERROR(TL_ERR_FORMAT, "%s: binary STL declares %zu facets but is truncated in facet %zu (%zu bytes, %zu needed)",
             label, n, have, size, 84 + 50 * n);
  if (n == 0) TL_ERROR(TL_ERR_FORMAT, "%s: binary STL declares no facet", label);
  TlCorners c = {0};
  TlStatus status = TL_OK;
  for (size_t t = 0; t < n; ++t) {
    const unsigned char *f = d + 84 + 50 * t + 12;
    for (int k = 0; k < 3; ++k) {
      TlVec3 p = tl_v3(lefloat(f + 12 * k), lefloat(f + 12 * k + 4), lefloat(f + 12 * k + 8));
      if (!tl_v3_isfinite(p)) {
        status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                              "%s: facet %zu, vertex %d has a non-finite coordinate (%g, %g, %g)", label, t, k, p.x,
                              p.y, p.z);
        goto done;
      }
      TL_CHECK_GOTO(status, corners_push(&c, p), done);
    }
  }
  /* the solid's name: the header's printable start, as ASCII files have it */
  char name[64] = "";
  size_t k = 0;
  while (k < 63 && k < 80 && d[k] >= 32 && d[k] < 127) name[k] = (char)d[k], ++k;
  name[k] = '\0';
  while (k > 0 && name[k - 1] == ' ') name[--k] = '\0';
  TL_CHECK_GOTO(status, corners_to_mesh(&c, name, m), done);
done:
  tl_free(&c.corner);
  return status;
}

/* ASCII: a token stream with line numbers. */
typedef struct {
  const char *p, *end;
  size_t line;
  const char *label;
} TlLexer;

static void lex_space(TlLexer *l)
{
  while (l->p < l->end && (*l->p == ' ' || *l->p == '\t' || *l->p == '\r' || *l->p == '\n' || *l->p == '\f' ||
                           *l->p == '\v')) {
    if (*l->p == '\n') ++l->line;
    ++l->p;
  }
}

/* Next token into tok (truncated to its size); 0 at the end. */
static int lex_token(TlLexer *l, char *tok, size_t cap)
{
  lex_space(l);
  if (l->p >= l->end) return 0;
  size_t n = 0;
  while (l->p < l->end && !(*l->p == ' ' || *l->p == '\t' || *l->p == '\r' || *l->p == '\n' || *l->p == '\f' ||
                            *l->p == '\v' || *l->p == '\0')) {
    if (n + 1 < cap) tok[n++] = *l->p;
    ++l->p;
  }
  if (n == 0) { /* a NUL byte */
    ++l->p;
    tok[n++] = '?';
  }
  tok[n] = '\0';
  return 1;
}

static TlStatus lex_expect(TlLexer *l, const char *word, size_t facet)
{
  char tok[64];
  if (!lex_token(l, tok, sizeof tok))
    TL_ERROR(TL_ERR_FORMAT, "%s: ASCII STL is truncated in facet %zu: '%s' expected at line %zu", l->label, facet, word,
             l->line);
  if (strcmp(tok, word) != 0)
    TL_ERROR(TL_ERR_FORMAT, "%s: facet %zu, line %zu: '%s' expected, got '%.40s'", l->label, facet, l->line, word, tok);
  return TL_OK;
}

static TlStatus lex_number(TlLexer *l, double *v, size_t facet, const char *what)
{
  char tok[128];
  if (!lex_token(l, tok, sizeof tok))
    TL_ERROR(TL_ERR_FORMAT, "%s: ASCII STL is truncated in facet %zu: a %s coordinate expected at line %zu", l->label,
             facet, what, l->line);
  char *end = NULL;
  *v = strtod(tok, &end);
  if (end == tok || *end != '\0')
    TL_ERROR(TL_ERR_FORMAT, "%s: facet %zu, line %zu: '%.40s' is not a number (%s coordinate)", l->label, facet,
             l->line, tok, what);
  return TL_OK;
}

static TlStatus stl_read_ascii(const char *d, size_t size, const char *label, TlSurfaceMesh **m)
{
  TlLexer l = {d, d + size, 1, label};
  TlCorners c = {0};
  TlStatus status = TL_OK;
  char tok[64], name[64] = "";
  size_t facet = 0;
  int solids = 0, in_solid = 0;
  while (lex_token(&l, tok, sizeof tok)) {
    if (!in_solid) {
      if (strcmp(tok, "solid") != 0) {
        status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: line %zu: 'solid' expected, got '%.40s'", label,
                              l.line, tok);
        goto done;
      }
      /* the rest of the line is the name */
      const char *p = l.p;
      while (p < l.end && (*p == ' ' || *p == '\t')) ++p;
      size_t k = 0;
      while (p < l.end && *p != '\n' && *p != '\r') {
        if (k < sizeof name - 1 && !solids) name[k++] = (*p >= 32 && *p < 127) ? *p : '?';
        ++p;
      }
      if (!solids) name[k] = '\0';
      l.p = p;
      in_solid = 1;
      ++solids;
      continue;
    }
    if (strcmp(tok, "endsolid") == 0) {
      /* skip the optional name on the same line */
      while (l.p < l.end && *l.p != '\n') ++l.p;
      in_solid = 0;
      continue;
    }
    if (strcmp(tok, "facet") != 0) {
      status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: line %zu: 'facet' or 'endsolid' expected after facet %zu, got '%.40s'",
                            label, l.line, facet, tok);
      goto done;
    }
    double nx, ny, nz;
    TL_CHECK_GOTO(status, lex_expect(&l, "normal", facet), done);
    TL_CHECK_GOTO(status, lex_number(&l, &nx, facet, "normal"), done);
    TL_CHECK_GOTO(status, lex_number(&l, &ny, facet, "normal"), done);
    TL_CHECK_GOTO(status, lex_number(&l, &nz, facet, "normal"), done);
    TL_CHECK_GOTO(status, lex_expect(&l, "outer", facet), done);
    TL_CHECK_GOTO(status, lex_expect(&l, "loop", facet), done);
    for (int k = 0;; ++k) {
      size_t line = l.line;
      if (!lex_token(&l, tok, sizeof tok)) {
        status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                              "%s: ASCII STL is truncated in facet %zu (line %zu): 'vertex' or 'endloop' expected",
                              label, facet, l.line);
        goto done;
      }
      if (strcmp(tok, "endloop") == 0) {
        if (k != 3) {
          status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                                "%s: facet %zu (line %zu) has %d vertices; STL facets are triangles", label, facet,
                                line, k);
          goto done;
        }
        break;
      }
      if (strcmp(tok, "vertex") != 0) {
        status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: facet %zu, line %zu: 'vertex' expected, got '%.40s'",
                              label, facet, line, tok);
        goto done;
      }
      if (k == 3) {
        status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                              "%s: facet %zu (line %zu) has more than 3 vertices; STL facets are triangles", label,
                              facet, line);
        goto done;
      }
      TlVec3 p;
      TL_CHECK_GOTO(status, lex_number(&l, &p.x, facet, "vertex"), done);
      TL_CHECK_GOTO(status, lex_number(&l, &p.y, facet, "vertex"), done);
      TL_CHECK_GOTO(status, lex_number(&l, &p.z, facet, "vertex"), done);
      if (!tl_v3_isfinite(p)) {
        status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                              "%s: facet %zu, vertex %d (line %zu) has a non-finite coordinate (%g, %g, %g)", label,
                              facet, k, line, p.x, p.y, p.z);
        goto done;
      }
      TL_CHECK_GOTO(status, corners_push(&c, p), done);
    }
    TL_CHECK_GOTO(status, lex_expect(&l, "endfacet", facet), done);
    ++facet;
  }
  if (in_solid) {
    status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: ASCII STL is truncated after facet %zu: 'endsolid' missing",
                          label, facet);
    goto done;
  }
  if (facet == 0) {
    status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: STL file has no facet", label);
    goto done;
  }
  TL_CHECK_GOTO(status, corners_to_mesh(&c, name, m), done);
done:
  tl_free(&c.corner);
  return status;
}

/* ASCII when it begins with "solid" and its first kilobyte is text. */
static int stl_looks_ascii(const unsigned char *d, size_t size)
{
  size_t i = 0;
  while (i < size && (d[i] == ' ' || d[i] == '\t' || d[i] == '\r' || d[i] == '\n')) ++i;
  if (size - i < 5 || memcmp(d + i, "solid", 5) != 0) return 0;
  for (size_t k = 0; k < size && k < 1024; ++k)
    if (d[k] == 0 || (d[k] < 32 && d[k] != '\n' && d[k] != '\r' && d[k] != '\t') || d[k] >= 127) return 0;
  return 1;
}

TlStatus tl_stl_read_memory(const void *data, size_t size, const char *label, TlSurfaceMesh **m)
{
  if (!m) TL_ERROR(TL_ERR_ARG, "tl_stl_read_memory: NULL output");
  *m = NULL;
  if (!data && size) TL_ERROR(TL_ERR_ARG, "tl_stl_read_memory: NULL data of %zu bytes", size);
  if (!label) label = "STL";
  const unsigned char *d = data;
  if (size == 0) TL_ERROR(TL_ERR_FORMAT, "%s: empty STL file", label);
  int binary = !stl_looks_ascii(d, size);
  if (size >= 84 && 84 + 50 * (size_t)le32(d + 80) == size) binary = 1;
  if (binary) TL_CHECK(stl_read_binary(d, size, label, m));
  else TL_CHECK(stl_read_ascii((const char *)d, size, label, m));
  return TL_OK;
}

typedef TlStatus (*SurfaceReader)(const void *data, size_t size, const char *label, TlSurfaceMesh **m);

/* A Gmsh file or an STL one, told apart by content. */
static TlStatus surface_read_memory(const void *data, size_t size, const char *label, TlSurfaceMesh **m)
{
  const char *c = data;
  size_t i = 0;
  while (i < size && (c[i] == ' ' || c[i] == '\n' || c[i] == '\r' || c[i] == '\t')) ++i;
  if (size - i >= 11 && memcmp(c + i, "$MeshFormat", 11) == 0) return tl_gmsh_surface_read_memory(data, size, label, m);
  return tl_stl_read_memory(data, size, label, m);
}

/* The whole file into memory, then read by `reader` under its path. */
static TlStatus read_path(const char *path, TlSurfaceMesh **m, const char *caller, SurfaceReader reader)
{
  if (!path || !m) TL_ERROR(TL_ERR_ARG, "%s: NULL path or output", caller);
  char *data = NULL;
  size_t size = 0;
  TL_CHECK(read_file(path, &data, &size));
  TlStatus status = reader(data, size, path, m);
  tl_free(&data);
  if (status != TL_OK) return tl_error_trace(status, __FILE__, __LINE__);
  return TL_OK;
}

TlStatus tl_stl_read(const char *path, TlSurfaceMesh **m)
{
  return read_path(path, m, "tl_stl_read", tl_stl_read_memory);
}

TlStatus tl_surface_mesh_read(const char *path, TlSurfaceMesh **m)
{
  return read_path(path, m, "tl_surface_mesh_read", surface_read_memory);
}

TlStatus tl_gmsh_surface_read(const char *path, TlSurfaceMesh **m)
{
  return read_path(path, m, "tl_gmsh_surface_read", tl_gmsh_surface_read_memory);
}

/* ------------------------------------------------------------ writing */

static void put32(unsigned char *p, uint32_t u)
{
  p[0] = (unsigned char)u, p[1] = (unsigned char)(u >> 8), p[2] = (unsigned char)(u >> 16), p[3] = (unsigned char)(u >> 24);
}

static void putfloat(unsigned char *p, double v)
{
  float f = (float)v;
  uint32_t u;
  memcpy(&u, &f, sizeof u);
  put32(p, u);
}

TlStatus tl_stl_write(const char *path, const TlSurfaceMesh *m, int binary)
{
  if (!path || !m) TL_ERROR(TL_ERR_ARG, "tl_stl_write: NULL path or mesh");
  if (m->n_triangles > UINT32_MAX) TL_ERROR(TL_ERR_ARG, "%zu triangles exceed the STL limit %u", m->n_triangles, UINT32_MAX);
  FILE *f = fopen(path, binary ? "wb" : "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write STL file '%s': %s", path, strerror(errno));
  int ok = 1;
  const char *name = m->name[0] ? m->name : "talus";
  if (binary) {
    unsigned char head[84] = {0};
    snprintf((char *)head, 80, "binary %s", name); /* never "solid": readers would take it for ASCII */
    put32(head + 80, (uint32_t)m->n_triangles);
    ok = fwrite(head, 1, 84, f) == 84;
  } else {
    ok = fprintf(f, "solid %s\n", name) > 0;
  }
  for (size_t t = 0; ok && t < m->n_triangles; ++t) {
    TlVec3 a = m->x[m->tri[t][0]], b = m->x[m->tri[t][1]], c = m->x[m->tri[t][2]];
    TlVec3 n = tl_v3_cross(tl_v3_sub(b, a), tl_v3_sub(c, a));
    double len = tl_v3_norm(n);
    n = len > 0.0 ? tl_v3_scale(n, 1.0 / len) : tl_v3(0, 0, 0);
    if (binary) {
      unsigned char rec[50] = {0};
      TlVec3 v[4] = {n, a, b, c};
      for (int k = 0; k < 4; ++k) {
        putfloat(rec + 12 * k, v[k].x);
        putfloat(rec + 12 * k + 4, v[k].y);
        putfloat(rec + 12 * k + 8, v[k].z);
      }
      ok = fwrite(rec, 1, 50, f) == 50;
    } else {
      ok = fprintf(f, " facet normal %.9g %.9g %.9g\n  outer loop\n   vertex %.17g %.17g %.17g\n   vertex %.17g %.17g "
                      "%.17g\n   vertex %.17g %.17g %.17g\n  endloop\n endfacet\n",
                   n.x, n.y, n.z, a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z) > 0;
    }
  }
  if (ok && !binary) ok = fprintf(f, "endsolid %s\n", name) > 0;
  if (fclose(f) != 0) ok = 0;
  if (!ok) TL_ERROR(TL_ERR_IO, "error writing STL file '%s'", path);
  return TL_OK;
}
