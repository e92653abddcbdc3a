/* Reader of Gmsh .msh files, formats 4.1 and 2.2, ASCII and binary:
 * sections $MeshFormat, $PhysicalNames, $Entities (4.1), $Nodes and
 * $Elements; other sections are skipped.  Every error names the file, the
 * line (ASCII) or the byte offset (binary) and what was expected.
 *
 * One reading path per format version: the numbers of a 4.1 file are read
 * through num_int / num_size / num_real, which take a token in an ASCII
 * file and the next 4 (int), data-size (size_t) or 8 (double) bytes in a
 * binary one, so the ASCII and binary layouts share their code.  In 2.2 the
 * physical group is a tag of each element; it stands in for the entity of
 * 4.1 (one synthetic entity per physical group and dimension), so both
 * versions build the mesh through the same code. */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_mesh.h"
#include "tl_mesh_gmsh_private.h"

typedef struct {
  const char *path;
  char *buf;
  size_t pos, len;
  int line;
  char tok[256];
  int tok_line;
  int binary;      /* the data of the current section are binary */
  int size_bytes;  /* size of size_t in a binary file (4 or 8) */
  int swap;        /* binary file of the other byte order */
} Reader;

/* The next whitespace-separated token (a quoted string counts as one);
 * 0 at the end of the file. */
static int next_token(Reader *r)
{
  while (r->pos < r->len && isspace((unsigned char)r->buf[r->pos])) {
    if (r->buf[r->pos] == '\n') r->line++;
    r->pos++;
  }
  if (r->pos >= r->len) return 0;
  r->tok_line = r->line;
  size_t k = 0;
  if (r->buf[r->pos] == '"') {
    r->pos++;
    while (r->pos < r->len && r->buf[r->pos] != '"' && r->buf[r->pos] != '\n') {
      if (k + 1 < sizeof r->tok) r->tok[k++] = r->buf[r->pos];
      r->pos++;
    }
    if (r->pos < r->len && r->buf[r->pos] == '"') r->pos++;
  } else {
    while (r->pos < r->len && !isspace((unsigned char)r->buf[r->pos])) {
      if (k + 1 < sizeof r->tok) r->tok[k++] = r->buf[r->pos];
      r->pos++;
    }
  }
  r->tok[k] = '\0';
  return 1;
}

static TlStatus read_long(Reader *r, const char *what, long lo, long hi, long *v)
{
  if (!next_token(r))
    TL_ERROR(TL_ERR_FORMAT, "%s line %d: unexpected end of file, expected %s", r->path, r->line,
             what);
  char *end = NULL;
  errno = 0;
  long value = strtol(r->tok, &end, 10);
  if (errno || !end || *end)
    TL_ERROR(TL_ERR_FORMAT, "%s line %d: expected an integer (%s), found '%s'", r->path,
             r->tok_line, what, r->tok);
  if (value < lo || value > hi)
    TL_ERROR(TL_ERR_FORMAT, "%s line %d: %s = %ld outside [%ld, %ld]", r->path, r->tok_line, what,
             value, lo, hi);
  *v = value;
  return TL_OK;
}

static TlStatus read_double(Reader *r, const char *what, double *v)
{
  if (!next_token(r))
    TL_ERROR(TL_ERR_FORMAT, "%s line %d: unexpected end of file, expected %s", r->path, r->line,
             what);
  char *end = NULL;
  errno = 0;
  double value = strtod(r->tok, &end);
  if (errno || !end || *end || !isfinite(value))
    TL_ERROR(TL_ERR_FORMAT, "%s line %d: expected a real number (%s), found '%s'", r->path,
             r->tok_line, what, r->tok);
  *v = value;
  return TL_OK;
}

static TlStatus expect(Reader *r, const char *word)
{
  if (!next_token(r))
    TL_ERROR(TL_ERR_FORMAT, "%s line %d: unexpected end of file, expected %s", r->path, r->line,
             word);
  if (strcmp(r->tok, word))
    TL_ERROR(TL_ERR_FORMAT, "%s line %d: expected %s, found '%s'", r->path, r->tok_line, word,
             r->tok);
  return TL_OK;
}

/* ---- binary data */

/* The newline that ends a section header or a count line before binary
 * data. */
