/* The HDF5 + XDMF pairs written by the particle and mesh writers: the .xmf
 * is well-formed XML, every HDF reference points at an existing dataset of
 * the stated dimensions and type, attribute sizes match their grid; and
 * h5dump (Debian's hdf5-tools) opens the HDF5 files and shows the layout
 * documented in docs/output.md.  Without h5dump the test ends with ctest's
 * skip code after the other checks (a skip, not a pass). */
#include <ctype.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_hdf5_util.h"
#include "tl_io.h"
#include "tl_test.h"

/* ------------------------------------------------------------ a small XML checker */
enum { MAX_DEPTH = 32, MAX_ATTRS = 16 };

typedef struct {
  char name[64];
  int n_attrs;
  char keys[MAX_ATTRS][64], values[MAX_ATTRS][256];
} Tag;

typedef struct {
  const char *dir; /* folder of the .xmf */
  Tag stack[MAX_DEPTH];
  int depth;
  int data_items, grids_with_time, uniform_grids, errors;
  /* state of the current uniform grid */
  long points, cells;
  int time_seen[MAX_DEPTH];
} Checker;

static const char *attr(const Tag *t, const char *key)
{
  for (int i = 0; i < t->n_attrs; ++i)
    if (strcmp(t->keys[i], key) == 0) return t->values[i];
  return NULL;
}

#define XML_FAIL(c, ...)                                                                                               \
  do {                                                                                                                 \
    ++(c)->errors;                                                                                                     \
    TL_TEST_ASSERT(0, __VA_ARGS__);                                                                                    \
  } while (0)

/* Checks a DataItem's HDF reference against the file; returns its first dimension. */
static long check_data_item(Checker *c, const Tag *item, const char *text)
{
  c->data_items++;
  const char *format = attr(item, "Format"), *dims_s = attr(item, "Dimensions"), *type = attr(item, "NumberType"),
             *prec = attr(item, "Precision");
  if (!format || strcmp(format, "HDF") != 0 || !dims_s || !type || !prec) {
    XML_FAIL(c, "DataItem lacks Format=HDF, Dimensions, NumberType or Precision");
    return -1;
  }
  long dims[4];
  int rank = 0;
  for (const char *p = dims_s; *p && rank < 4;) {
    char *end;
    dims[rank++] = strtol(p, &end, 10);
    if (end == p) break;
    p = end;
  }
  while (isspace((unsigned char)*text)) ++text;
  char ref[512];
  snprintf(ref, sizeof ref, "%s", text);
  for (size_t n = strlen(ref); n > 0 && isspace((unsigned char)ref[n - 1]); --n) ref[n - 1] = '\0';
  char *colon = strchr(ref, ':');
  if (!colon) {
    XML_FAIL(c, "HDF reference '%s' has no ':'", ref);
    return -1;
  }
  *colon = '\0';
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", c->dir, ref);
  TlH5File f;
  if (tl_h5_open(path, &f) != TL_OK) {
    XML_FAIL(c, "referenced file %s does not open: %s", path, tl_error_message());
    return -1;
  }
  int r;
  hsize_t have[TL_H5_MAX_RANK];
  if (tl_h5_dims(&f, colon + 1, &r, have) != TL_OK) {
    XML_FAIL(c, "%s", tl_error_message());
  } else {
    int same = r == rank;
    for (int i = 0; same && i < r; ++i) same = (long)have[i] == dims[i];
    if (!same) XML_FAIL(c, "%s:%s has rank %d, XDMF says Dimensions=\"%s\"", path, colon + 1, r, dims_s);
    hid_t d = H5Dopen2(f.id, colon + 1, H5P_DEFAULT);
    hid_t t = H5Dget_type(d);
    H5T_class_t cls = H5Tget_class(t);
    size_t size = H5Tget_size(t);
    H5Tclose(t);
    H5Dclose(d);
    int want_float = strcmp(type, "Float") == 0;
    if ((want_float ? cls != H5T_FLOAT : cls != H5T_INTEGER) || (long)size != atol(prec))
      XML_FAIL(c, "%s:%s is of class %d size %zu, XDMF says %s/%s", path, colon + 1, (int)cls, size, type, prec);
  }
  tl_h5_close(&f);
  return dims[0];
}

