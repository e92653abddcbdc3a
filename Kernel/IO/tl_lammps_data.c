/* Reader of LAMMPS data files of spheres; see tl_lammps_data.h. */
#include "tl_lammps_data.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tl_memory.h"

enum { MAX_WORDS = 32 };

/* The state of one read: the file, the current line and its words. */
typedef struct {
  const char *path;
  FILE *file;
  char *line;      /* current line, cut into words in place */
  size_t line_cap;
  long line_no;    /* 1-based number of the current line */
  char *comment;   /* text after '#' on the current line, or NULL */
  int n_words;
  char *words[MAX_WORDS];
} Reader;

/* Reads the next line; *eof = 1 at the end of the file.  Cuts the comment
 * off and splits the rest into whitespace-separated words. */
static TlStatus next_line(Reader *r, int *eof)
{
  errno = 0;
  ssize_t len = getline(&r->line, &r->line_cap, r->file);
  if (len < 0) {
    if (ferror(r->file)) TL_ERROR(TL_ERR_IO, "%s: read error after line %ld", r->path, r->line_no);
    *eof = 1;
    return TL_OK;
  }
  *eof = 0;
  ++r->line_no;
  if ((size_t)len != strlen(r->line))
    TL_ERROR(TL_ERR_FORMAT, "%s:%ld: line contains a NUL byte (not a text data file?)", r->path, r->line_no);
  char *hash = strchr(r->line, '#');
  r->comment = NULL;
  if (hash) {
    *hash = '\0';
    r->comment = hash + 1;
    r->comment[strcspn(r->comment, "\r\n")] = '\0';
  }
  r->n_words = 0;
  char *save = NULL;
  for (char *w = strtok_r(r->line, " \t\r\n\f\v", &save); w; w = strtok_r(NULL, " \t\r\n\f\v", &save)) {
    if (r->n_words == MAX_WORDS)
      TL_ERROR(TL_ERR_FORMAT, "%s:%ld: more than %d values on one line", r->path, r->line_no, MAX_WORDS);
    r->words[r->n_words++] = w;
  }
  return TL_OK;
}

/* Next non-blank line; *eof = 1 when none is left. */
static TlStatus next_content_line(Reader *r, int *eof)
{
  do {
    TL_CHECK(next_line(r, eof));
  } while (!*eof && r->n_words == 0);
  return TL_OK;
}

static int parse_double(const char *s, double *value)
{
  char *end = NULL;
  errno = 0;
  double d = strtod(s, &end);
  /* ERANGE on underflow is no error: LAMMPS's write_data prints subnormal
   * velocities (2.02e-320) and strtod returns them exactly; an overflow
   * returns ±HUGE_VAL, refused as not finite */
  if (end == s || *end != '\0' || !isfinite(d) || (errno == ERANGE && fabs(d) >= 1.0)) return 0;
  *value = d;
  return 1;
}

static int parse_int64(const char *s, int64_t *value)
{
  char *end = NULL;
  errno = 0;
  long long v = strtoll(s, &end, 10);
  if (end == s || *end != '\0' || errno == ERANGE) return 0;
  *value = (int64_t)v;
  return 1;
}

/* Whether a word starts like a number (header lines begin with numbers,
 * section names with letters). */
static int looks_numeric(const char *s)
{
  if (*s == '+' || *s == '-') ++s;
  if (*s == '.') ++s;
  return *s >= '0' && *s <= '9';
}

/* Joins words[from..n_words) with single spaces into buf. */
static void join_words(const Reader *r, int from, char *buf, size_t cap)
{
  buf[0] = '\0';
  size_t used = 0;
  for (int k = from; k < r->n_words; ++k) {
    int wrote = snprintf(buf + used, cap - used, "%s%s", k > from ? " " : "", r->words[k]);
    if (wrote < 0 || (size_t)wrote >= cap - used) break;
    used += (size_t)wrote;
  }
}

