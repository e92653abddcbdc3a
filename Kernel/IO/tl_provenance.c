#include "tl_provenance.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "tl_hdf5_util.h"
#include "tl_init.h"
#include "tl_memory.h"
#include "tl_options.h"

/* HDF5 keeps attributes in the object header, which holds 64 KiB: a longer
 * option list goes into a dataset of the same name. */
enum { TL_PROVENANCE_ATTR_MAX = 60000 };

/* The options in force, one "-name value" a line, allocated. */
static TlStatus tl_provenance_options_text(const TlOptions *o, char **text)
{
  size_t n = o ? tl_options_n_values(o) : 0, len = 1;
  for (size_t i = 0; i < n; ++i) {
    const char *name, *value;
    tl_options_value_at(o, i, &name, &value);
    len += strlen(name) + 1 + (value ? strlen(value) : 0) + 1;
  }
  TL_CHECK(tl_calloc(text, len, 1));
  char *p = *text;
  for (size_t i = 0; i < n; ++i) {
    const char *name, *value;
    tl_options_value_at(o, i, &name, &value);
    p += sprintf(p, "%s%s %s", i ? "\n" : "", name, value ? value : "");
    /* a value is one line: a newline in it (never from the command line)
     * would split the record */
  }
  for (char *c = *text; *c; ++c)
    if (*c == '\r') *c = ' ';
  return TL_OK;
}

TlStatus tl_provenance_write_h5(TlH5File *file)
{
  const TlOptions *o = tl_options_current();
  TL_CHECK(tl_h5_group(file, "/provenance"));
  TL_CHECK(tl_h5_attr_write_string(file, "/provenance", "talus_version", tl_version()));
  TL_CHECK(tl_h5_attr_write_string(file, "/provenance", "talus_revision", tl_revision()));
  TL_CHECK(tl_h5_attr_write_string(file, "/provenance", "program", o ? tl_options_program(o) : ""));
  TL_CHECK(tl_h5_attr_write_string(file, "/provenance", "command_line", o ? tl_options_command_line(o) : ""));
  char *text = NULL;
  TL_CHECK(tl_provenance_options_text(o, &text));
  TlStatus s = strlen(text) < TL_PROVENANCE_ATTR_MAX
                   ? tl_h5_attr_write_string(file, "/provenance", "options", text)
                   : tl_h5_write_string(file, "/provenance/options", text);
  tl_free(&text);
  return s;
}

TlStatus tl_provenance_write_text(FILE *f, const char *comment)
{
  const TlOptions *o = tl_options_current();
  fprintf(f, "%stalus_version: %s\n%stalus_revision: %s\n", comment, tl_version(), comment, tl_revision());
  fprintf(f, "%sprogram: %s\n%scommand_line: %s\n", comment, o ? tl_options_program(o) : "", comment,
          o ? tl_options_command_line(o) : "");
  size_t n = o ? tl_options_n_values(o) : 0;
  for (size_t i = 0; i < n; ++i) {
    const char *name, *value;
    tl_options_value_at(o, i, &name, &value);
    fprintf(f, "%soption: %s ", comment, name);
    for (const char *c = value ? value : ""; *c; ++c) fputc(*c == '\n' || *c == '\r' ? ' ' : *c, f);
    fputc('\n', f);
  }
  if (ferror(f)) TL_ERROR(TL_ERR_IO, "write error in the provenance lines");
  return TL_OK;
}

/* ---------------------------------------------------------------- reading */
static TlStatus tl_provenance_dup(const char *s, size_t n, char **out)
{
  TL_CHECK(tl_calloc(out, n + 1, 1));
  memcpy(*out, s, n);
  return TL_OK;
}

static TlStatus tl_provenance_add_option(TlProvenance *p, size_t *cap, const char *s, size_t n)
{
  TL_CHECK(tl_array_reserve(&p->options, cap, p->n_options + 1, sizeof *p->options));
  TL_CHECK(tl_provenance_dup(s, n, &p->options[p->n_options]));
  p->n_options++;
  return TL_OK;
}