static void check_xmf(const char *dir, const char *name, int *steps)
{
  char path[512];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  char *xml = tl_test_read_file(path);
  TL_TEST_ASSERT(xml != NULL, "cannot read %s", path);
  if (!xml) return;
  Checker c = {.dir = dir};
  const char *p = xml, *text_start = NULL;
  int saw_root = 0;
  *steps = 0;
  while (*p) {
    if (*p != '<') {
      if (*p == '&' || *p == '>') XML_FAIL(&c, "unescaped '%c' in text at offset %ld", *p, (long)(p - xml));
      ++p;
      continue;
    }
    if (strncmp(p, "<?", 2) == 0 || strncmp(p, "<!", 2) == 0) {
      const char *e = strchr(p, '>');
      if (!e) break;
      p = e + 1;
      continue;
    }
    if (p[1] == '/') { /* closing tag */
      const char *e = strchr(p, '>');
      char nm[64] = {0};
      size_t len = e ? (size_t)(e - p - 2) : 0;
      if (!e || len >= sizeof nm) {
        XML_FAIL(&c, "broken closing tag");
        break;
      }
      memcpy(nm, p + 2, len);
      if (c.depth == 0 || strcmp(c.stack[c.depth - 1].name, nm) != 0) {
        XML_FAIL(&c, "closing </%s> does not match <%s>", nm, c.depth ? c.stack[c.depth - 1].name : "(none)");
        break;
      }
      Tag *t = &c.stack[c.depth - 1];
      if (strcmp(nm, "DataItem") == 0 && text_start) {
        char text[600] = {0};
        snprintf(text, sizeof text, "%.*s", (int)(p - text_start), text_start);
        long first = check_data_item(&c, t, text);
        const Tag *parent = c.depth >= 2 ? &c.stack[c.depth - 2] : NULL;
        if (parent && strcmp(parent->name, "Geometry") == 0) c.points = first;
        if (parent && strcmp(parent->name, "Attribute") == 0) {
          const char *center = attr(parent, "Center");
          long want = center && strcmp(center, "Cell") == 0 ? c.cells : c.points;
          TL_TEST_ASSERT(first == want, "attribute %s has %ld rows, its grid has %ld %s", attr(parent, "Name"), first, want,
                         center ? center : "?");
        }
      }
      if (strcmp(nm, "Grid") == 0) c.time_seen[c.depth - 1] = 0;
      text_start = NULL;
      c.depth--;
      p = e + 1;
      continue;
    }
    /* opening tag */
    Tag t = {0};
    const char *q = p + 1;
    size_t k = 0;
    while (*q && !isspace((unsigned char)*q) && *q != '>' && *q != '/' && k < sizeof t.name - 1) t.name[k++] = *q++;
    for (;;) {
      while (isspace((unsigned char)*q)) ++q;
      if (*q == '>' || (q[0] == '/' && q[1] == '>') || !*q) break;
      if (t.n_attrs == MAX_ATTRS) {
        XML_FAIL(&c, "too many attributes on <%s>", t.name);
        break;
      }
      const char *eq = strchr(q, '=');
      if (!eq || eq[1] != '"') {
        XML_FAIL(&c, "attribute without a quoted value in <%s>", t.name);
        break;
      }
      snprintf(t.keys[t.n_attrs], sizeof t.keys[0], "%.*s", (int)(eq - q), q);
      const char *close = strchr(eq + 2, '"');
      if (!close) {
        XML_FAIL(&c, "unterminated attribute value in <%s>", t.name);
        break;
      }
      snprintf(t.values[t.n_attrs], sizeof t.values[0], "%.*s", (int)(close - eq - 2), eq + 2);
      if (strpbrk(t.values[t.n_attrs], "<&")) XML_FAIL(&c, "unescaped character in attribute of <%s>", t.name);
      t.n_attrs++;
      q = close + 1;
    }
    int self_closing = q[0] == '/';
    const char *e = strchr(q, '>');
    if (!e) {
      XML_FAIL(&c, "unterminated tag <%s>", t.name);
      break;
    }
    if (c.depth == 0) {
      TL_TEST_ASSERT(!saw_root && strcmp(t.name, "Xdmf") == 0, "root element <%s>", t.name);
      saw_root = 1;
    }
    if (strcmp(t.name, "Time") == 0) {
      TL_TEST_ASSERT(c.depth > 0 && strcmp(c.stack[c.depth - 1].name, "Grid") == 0, "<Time> outside a grid");
      if (c.depth > 0) c.time_seen[c.depth - 1] = 1;
      c.grids_with_time++;
    }
    if (strcmp(t.name, "Topology") == 0) {
      const char *ne = attr(&t, "NumberOfElements");
      c.cells = ne ? atol(ne) : -1;
    }
    if (strcmp(t.name, "Grid") == 0) {
      const char *type = attr(&t, "GridType");
      if (type && strcmp(type, "Uniform") == 0) c.uniform_grids++;
      /* a direct child of the temporal collection is one step */
      if (c.depth >= 1 && attr(&c.stack[c.depth - 1], "CollectionType") &&
          strcmp(attr(&c.stack[c.depth - 1], "CollectionType"), "Temporal") == 0)
        (*steps)++;
    }
    if (!self_closing) {
      if (c.depth == MAX_DEPTH) {
        XML_FAIL(&c, "nesting deeper than %d", MAX_DEPTH);
        break;
      }
      c.stack[c.depth++] = t;
      text_start = e + 1;
    }
    p = e + 1;
  }
  TL_TEST_ASSERT(c.depth == 0, "%s: %d elements left open", name, c.depth);
  TL_TEST_ASSERT(saw_root, "%s: no <Xdmf> root", name);
  TL_TEST_ASSERT(c.errors == 0, "%s: %d XML errors", name, c.errors);
  TL_TEST_ASSERT(c.grids_with_time == *steps, "%s: %d <Time> for %d steps", name, c.grids_with_time, *steps);
  TL_TEST_ASSERT(c.data_items > 0, "%s: no data items", name);
  free(xml);
}