/* Header counts that name how many lines a skipped section has. */
typedef struct {
  int64_t atoms, atom_types;
  int64_t bonds, angles, dihedrals, impropers;
  int64_t bond_types, angle_types, dihedral_types, improper_types;
  int64_t ellipsoids, lines, triangles, bodies;
} HeaderCounts;

/* Parses one header line (leading numbers, then a keyword). */
static TlStatus parse_header_line(Reader *r, HeaderCounts *hc, TlLammpsData *d)
{
  int n_num = 0;
  while (n_num < r->n_words && looks_numeric(r->words[n_num])) ++n_num;
  char key[128];
  join_words(r, n_num, key, sizeof key);

  if (!strcmp(key, "xlo xhi") || !strcmp(key, "ylo yhi") || !strcmp(key, "zlo zhi")) {
    int axis = key[0] - 'x';
    double lo, hi;
    if (n_num != 2 || !parse_double(r->words[0], &lo) || !parse_double(r->words[1], &hi))
      TL_ERROR(TL_ERR_FORMAT, "%s:%ld: expected two finite numbers before \"%s\"", r->path, r->line_no, key);
    if (!(lo < hi))
      TL_ERROR(TL_ERR_FORMAT, "%s:%ld: box bounds %s = %g %g: the low bound must be below the high one",
               r->path, r->line_no, key, lo, hi);
    d->lo[axis] = lo;
    d->hi[axis] = hi;
    return TL_OK;
  }
  if (!strcmp(key, "xy xz yz")) {
    if (n_num != 3)
      TL_ERROR(TL_ERR_FORMAT, "%s:%ld: expected three tilt factors before \"xy xz yz\"", r->path, r->line_no);
    for (int k = 0; k < 3; ++k)
      if (!parse_double(r->words[k], &d->tilt[k]))
        TL_ERROR(TL_ERR_FORMAT, "%s:%ld: tilt factor \"%s\" is not a finite number", r->path, r->line_no,
                 r->words[k]);
    d->triclinic = 1;
    return TL_OK;
  }

  static const struct { const char *key; size_t offset; } counts[] = {
    {"atoms", offsetof(HeaderCounts, atoms)},
    {"atom types", offsetof(HeaderCounts, atom_types)},
    {"bonds", offsetof(HeaderCounts, bonds)},
    {"angles", offsetof(HeaderCounts, angles)},
    {"dihedrals", offsetof(HeaderCounts, dihedrals)},
    {"impropers", offsetof(HeaderCounts, impropers)},
    {"bond types", offsetof(HeaderCounts, bond_types)},
    {"angle types", offsetof(HeaderCounts, angle_types)},
    {"dihedral types", offsetof(HeaderCounts, dihedral_types)},
    {"improper types", offsetof(HeaderCounts, improper_types)},
    {"ellipsoids", offsetof(HeaderCounts, ellipsoids)},
    {"lines", offsetof(HeaderCounts, lines)},
    {"triangles", offsetof(HeaderCounts, triangles)},
    {"bodies", offsetof(HeaderCounts, bodies)},
  };
  /* Counts that size nothing this reader keeps (per-atom extra slots). */
  static const char *ignored[] = {"extra bond per atom", "extra angle per atom", "extra dihedral per atom",
                                  "extra improper per atom", "extra special per atom"};
  for (size_t k = 0; k < sizeof counts / sizeof counts[0]; ++k) {
    if (strcmp(key, counts[k].key)) continue;
    int64_t value;
    if (n_num != 1 || !parse_int64(r->words[0], &value) || value < 0)
      TL_ERROR(TL_ERR_FORMAT, "%s:%ld: expected one non-negative integer before \"%s\", got \"%s\"", r->path,
               r->line_no, key, n_num >= 1 ? r->words[0] : "");
    *(int64_t *)((char *)hc + counts[k].offset) = value;
    return TL_OK;
  }
  for (size_t k = 0; k < sizeof ignored / sizeof ignored[0]; ++k)
    if (!strcmp(key, ignored[k])) return TL_OK;
  TL_ERROR(TL_ERR_FORMAT, "%s:%ld: unknown header line \"%s\" (expected e.g. \"N atoms\", \"N atom types\", "
           "\"lo hi xlo xhi\")", r->path, r->line_no, key);
}