static void skip_eol(Reader *r)
{
  if (r->pos < r->len && r->buf[r->pos] == '\r') r->pos++;
  if (r->pos < r->len && r->buf[r->pos] == '\n') {
    r->pos++;
    r->line++;
  }
}

static TlStatus raw_bytes(Reader *r, const char *what, void *out, size_t n)
{
  if (r->len - r->pos < n)
    TL_ERROR(TL_ERR_FORMAT, "%s byte %zu: the file ends inside %s (%zu bytes needed, %zu left)", r->path, r->pos,
             what, n, r->len - r->pos);
  unsigned char *o = out;
  memcpy(o, r->buf + r->pos, n);
  if (r->swap)
    for (size_t i = 0; i < n / 2; ++i) {
      unsigned char t = o[i];
      o[i] = o[n - 1 - i];
      o[n - 1 - i] = t;
    }
  r->pos += n;
  return TL_OK;
}

static TlStatus bin_check(Reader *r, size_t at, const char *what, long long v, long lo, long hi, long *out)
{
  if (v < lo || v > hi)
    TL_ERROR(TL_ERR_FORMAT, "%s byte %zu: %s = %lld outside [%ld, %ld]", r->path, at, what, v, lo, hi);
  *out = (long)v;
  return TL_OK;
}

/* An int: a token in ASCII, 4 bytes in binary. */
static TlStatus num_int(Reader *r, const char *what, long lo, long hi, long *v)
{
  if (!r->binary) return read_long(r, what, lo, hi, v);
  size_t at = r->pos;
  int32_t x = 0;
  TL_CHECK(raw_bytes(r, what, &x, sizeof x));
  return bin_check(r, at, what, x, lo, hi, v);
}

/* A size_t: a token in ASCII, the file's data size in binary. */
static TlStatus num_size(Reader *r, const char *what, long lo, long hi, long *v)
{
  if (!r->binary) return read_long(r, what, lo, hi, v);
  size_t at = r->pos;
  if (r->size_bytes == 4) {
    uint32_t x = 0;
    TL_CHECK(raw_bytes(r, what, &x, sizeof x));
    return bin_check(r, at, what, (long long)x, lo, hi, v);
  }
  uint64_t x = 0;
  TL_CHECK(raw_bytes(r, what, &x, sizeof x));
  if (x > (uint64_t)LLONG_MAX)
    TL_ERROR(TL_ERR_FORMAT, "%s byte %zu: %s = %llu is beyond any count", r->path, at, what, (unsigned long long)x);
  return bin_check(r, at, what, (long long)x, lo, hi, v);
}

static TlStatus num_real(Reader *r, const char *what, double *v)
{
  if (!r->binary) return read_double(r, what, v);
  size_t at = r->pos;
  TL_CHECK(raw_bytes(r, what, v, sizeof *v));
  if (!isfinite(*v)) TL_ERROR(TL_ERR_FORMAT, "%s byte %zu: %s is not a finite number", r->path, at, what);
  return TL_OK;
}



static void gmsh_free(GmshData *g)
{
  tl_free(&g->entities);
  tl_free(&g->names);
  tl_free(&g->node_tag_to_index);
  tl_free(&g->x);
  tl_free(&g->elements);
  tl_free(&g->element_nodes);
}

static TlStatus read_entities(Reader *r, GmshData *g)
{
  long count[4];
  for (int d = 0; d < 4; ++d) TL_CHECK(num_size(r, "number of entities", 0, 100000000, &count[d]));
  for (int d = 0; d < 4; ++d)
    for (long i = 0; i < count[d]; ++i) {
      long tag, nphys;
      double v;
      TL_CHECK(num_int(r, "entity tag", 1, LONG_MAX, &tag));
      for (int k = 0; k < (d == 0 ? 3 : 6); ++k) TL_CHECK(num_real(r, "bounding box", &v));
      TL_CHECK(num_size(r, "number of physical tags", 0, 1000000, &nphys));
      long phys = 0;
      for (long k = 0; k < nphys; ++k) {
        long p;
        TL_CHECK(num_int(r, "physical tag", LONG_MIN + 1, LONG_MAX, &p));
        if (k == 0) phys = labs(p);
      }
      if (d > 0) {
        long nb, b;
        TL_CHECK(num_size(r, "number of bounding entities", 0, 100000000, &nb));
        for (long k = 0; k < nb; ++k) TL_CHECK(num_int(r, "bounding entity", LONG_MIN + 1, LONG_MAX, &b));
      }
      TL_CHECK(tl_array_reserve(&g->entities, &g->cap_entities, g->n_entities + 1, sizeof(Entity)));
      g->entities[g->n_entities++] = (Entity){d, tag, phys};
    }
  TL_CHECK(expect(r, "$EndEntities"));
  return TL_OK;
}