/* ------------------------------------------------------------ h5dump */
static int have_h5dump(void)
{
  FILE *p = popen("command -v h5dump 2>/dev/null", "r");
  char buf[512] = {0};
  int ok = p && fgets(buf, sizeof buf, p) && buf[0] == '/';
  if (p) pclose(p);
  return ok;
}

/* Runs h5dump -H and flattens its output to lines "path (dims)" for
 * datasets and "path@attribute" for attributes, in `out`. */
static int h5dump_structure(const char *file, char *out, size_t cap)
{
  char cmd[600];
  snprintf(cmd, sizeof cmd, "h5dump -H %s 2>&1", file);
  FILE *p = popen(cmd, "r");
  if (!p) return -1;
  char line[1024], stack[16][600];
  int kind[16], depth = 0; /* kind: 0 group, 1 dataset, 2 attribute, 3 other */
  size_t used = 0;
  out[0] = '\0';
  while (fgets(line, sizeof line, p)) {
    char *s = line;
    while (isspace((unsigned char)*s)) ++s;
    size_t n = strlen(s);
    while (n > 0 && isspace((unsigned char)s[n - 1])) s[--n] = '\0';
    if (strcmp(s, "}") == 0) {
      if (depth > 0) --depth;
      continue;
    }
    if (n > 0 && s[n - 1] == '{' && depth < 16) {
      char name[256] = "";
      const char *q1 = strchr(s, '"'), *q2 = q1 ? strchr(q1 + 1, '"') : NULL;
      if (q1 && q2) snprintf(name, sizeof name, "%.*s", (int)(q2 - q1 - 1), q1 + 1);
      int k = strncmp(s, "GROUP", 5) == 0 ? 0 : strncmp(s, "DATASET", 7) == 0 ? 1 : strncmp(s, "ATTRIBUTE", 9) == 0 ? 2 : 3;
      char parent[600] = "";
      if (depth > 0) memcpy(parent, stack[depth - 1], sizeof parent);
      int len = 0;
      if (k == 0 && strcmp(name, "/") == 0)
        stack[depth][0] = '\0';
      else if (k <= 1)
        len = snprintf(stack[depth], sizeof stack[0], "%s/%s", parent, name);
      else
        len = snprintf(stack[depth], sizeof stack[0], "%s", parent);
      if (len < 0 || (size_t)len >= sizeof stack[0]) return -1; /* a path longer than any we write */
      if (k == 2) used += (size_t)snprintf(out + used, cap - used, "%s@%s\n", parent[0] ? parent : "/", name);
      kind[depth++] = k;
      continue;
    }
    if (depth > 0 && kind[depth - 1] == 1 && strncmp(s, "DATASPACE", 9) == 0) {
      const char *open = strchr(s, '('), *close = open ? strchr(open, ')') : NULL;
      char dims[128] = "scalar";
      if (open && close) snprintf(dims, sizeof dims, "%.*s", (int)(close - open + 1), open);
      used += (size_t)snprintf(out + used, cap - used, "%s %s\n", stack[depth - 1], dims);
    }
    if (used >= cap) break;
  }
  return pclose(p);
}