static TlStatus read_atoms(Reader *r, TlLammpsData *d)
{
  /* The style hint of write_data ("Atoms # sphere"); none: assume sphere.
   * LIGGGHTS's granular style has the same columns. */
  char style[64] = "";
  if (r->comment && sscanf(r->comment, "%63s", style) == 1 && strcmp(style, "sphere") && strcmp(style, "granular"))
    TL_ERROR(TL_ERR_UNSUPPORTED, "%s:%ld: Atoms section of style \"%s\": only atom_style sphere (or LIGGGHTS "
             "granular) is read", r->path, r->line_no, style);
  int eof = 0;
  for (size_t i = 0; i < d->n; ++i) {
    TL_CHECK(next_content_line(r, &eof));
    if (eof)
      TL_ERROR(TL_ERR_FORMAT, "%s: file ends inside the Atoms section after %zu of %zu atoms (line %ld)", r->path,
               i, d->n, r->line_no);
    if (r->n_words != 7 && r->n_words != 10)
      TL_ERROR(TL_ERR_FORMAT, "%s:%ld: Atoms line has %d values, expected 7 (id type diameter density x y z) or "
               "10 (with image flags ix iy iz)", r->path, r->line_no, r->n_words);
    if (i == 0) d->has_images = r->n_words == 10;
    else if (d->has_images != (r->n_words == 10))
      TL_ERROR(TL_ERR_FORMAT, "%s:%ld: Atoms line has %d values but the first atom line had %d: image flags "
               "must be given on all lines or none", r->path, r->line_no, r->n_words, d->has_images ? 10 : 7);
    int64_t id, type;
    double c[5];
    if (!parse_int64(r->words[0], &id) || id <= 0)
      TL_ERROR(TL_ERR_FORMAT, "%s:%ld: atom id \"%s\" is not a positive integer", r->path, r->line_no,
               r->words[0]);
    if (!parse_int64(r->words[1], &type) || type < 1 || type > d->n_types)
      TL_ERROR(TL_ERR_FORMAT, "%s:%ld: atom type \"%s\" is not an integer in 1..%d (the header's atom types)",
               r->path, r->line_no, r->words[1], d->n_types);
    static const char *names[5] = {"diameter", "density", "x", "y", "z"};
    for (int k = 0; k < 5; ++k)
      if (!parse_double(r->words[2 + k], &c[k]))
        TL_ERROR(TL_ERR_FORMAT, "%s:%ld: %s \"%s\" is not a finite number", r->path, r->line_no, names[k],
                 r->words[2 + k]);
    if (!(c[0] > 0.0))
      TL_ERROR(TL_ERR_FORMAT, "%s:%ld: diameter %g of atom %lld must be > 0", r->path, r->line_no, c[0],
               (long long)id);
    if (!(c[1] > 0.0))
      TL_ERROR(TL_ERR_FORMAT, "%s:%ld: density %g of atom %lld must be > 0", r->path, r->line_no, c[1],
               (long long)id);
    d->id[i] = id;
    d->type[i] = (int32_t)type;
    d->diameter[i] = c[0];
    d->density[i] = c[1];
    d->x[i] = tl_v3(c[2], c[3], c[4]);
    if (d->has_images) {
      for (int k = 0; k < 3; ++k) {
        int64_t f;
        if (!parse_int64(r->words[7 + k], &f) || f < INT32_MIN || f > INT32_MAX)
          TL_ERROR(TL_ERR_FORMAT, "%s:%ld: image flag \"%s\" is not a 32-bit integer", r->path, r->line_no,
                   r->words[7 + k]);
        d->image[3 * i + k] = (int32_t)f;
      }
    }
  }
  return TL_OK;
}