TlStatus tl_provenance_read_h5(const char *path, TlProvenance *p)
{
  memset(p, 0, sizeof *p);
  TlH5File f;
  TL_CHECK(tl_h5_open(path, &f));
  TlStatus s = TL_OK;
  char *text = NULL;
  if (!tl_h5_exists(&f, "/provenance")) {
    s = tl_error_set(TL_ERR_NOT_FOUND, __FILE__, __LINE__, "'%s' has no /provenance group (written by a Talus "
                     "older than its provenance record, or by another program)", path);
    goto done;
  }
  TL_CHECK_GOTO(s, tl_h5_attr_read_string(&f, "/provenance", "talus_version", &p->version), done);
  TL_CHECK_GOTO(s, tl_h5_attr_read_string(&f, "/provenance", "talus_revision", &p->revision), done);
  TL_CHECK_GOTO(s, tl_h5_attr_read_string(&f, "/provenance", "program", &p->program), done);
  TL_CHECK_GOTO(s, tl_h5_attr_read_string(&f, "/provenance", "command_line", &p->command_line), done);
  if (tl_h5_exists(&f, "/provenance/options"))
    TL_CHECK_GOTO(s, tl_h5_read_string(&f, "/provenance/options", &text), done);
  else
    TL_CHECK_GOTO(s, tl_h5_attr_read_string(&f, "/provenance", "options", &text), done);
  size_t cap = 0;
  for (const char *c = text; *c;) {
    size_t n = strcspn(c, "\n");
    if (n) TL_CHECK_GOTO(s, tl_provenance_add_option(p, &cap, c, n), done);
    c += n + (c[n] == '\n');
  }
done:
  tl_free(&text);
  tl_h5_close(&f);
  if (s != TL_OK) {
    tl_provenance_free(p);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
}

TlStatus tl_provenance_read_text(const char *path, TlProvenance *p)
{
  memset(p, 0, sizeof *p);
  FILE *f = fopen(path, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot open '%s': %s", path, strerror(errno));
  char *line = NULL;
  size_t cap_line = 0, cap = 0;
  ssize_t len;
  TlStatus s = TL_OK;
  int found = 0;
  while (s == TL_OK && (len = getline(&line, &cap_line, f)) > 0 && line[0] == '#') {
    while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) line[--len] = '\0';
    const char *c = line + 1;
    while (*c == ' ') ++c;
    const char *colon = strstr(c, ": ");
    if (!colon) continue;
    size_t key = (size_t)(colon - c);
    const char *value = colon + 2;
    size_t n = strlen(value);
    char **slot = NULL;
    if (key == 13 && strncmp(c, "talus_version", key) == 0) slot = &p->version;
    else if (key == 14 && strncmp(c, "talus_revision", key) == 0) slot = &p->revision;
    else if (key == 7 && strncmp(c, "program", key) == 0) slot = &p->program;
    else if (key == 12 && strncmp(c, "command_line", key) == 0) slot = &p->command_line;
    if (slot) {
      tl_free(slot);
      s = tl_provenance_dup(value, n, slot);
      found = 1;
    } else if (key == 6 && strncmp(c, "option", key) == 0) {
      s = tl_provenance_add_option(p, &cap, value, n);
    }
  }
  free(line);
  fclose(f);
  if (s == TL_OK && !found)
    s = tl_error_set(TL_ERR_NOT_FOUND, __FILE__, __LINE__, "'%s' begins with no provenance lines", path);
  if (s != TL_OK) {
    tl_provenance_free(p);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
}

const char *tl_provenance_option(const TlProvenance *p, const char *name)
{
  size_t n = strlen(name);
  for (size_t i = 0; i < p->n_options; ++i)
    if (strncmp(p->options[i], name, n) == 0 && p->options[i][n] == ' ') return p->options[i] + n + 1;
  return NULL;
}

void tl_provenance_free(TlProvenance *p)
{
  tl_free(&p->version);
  tl_free(&p->revision);
  tl_free(&p->program);
  tl_free(&p->command_line);
  for (size_t i = 0; i < p->n_options; ++i) tl_free(&p->options[i]);
  tl_free(&p->options);
  p->n_options = 0;
}