/* Bytes left in the file: a count announced in a header cannot exceed what
 * the rest of the file can hold (each item takes at least two bytes), so a
 * corrupt header is refused before it sizes an allocation. */
static long bytes_left(const Reader *r) { return (long)(r->len - r->pos); }

static TlStatus read_nodes(Reader *r, GmshData *g)
{
  long nblocks, nnodes, min_tag, max_tag;
  TL_CHECK(num_size(r, "number of node blocks", 0, 100000000, &nblocks));
  TL_CHECK(num_size(r, "number of nodes", 0, bytes_left(r) / 2, &nnodes));
  TL_CHECK(num_size(r, "smallest node tag", 0, LONG_MAX, &min_tag));
  TL_CHECK(num_size(r, "largest node tag", 0, 4 * (nnodes + 1000000L), &max_tag));
  TL_CHECK(tl_calloc(&g->node_tag_to_index, max_tag + 1, sizeof(long)));
  for (long t = 0; t <= max_tag; ++t) g->node_tag_to_index[t] = -1;
  g->max_node_tag = max_tag;
  TL_CHECK(tl_calloc(&g->x, 3 * (nnodes ? nnodes : 1), sizeof(double)));
  long *tags = NULL;
  size_t done = 0;
  TlStatus s = TL_OK;
  for (long b = 0; b < nblocks && s == TL_OK; ++b) {
    long edim, etag, parametric, n = 0;
    s = num_int(r, "entity dimension", 0, 3, &edim);
    if (s == TL_OK) s = num_int(r, "entity tag", LONG_MIN + 1, LONG_MAX, &etag);
    if (s == TL_OK) s = num_int(r, "parametric flag", 0, 1, &parametric);
    if (s == TL_OK) s = num_size(r, "nodes in block", 0, nnodes - (long)done, &n);
    if (s == TL_OK) s = tl_realloc(&tags, n ? n : 1, sizeof(long));
    for (long i = 0; i < n && s == TL_OK; ++i) {
      s = num_size(r, "node tag", 1, max_tag, &tags[i]);
      if (s == TL_OK && g->node_tag_to_index[tags[i]] >= 0)
        s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s line %d: node tag %ld defined twice",
                         r->path, r->tok_line, tags[i]);
      if (s == TL_OK) g->node_tag_to_index[tags[i]] = (long)(done + i);
    }
    for (long i = 0; i < n && s == TL_OK; ++i) {
      for (int k = 0; k < 3 && s == TL_OK; ++k) s = num_real(r, "node coordinate", &g->x[3 * (done + i) + k]);
      for (long k = 0; k < (parametric ? edim : 0) && s == TL_OK; ++k) {
        double u;
        s = num_real(r, "parametric coordinate", &u);
      }
    }
    if (s == TL_OK) done += n;
  }
  tl_free(&tags);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  if ((long)done != nnodes)
    TL_ERROR(TL_ERR_FORMAT, "%s line %d: the node blocks hold %zu nodes, the header announced %ld",
             r->path, r->line, done, nnodes);
  g->n_nodes = done;
  TL_CHECK(expect(r, "$EndNodes"));
  return TL_OK;
}