/* (id, index) pairs sorted by id, to match Velocities lines to atoms. */
typedef struct { int64_t id; size_t index; } IdIndex;

static int compare_id(const void *a, const void *b)
{
  int64_t x = ((const IdIndex *)a)->id, y = ((const IdIndex *)b)->id;
  return (x > y) - (x < y);
}

static TlStatus build_id_map(const char *path, const TlLammpsData *d, IdIndex **map)
{
  TL_CHECK(tl_calloc(map, d->n ? d->n : 1, sizeof **map));
  for (size_t i = 0; i < d->n; ++i) (*map)[i] = (IdIndex){d->id[i], i};
  qsort(*map, d->n, sizeof **map, compare_id);
  for (size_t i = 1; i < d->n; ++i)
    if ((*map)[i].id == (*map)[i - 1].id) {
      int64_t dup = (*map)[i].id;
      tl_free(map);
      TL_ERROR(TL_ERR_FORMAT, "%s: atom id %lld appears twice in the Atoms section", path, (long long)dup);
    }
  return TL_OK;
}

static TlStatus read_velocities(Reader *r, TlLammpsData *d, const IdIndex *map)
{
  unsigned char *seen = NULL;
  TL_CHECK(tl_calloc(&seen, d->n ? d->n : 1, 1));
  TlStatus status = TL_OK;
  int eof = 0;
  for (size_t i = 0; i < d->n; ++i) {
    TL_CHECK_GOTO(status, next_content_line(r, &eof), done);
    if (eof) {
      status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: file ends inside the Velocities section "
                            "after %zu of %zu atoms (line %ld)", r->path, i, d->n, r->line_no);
      goto done;
    }
    if (r->n_words != 7) {
      status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s:%ld: Velocities line has %d values, "
                            "expected 7 (id vx vy vz wx wy wz)", r->path, r->line_no, r->n_words);
      goto done;
    }
    int64_t id;
    double c[6];
    int ok = parse_int64(r->words[0], &id);
    for (int k = 0; k < 6 && ok; ++k) ok = parse_double(r->words[1 + k], &c[k]);
    if (!ok) {
      status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s:%ld: Velocities line is not an integer id "
                            "followed by six finite numbers", r->path, r->line_no);
      goto done;
    }
    IdIndex key = {id, 0};
    const IdIndex *hit = bsearch(&key, map, d->n, sizeof *map, compare_id);
    if (!hit) {
      status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s:%ld: Velocities line for atom id %lld, "
                            "which is not in the Atoms section", r->path, r->line_no, (long long)id);
      goto done;
    }
    if (seen[hit->index]) {
      status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s:%ld: second Velocities line for atom id "
                            "%lld", r->path, r->line_no, (long long)id);
      goto done;
    }
    seen[hit->index] = 1;
    d->v[hit->index] = tl_v3(c[0], c[1], c[2]);
    d->omega[hit->index] = tl_v3(c[3], c[4], c[5]);
  }
  d->has_velocities = 1;
done:
  tl_free(&seen);
  return status;
}

/* Skips `count` non-blank lines of a section this reader does not keep. */
static TlStatus skip_section(Reader *r, const char *name, int64_t count)
{
  int eof = 0;
  for (int64_t k = 0; k < count; ++k) {
    TL_CHECK(next_content_line(r, &eof));
    if (eof)
      TL_ERROR(TL_ERR_FORMAT, "%s: file ends inside the %s section after %lld of %lld lines", r->path, name,
               (long long)k, (long long)count);
  }
  return TL_OK;
}