static int count_lines(const char *s)
{
  int n = 0;
  for (; *s; ++s) n += *s == '\n';
  return n;
}

static void expect_structure(const char *file, const char *const *expected, int n_expected, int n_datasets)
{
  char got[8192];
  int rc = h5dump_structure(file, got, sizeof got);
  TL_TEST_ASSERT(rc == 0, "h5dump -H %s exited with %d:\n%s", file, rc, got);
  for (int i = 0; i < n_expected; ++i) {
    char line[300];
    snprintf(line, sizeof line, "%s\n", expected[i]);
    TL_TEST_ASSERT(strstr(got, line) != NULL, "h5dump of %s lacks '%s'; it shows:\n%s", file, expected[i], got);
  }
  int datasets = 0;
  for (const char *s = got; *s;) {
    const char *e = strchr(s, '\n');
    if (!memchr(s, '@', (size_t)(e - s))) ++datasets;
    s = e + 1;
  }
  TL_TEST_ASSERT(datasets == n_datasets, "%s has %d datasets, expected %d (of %d lines):\n%s", file, datasets, n_datasets,
                 count_lines(got), got);
}

/* A long series may defer rewriting its sidecar, but flush and destroy write
 * every step added. */
static void test_long_series(void)
{
  static char grid[300000];
  TlXdmfSeries *s;
  TL_TEST_STATUS(tl_xdmf_series_create("long.xmf", &s), TL_OK);
  if (!s) return;
  for (int k = 0; k < 12; ++k) {
    int n = snprintf(grid, sizeof grid, "      <Grid Name=\"g%d\" GridType=\"Uniform\">\n        <Time Value=\"%d\"/>\n", k, k);
    memset(grid + n, ' ', sizeof grid - (size_t)n - 40);
    snprintf(grid + sizeof grid - 40, 40, "\n      </Grid>\n");
    TL_TEST_STATUS(tl_xdmf_series_add(s, grid), TL_OK);
  }
  TL_TEST_ASSERT(tl_xdmf_series_steps(s) == 12, "%zu steps", tl_xdmf_series_steps(s));
  TL_TEST_STATUS(tl_xdmf_series_flush(s), TL_OK);
  char *text = tl_test_read_file("long.xmf");
  TL_TEST_ASSERT(text && strstr(text, "<Grid Name=\"g11\"") && strstr(text, "</Xdmf>"), "flush lost steps");
  free(text);
  TL_TEST_STATUS(tl_xdmf_series_add(s, grid), TL_OK);
  tl_xdmf_series_destroy(&s);
  text = tl_test_read_file("long.xmf");
  int count = 0;
  for (const char *p = text; p && (p = strstr(p, "<Time Value=")); ++p) ++count;
  TL_TEST_ASSERT(count == 13, "destroy left %d of 13 steps in the file", count);
  free(text);
}