static TlStatus read_elements(Reader *r, GmshData *g)
{
  long nblocks, nel, min_tag, max_tag;
  TL_CHECK(num_size(r, "number of element blocks", 0, 100000000, &nblocks));
  TL_CHECK(num_size(r, "number of elements", 0, bytes_left(r) / 2, &nel));
  TL_CHECK(num_size(r, "smallest element tag", 0, LONG_MAX, &min_tag));
  TL_CHECK(num_size(r, "largest element tag", 0, LONG_MAX, &max_tag));
  TL_CHECK(tl_calloc(&g->elements, nel ? nel : 1, sizeof(RawElement)));
  size_t cap_nodes = 0;
  size_t done = 0;
  for (long b = 0; b < nblocks; ++b) {
    long edim, etag, gtype, n;
    TL_CHECK(num_int(r, "entity dimension", 0, 3, &edim));
    TL_CHECK(num_int(r, "entity tag", LONG_MIN + 1, LONG_MAX, &etag));
    TL_CHECK(num_int(r, "element type", 1, 1000, &gtype));
    int type_line = r->binary ? (int)(r->pos > INT_MAX ? INT_MAX : r->pos) : r->tok_line;
    TL_CHECK(num_size(r, "elements in block", 0, nel - (long)done, &n));
    /* Any registered element type, built in or not, by its Gmsh code;
     * type 15 is a point (node sets only). */
    const TlElementType *type = NULL;
    int nn = 1;
    if (gtype != 15) {
      if (tl_element_type_find_gmsh((int)gtype, &type) != TL_OK) {
        char why[512];
        snprintf(why, sizeof why, "%s", tl_error_message());
        TL_ERROR(TL_ERR_FORMAT, "%s line %d: Gmsh element type %ld is not supported: %s", r->path, type_line,
                 gtype, why);
      }
      nn = type->n_nodes;
      if (type->dim != edim)
        TL_ERROR(TL_ERR_FORMAT, "%s line %d: element type %ld (%s) in an entity of dimension %ld",
                 r->path, type_line, gtype, type->header.name, edim);
    }
    for (long i = 0; i < n; ++i) {
      RawElement *e = &g->elements[done + i];
      TL_CHECK(num_size(r, "element tag", 1, LONG_MAX, &e->tag));
      e->line = r->binary ? (int)(r->pos > INT_MAX ? INT_MAX : r->pos) : r->tok_line;
      e->dim = (int)edim;
      e->entity = etag;
      e->type = type;
      e->n_nodes = nn;
      e->first = g->n_element_nodes;
      TL_CHECK(tl_array_reserve(&g->element_nodes, &cap_nodes, g->n_element_nodes + nn, sizeof(long)));
      for (int k = 0; k < nn; ++k) {
        long t;
        if (!r->binary) {
          size_t pos = r->pos;
          int line = r->line;
          if (!next_token(r) || r->tok_line != e->line)
            TL_ERROR(TL_ERR_FORMAT, "%s line %d: element %ld has %d of %d nodes (%s)", r->path,
                     e->line, e->tag, k, nn, type ? type->header.name : "point");
          r->pos = pos, r->line = line; /* re-read the token as a number */
        }
        TL_CHECK(num_size(r, "node tag", LONG_MIN + 1, LONG_MAX, &t));
        if (t < 1 || t > g->max_node_tag || g->node_tag_to_index[t] < 0)
          TL_ERROR(TL_ERR_FORMAT, "%s line %d: element %ld refers to node %ld, which is not defined",
                   r->path, e->line, e->tag, t);
        g->element_nodes[g->n_element_nodes++] = t;
      }
    }
    done += n;
  }
  if ((long)done != nel)
    TL_ERROR(TL_ERR_FORMAT, "%s line %d: the element blocks hold %zu elements, the header announced %ld",
             r->path, r->line, done, nel);
  g->n_elements = done;
  TL_CHECK(expect(r, "$EndElements"));
  return TL_OK;
}

/* ---- format 2.2 */

/* The entity standing for a physical group of 2.2 (0: none). */
static TlStatus entity_of_phys(GmshData *g, int dim, long phys, long *entity)
{
  *entity = phys;
  if (phys == 0 || tl_gmsh_entity_phys(g, dim, phys) == phys) return TL_OK;
  TL_CHECK(tl_array_reserve(&g->entities, &g->cap_entities, g->n_entities + 1, sizeof(Entity)));
  g->entities[g->n_entities++] = (Entity){dim, phys, phys};
  return TL_OK;
}

/* $Nodes of 2.2: a count (ASCII), then "tag x y z" per node (binary: int
 * tag, three doubles). */