static TlStatus allocate_atoms(TlLammpsData *d)
{
  size_t n = d->n ? d->n : 1;
  TL_CHECK(tl_calloc(&d->id, n, sizeof *d->id));
  TL_CHECK(tl_calloc(&d->type, n, sizeof *d->type));
  TL_CHECK(tl_calloc(&d->diameter, n, sizeof *d->diameter));
  TL_CHECK(tl_calloc(&d->density, n, sizeof *d->density));
  TL_CHECK(tl_calloc(&d->x, n, sizeof *d->x));
  TL_CHECK(tl_calloc(&d->image, 3 * n, sizeof *d->image));
  TL_CHECK(tl_calloc(&d->v, n, sizeof *d->v));
  TL_CHECK(tl_calloc(&d->omega, n, sizeof *d->omega));
  return TL_OK;
}

static TlStatus read_file(Reader *r, TlLammpsData *d)
{
  int eof = 0;
  /* title line */
  errno = 0;
  ssize_t len = getline(&r->line, &r->line_cap, r->file);
  if (len < 0) TL_ERROR(TL_ERR_FORMAT, "%s: empty file (a LAMMPS data file starts with a title line)", r->path);
  r->line_no = 1;
  r->line[strcspn(r->line, "\r\n")] = '\0';
  size_t tlen = strlen(r->line);
  TL_CHECK(tl_calloc(&d->title, tlen + 1, 1));
  memcpy(d->title, r->line, tlen);

  /* header, up to the first section name */
  HeaderCounts hc = {0};
  hc.atoms = -1;
  for (int k = 0; k < 3; ++k) {
    d->lo[k] = -0.5;
    d->hi[k] = 0.5;
  }
  for (;;) {
    TL_CHECK(next_content_line(r, &eof));
    if (eof) break;
    if (!looks_numeric(r->words[0])) break;
    TL_CHECK(parse_header_line(r, &hc, d));
  }
  if (hc.atoms < 0)
    TL_ERROR(TL_ERR_FORMAT, "%s: the header has no \"N atoms\" line (line %ld reached)", r->path, r->line_no);
  if (hc.atom_types < 1 || hc.atom_types > INT32_MAX)
    TL_ERROR(TL_ERR_FORMAT, "%s: the header declares %lld atom types; expected a \"N atom types\" line with N >= 1",
             r->path, (long long)hc.atom_types);
  if ((uint64_t)hc.atoms > SIZE_MAX / (3 * sizeof(double)))
    TL_ERROR(TL_ERR_FORMAT, "%s: %lld atoms is too many to hold in memory", r->path, (long long)hc.atoms);
  /* every atom is a line of the Atoms section, of 7 fields at least
   * ("1 1 1 1 0 0 0"): a large count the rest of the file cannot hold is
   * refused before it sizes an allocation (small ones are read and meet the
   * section's own, more telling, diagnosis) */
  long here = ftell(r->file);
  if (here >= 0 && fseek(r->file, 0, SEEK_END) == 0) {
    long end = ftell(r->file);
    if (fseek(r->file, here, SEEK_SET) != 0)
      TL_ERROR(TL_ERR_IO, "%s: cannot return to line %ld after measuring the file", r->path, r->line_no);
    const long long room = (end - here + (long)strlen(r->line) + 1) / 14;
    if (hc.atoms > 4096 && hc.atoms > room)
      TL_ERROR(TL_ERR_FORMAT, "%s: the header declares %lld atoms, but the rest of the file (%ld bytes) holds at "
               "most %lld atom lines", r->path, (long long)hc.atoms, end - here, room);
  }
  d->n = (size_t)hc.atoms;
  d->n_types = (int)hc.atom_types;
  TL_CHECK(allocate_atoms(d));

  /* sections */
  int have_atoms = 0;
  IdIndex *map = NULL;
  TlStatus status = TL_OK;
  while (!eof) {
    char name[128];
    join_words(r, 0, name, sizeof name);
    if (!strcmp(name, "Atoms")) {
      if (have_atoms) {
        status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s:%ld: second Atoms section", r->path,
                              r->line_no);
        goto done;
      }
      TL_CHECK_GOTO(status, read_atoms(r, d), done);
      TL_CHECK_GOTO(status, build_id_map(r->path, d, &map), done);
      have_atoms = 1;
    } else if (!strcmp(name, "Velocities")) {
      if (!have_atoms) {
        status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s:%ld: Velocities section before the Atoms "
                              "section", r->path, r->line_no);
        goto done;
      }
      if (d->has_velocities) {
        status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s:%ld: second Velocities section", r->path,
                              r->line_no);
        goto done;
      }
      TL_CHECK_GOTO(status, read_velocities(r, d, map), done);
    } else if (!strcmp(name, "Masses") || !strcmp(name, "Pair Coeffs")) {
      TL_CHECK_GOTO(status, skip_section(r, name, hc.atom_types), done);
    } else if (!strcmp(name, "PairIJ Coeffs")) {
      TL_CHECK_GOTO(status, skip_section(r, name, hc.atom_types * (hc.atom_types + 1) / 2), done);
    } else if (looks_numeric(r->words[0])) {
      status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s:%ld: %d values where a section name was "
                            "expected: the previous section has more lines than the header declares", r->path,
                            r->line_no, r->n_words);
      goto done;
    } else {
      status = tl_error_set(TL_ERR_UNSUPPORTED, __FILE__, __LINE__, "%s:%ld: section \"%s\" is not read (this "
                            "reader knows Atoms, Velocities, Masses, Pair Coeffs, PairIJ Coeffs)", r->path,
                            r->line_no, name);
      goto done;
    }
    TL_CHECK_GOTO(status, next_content_line(r, &eof), done);
  }
  if (!have_atoms && d->n > 0)
    status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "%s: the header declares %zu atoms but the file "
                          "has no Atoms section", r->path, d->n);