int main(void)
{
  test_long_series();
  /* a particle series with every optional array and two extra fields */
  enum { N = 5 };
  TlVec3 x[N], v[N];
  double r[N], s6[6 * N], phi[N];
  int sp[N];
  for (int i = 0; i < N; ++i) {
    x[i] = tl_v3(i, 2.0 * i, -i);
    v[i] = tl_v3(0.1 * i, 0, 0);
    r[i] = 0.5 + 0.01 * i;
    sp[i] = i % 2;
    phi[i] = i;
    for (int k = 0; k < 6; ++k) s6[6 * i + k] = k;
  }
  TlField pf[2] = {{"overlap", 1, phi}, {"stress", 6, s6}};
  TlParticleView pv = {.n = N, .position = x, .radius = r, .velocity = v, .angular_velocity = v, .force = v,
                       .torque = v, .species = sp, .n_fields = 2, .fields = pf};
  TlParticleWriter *pw;
  TL_TEST_STATUS(tl_particle_writer_create("out", "grains", &pw), TL_OK);
  for (int k = 0; pw && k < 3; ++k) TL_TEST_STATUS(tl_particle_writer_write(pw, k, 0.1 * k, &pv), TL_OK);
  tl_particle_writer_destroy(&pw);

  /* a mesh series with two blocks (hex27 and tri6) */
  TlVec3 nodes[30];
  for (int i = 0; i < 30; ++i) nodes[i] = tl_v3(i % 3, (i / 3) % 3, i / 9);
  int hex[27], tri[6] = {27, 28, 29, 0, 1, 2};
  for (int i = 0; i < 27; ++i) hex[i] = i;
  double tnode[30], tcell[9];
  for (int i = 0; i < 30; ++i) tnode[i] = i;
  for (int i = 0; i < 9; ++i) tcell[i] = i;
  TlField nf[1] = {{"temperature", 1, tnode}};
  TlField cf[1] = {{"stress", 9, tcell}};
  TlMeshBlock blocks[2] = {{"body", TL_CELL_HEX27, 1, hex, 1, cf}, {"skin", TL_CELL_TRI6, 1, tri, 0, NULL}};
  TlMeshView mv = {.n_nodes = 30, .reference = nodes, .displacement = nodes, .n_node_fields = 1, .node_fields = nf,
                   .n_blocks = 2, .blocks = blocks};
  TlMeshWriter *mw;
  TL_TEST_STATUS(tl_mesh_writer_create("out", "solid", &mw), TL_OK);
  for (int k = 0; mw && k < 2; ++k) TL_TEST_STATUS(tl_mesh_writer_write(mw, k, 0.5 * k, &mv), TL_OK);
  tl_mesh_writer_destroy(&mw);

  int steps = 0;
  check_xmf("out", "grains.xmf", &steps);
  TL_TEST_ASSERT(steps == 3, "grains.xmf lists %d steps, expected 3", steps);
  check_xmf("out", "solid.xmf", &steps);
  TL_TEST_ASSERT(steps == 2, "solid.xmf lists %d steps, expected 2", steps);

  if (!have_h5dump()) {
    return tl_test_skip("h5dump structure check (h5dump not found on PATH; install Debian's hdf5-tools)");
  }
  static const char *const particles[] = {
      "/@format", "/@format_version", "/@step", "/@time",
      "/particles/position ( 5, 3 )", "/particles/radius ( 5 )", "/particles/vertices ( 5 )", "/particles/velocity ( 5, 3 )",
      "/particles/angular_velocity ( 5, 3 )", "/particles/force ( 5, 3 )", "/particles/torque ( 5, 3 )",
      "/particles/species ( 5 )", "/particles/fields@names", "/particles/fields/overlap ( 5 )",
      "/particles/fields/stress ( 5, 6 )"};
  expect_structure("out/grains_000002.h5", particles, sizeof particles / sizeof *particles, 10);
  static const char *const mesh[] = {
      "/@format", "/@format_version", "/mesh/reference_coordinates ( 30, 3 )", "/mesh/blocks@names",
      "/mesh/blocks/body@cell_type", "/mesh/blocks/body/connectivity ( 1, 27 )", "/mesh/blocks/skin/connectivity ( 1, 6 )"};
  expect_structure("out/solid_mesh_0000.h5", mesh, sizeof mesh / sizeof *mesh, 3);
  static const char *const step[] = {
      "/@format", "/@time", "/@step", "/@mesh_file", "/mesh/displacement ( 30, 3 )", "/mesh/node_fields@names",
      "/mesh/node_fields/temperature ( 30 )", "/mesh/blocks/body/cell_fields/stress ( 1, 9 )"};
  expect_structure("out/solid_000001.h5", step, sizeof step / sizeof *step, 3);
  return tl_test_report();
}