static TlStatus read_nodes_22(Reader *r, GmshData *g, int binary)
{
  long n;
  TL_CHECK(read_long(r, "number of nodes", 0, bytes_left(r) / (binary ? 28 : 8), &n));
  if (binary) skip_eol(r);
  r->binary = binary;
  long *tags = NULL;
  TlStatus s = tl_calloc(&tags, n ? n : 1, sizeof *tags);
  if (s == TL_OK) s = tl_calloc(&g->x, 3 * (n ? n : 1), sizeof(double));
  long max_tag = 0;
  for (long i = 0; i < n && s == TL_OK; ++i) {
    s = num_int(r, "node tag", 1, 4 * (n + 1000000L), &tags[i]);
    for (int k = 0; k < 3 && s == TL_OK; ++k) s = num_real(r, "node coordinate", &g->x[3 * i + k]);
    if (tags[i] > max_tag) max_tag = tags[i];
  }
  if (s == TL_OK) s = tl_calloc(&g->node_tag_to_index, max_tag + 1, sizeof(long));
  if (s == TL_OK) {
    for (long t = 0; t <= max_tag; ++t) g->node_tag_to_index[t] = -1;
    g->max_node_tag = max_tag;
    for (long i = 0; i < n && s == TL_OK; ++i) {
      if (g->node_tag_to_index[tags[i]] >= 0)
        s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: node tag %ld defined twice (node %ld of $Nodes)",
                         r->path, tags[i], i + 1);
      else
        g->node_tag_to_index[tags[i]] = i;
    }
  }
  tl_free(&tags);
  r->binary = 0;
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  g->n_nodes = (size_t)n;
  TL_CHECK(expect(r, "$EndNodes"));
  return TL_OK;
}

/* One element of 2.2 once its type and tags are known. */
static TlStatus add_element_22(Reader *r, GmshData *g, size_t *cap_nodes, long tag, long gtype, long ntags,
                               const long *etags, int at)
{
  const TlElementType *type = NULL;
  int nn = 1, dim = 0;
  if (gtype != 15) {
    if (tl_element_type_find_gmsh((int)gtype, &type) != TL_OK) {
      char why[512];
      snprintf(why, sizeof why, "%s", tl_error_message());
      TL_ERROR(TL_ERR_FORMAT, "%s line %d: Gmsh element type %ld is not supported: %s", r->path, at, gtype, why);
    }
    nn = type->n_nodes;
    dim = type->dim;
  }
  RawElement *e = &g->elements[g->n_elements];
  e->tag = tag;
  e->line = at;
  e->dim = dim;
  e->type = type;
  e->n_nodes = nn;
  e->first = g->n_element_nodes;
  TL_CHECK(entity_of_phys(g, dim, ntags > 0 ? labs(etags[0]) : 0, &e->entity));
  TL_CHECK(tl_array_reserve(&g->element_nodes, cap_nodes, g->n_element_nodes + nn, sizeof(long)));
  for (int k = 0; k < nn; ++k) {
    long t;
    if (!r->binary) {
      size_t pos = r->pos;
      int line = r->line;
      if (!next_token(r) || r->tok_line != at)
        TL_ERROR(TL_ERR_FORMAT, "%s line %d: element %ld has %d of %d nodes (%s)", r->path, at, tag, k, nn,
                 type ? type->header.name : "point");
      r->pos = pos, r->line = line;
    }
    TL_CHECK(num_int(r, "node tag", LONG_MIN + 1, LONG_MAX, &t));
    if (t < 1 || t > g->max_node_tag || g->node_tag_to_index[t] < 0)
      TL_ERROR(TL_ERR_FORMAT, "%s line %d: element %ld refers to node %ld, which is not defined", r->path, at, tag, t);
    g->element_nodes[g->n_element_nodes++] = t;
  }
  g->n_elements++;
  return TL_OK;
}

/* $Elements of 2.2: a count (ASCII), then "tag type ntags tags... nodes..."
 * per element; binary: blocks of a header (int type, count, ntags) and
 * `count` elements of int tag, ntags ints, the nodes as ints. */