done:
  tl_free(&map);
  return status;
}

TlStatus tl_lammps_data_read(const char *path, TlLammpsData **data)
{
  if (!path || !data) TL_ERROR(TL_ERR_ARG, "tl_lammps_data_read: path and data must not be NULL");
  *data = NULL;
  Reader r = {.path = path};
  r.file = fopen(path, "r");
  if (!r.file) TL_ERROR(TL_ERR_IO, "cannot open LAMMPS data file %s: %s", path, strerror(errno));
  TlLammpsData *d = NULL;
  TlStatus status = TL_NEW(d);
  if (status == TL_OK) status = read_file(&r, d);
  if (status != TL_OK) tl_error_trace(status, __FILE__, __LINE__);
  free(r.line);
  fclose(r.file);
  if (status != TL_OK) {
    tl_lammps_data_destroy(&d);
    return status;
  }
  *data = d;
  return TL_OK;
}

void tl_lammps_data_destroy(TlLammpsData **data)
{
  if (!data || !*data) return;
  TlLammpsData *d = *data;
  tl_free(&d->title);
  tl_free(&d->id);
  tl_free(&d->type);
  tl_free(&d->diameter);
  tl_free(&d->density);
  tl_free(&d->x);
  tl_free(&d->image);
  tl_free(&d->v);
  tl_free(&d->omega);
  tl_free(data);
}

double tl_lammps_data_mass(const TlLammpsData *d, size_t i)
{
  double r = d->diameter[i];
  return d->density[i] * TL_PI / 6.0 * r * r * r;
}

TlVec3 tl_lammps_data_unwrapped(const TlLammpsData *d, size_t i)
{
  const int32_t *im = d->image + 3 * i;
  double lx = d->hi[0] - d->lo[0], ly = d->hi[1] - d->lo[1], lz = d->hi[2] - d->lo[2];
  TlVec3 x = d->x[i];
  return tl_v3(x.x + im[0] * lx + im[1] * d->tilt[0] + im[2] * d->tilt[1], x.y + im[1] * ly + im[2] * d->tilt[2],
               x.z + im[2] * lz);
}

size_t tl_lammps_data_count_type(const TlLammpsData *d, int type)
{
  size_t count = 0;
  for (size_t i = 0; i < d->n; ++i) count += d->type[i] == type;
  return count;
}