static TlStatus read_elements_22(Reader *r, GmshData *g, int binary)
{
  long nel;
  TL_CHECK(read_long(r, "number of elements", 0, bytes_left(r) / 2, &nel));
  TL_CHECK(tl_calloc(&g->elements, nel ? nel : 1, sizeof(RawElement)));
  size_t cap_nodes = 0;
  long etags[64];
  TlStatus s = TL_OK;
  if (!binary) {
    for (long i = 0; i < nel && s == TL_OK; ++i) {
      long tag, gtype, ntags;
      s = read_long(r, "element tag", 1, LONG_MAX, &tag);
      int at = r->tok_line;
      if (s == TL_OK) s = read_long(r, "element type", 1, 1000, &gtype);
      if (s == TL_OK) s = read_long(r, "number of tags", 0, 64, &ntags);
      for (long k = 0; k < ntags && s == TL_OK; ++k) s = read_long(r, "element tag", LONG_MIN + 1, LONG_MAX, &etags[k]);
      if (s == TL_OK) s = add_element_22(r, g, &cap_nodes, tag, gtype, ntags, etags, at);
    }
  } else {
    skip_eol(r);
    r->binary = 1;
    long done = 0;
    while (done < nel && s == TL_OK) {
      long gtype, count, ntags;
      int at = (int)(r->pos > INT_MAX ? INT_MAX : r->pos);
      s = num_int(r, "element type", 1, 1000, &gtype);
      if (s == TL_OK) s = num_int(r, "elements in block", 1, nel - done, &count);
      if (s == TL_OK) s = num_int(r, "number of tags", 0, 64, &ntags);
      for (long i = 0; i < count && s == TL_OK; ++i) {
        long tag;
        s = num_int(r, "element tag", 1, LONG_MAX, &tag);
        for (long k = 0; k < ntags && s == TL_OK; ++k) s = num_int(r, "element tag", LONG_MIN + 1, LONG_MAX, &etags[k]);
        if (s == TL_OK) s = add_element_22(r, g, &cap_nodes, tag, gtype, ntags, etags, at);
      }
      done += count;
    }
    r->binary = 0;
  }
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  TL_CHECK(expect(r, "$EndElements"));
  return TL_OK;
}

static TlStatus parse(Reader *r, GmshData *g)
{
  int have_format = 0, have_nodes = 0, have_elements = 0, v2 = 0, binary = 0;
  while (next_token(r)) {
    if (r->tok[0] != '$')
      TL_ERROR(TL_ERR_FORMAT, "%s line %d: expected a section header ($Name), found '%s'", r->path,
               r->tok_line, r->tok);
    if (!strcmp(r->tok, "$MeshFormat")) {
      double version = 0.0;
      long ftype = 0, dsize = 0;
      TL_CHECK(read_double(r, "format version", &version));
      int vline = r->tok_line;
      TL_CHECK(read_long(r, "file type", 0, 1, &ftype));
      TL_CHECK(read_long(r, "data size", 1, 16, &dsize));
      v2 = version >= 1.95 && version < 2.25;
      if (!v2 && (version < 4.05 || version > 4.15))
        TL_ERROR(TL_ERR_FORMAT, "%s line %d: mesh format version %g is not supported, expected 4.1 or 2.2",
                 r->path, vline, version);
      binary = ftype == 1;
      if (binary) {
        if (dsize != 4 && dsize != 8)
          TL_ERROR(TL_ERR_FORMAT, "%s line %d: binary data size %ld (the size of size_t) is not 4 or 8",
                   r->path, vline, dsize);
        r->size_bytes = (int)dsize;
        /* the integer 1, which tells the byte order */
        skip_eol(r);
        size_t at = r->pos;
        int32_t one = 0;
        TL_CHECK(raw_bytes(r, "the byte-order integer", &one, sizeof one));
        if (one == 0x01000000)
          r->swap = 1;
        else if (one != 1)
          TL_ERROR(TL_ERR_FORMAT, "%s byte %zu: the byte-order integer reads %d, expected 1", r->path, at, (int)one);
      }
      TL_CHECK(expect(r, "$EndMeshFormat"));
      have_format = 1;
    } else if (!have_format) {
      TL_ERROR(TL_ERR_FORMAT, "%s line %d: section %s before $MeshFormat", r->path, r->tok_line,
               r->tok);
    } else if (!strcmp(r->tok, "$PhysicalNames")) {
      long n;
      TL_CHECK(read_long(r, "number of physical names", 0, 1000000, &n));
      for (long i = 0; i < n; ++i) {
        long dim, tag;
        TL_CHECK(read_long(r, "physical dimension", 0, 3, &dim));
        TL_CHECK(read_long(r, "physical tag", 1, LONG_MAX, &tag));
        if (!next_token(r))
          TL_ERROR(TL_ERR_FORMAT, "%s line %d: unexpected end of file in $PhysicalNames", r->path,
                   r->line);
        TL_CHECK(tl_array_reserve(&g->names, &g->cap_names, g->n_names + 1, sizeof(PhysName)));
        PhysName *p = &g->names[g->n_names++];
        p->dim = (int)dim;
        p->tag = tag;
        tl_gmsh_copy_name(p->name, r->tok);
      }
      TL_CHECK(expect(r, "$EndPhysicalNames"));
    } else if (!strcmp(r->tok, "$Entities")) {
      if (g->n_entities) TL_ERROR(TL_ERR_FORMAT, "%s line %d: a second $Entities section", r->path, r->tok_line);
      if (v2) TL_ERROR(TL_ERR_FORMAT, "%s line %d: an $Entities section in a 2.2 file", r->path, r->tok_line);
      if (binary) skip_eol(r);
      r->binary = binary;
      TlStatus se = read_entities(r, g);
      r->binary = 0;
      TL_CHECK(se);
    } else if (!strcmp(r->tok, "$Nodes")) {
      /* One node and one element section: a second would replace the node
       * numbering the elements already read refer to. */
      if (have_nodes) TL_ERROR(TL_ERR_FORMAT, "%s line %d: a second $Nodes section", r->path, r->tok_line);
      if (v2) {
        TL_CHECK(read_nodes_22(r, g, binary));
      } else {
        if (binary) skip_eol(r);
        r->binary = binary;
        TlStatus sn = read_nodes(r, g);
        r->binary = 0;
        TL_CHECK(sn);
      }
      have_nodes = 1;
    } else if (!strcmp(r->tok, "$Elements")) {
      if (!have_nodes)
        TL_ERROR(TL_ERR_FORMAT, "%s line %d: $Elements before $Nodes", r->path, r->tok_line);
      if (have_elements) TL_ERROR(TL_ERR_FORMAT, "%s line %d: a second $Elements section", r->path, r->tok_line);
      if (v2) {
        TL_CHECK(read_elements_22(r, g, binary));
      } else {
        if (binary) skip_eol(r);
        r->binary = binary;
        TlStatus sl = read_elements(r, g);
        r->binary = 0;
        TL_CHECK(sl);
      }
      have_elements = 1;
    } else {
      /* Skip an unknown section up to its $End line. */
      char end[300];
      snprintf(end, sizeof end, "$End%s", r->tok + 1);
      int start = r->tok_line;
      int found = 0;
      while (next_token(r))
        if (!strcmp(r->tok, end)) {
          found = 1;
          break;
        }
      if (!found)
        TL_ERROR(TL_ERR_FORMAT, "%s line %d: section opened here never closed (no %s)", r->path,
                 start, end);
    }
  }
  if (!have_format) TL_ERROR(TL_ERR_FORMAT, "%s: no $MeshFormat section (not a Gmsh file?)", r->path);
  if (!have_elements) TL_ERROR(TL_ERR_FORMAT, "%s: no $Elements section", r->path);
  return TL_OK;
}

TlStatus tl_mesh_read_gmsh(const char *path, TlMesh **mesh)
{
  if (!path || !mesh) TL_ERROR(TL_ERR_ARG, "tl_mesh_read_gmsh: NULL argument");
  FILE *f = fopen(path, "rb");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot open mesh file %s: %s", path, strerror(errno));
  Reader r = {.path = path, .line = 1};
  fseek(f, 0, SEEK_END);
  long size = ftell(f);
  fseek(f, 0, SEEK_SET);
  if (size < 0) {
    fclose(f);
    TL_ERROR(TL_ERR_IO, "cannot determine the size of %s", path);
  }
  TlStatus s = tl_calloc(&r.buf, (size_t)size + 1, 1);
  if (s != TL_OK) {
    fclose(f);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  r.len = fread(r.buf, 1, (size_t)size, f);
  fclose(f);
  GmshData g;
  memset(&g, 0, sizeof g);
  s = parse(&r, &g);
  if (s == TL_OK) s = tl_gmsh_build(r.path, &g, mesh);
  gmsh_free(&g);
  tl_free(&r.buf);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  return TL_OK;
}
