#include "tl_options.h"

#include <ctype.h>
#include <limits.h>
#include <strings.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "tl_init.h"
#include "tl_log.h"
#include "tl_memory.h"

#include "tl_options_private.h"


static char *tl_options_strdup(const char *s)
{
  if (!s) return NULL;
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

/* An option name is '-' followed by a letter: "-0.5" and "-1e3" are values,
 * and so are "-nan" and "-inf" (whole numbers to strtod), which the getters
 * then refuse as not finite rather than as a missing value. */
static int tl_is_option_name(const char *s)
{
  if (!(s[0] == '-' && (isalpha((unsigned char)s[1]) || s[1] == '_'))) return 0;
  char *end = NULL;
  (void)strtod(s, &end);
  return !(end && end != s && *end == '\0');
}

static TlOptionEntry *tl_find(TlOptions *o, const char *name)
{
  for (size_t i = 0; i < o->n_entry; ++i)
    if (strcmp(o->entry[i].name, name) == 0) return &o->entry[i];
  return NULL;
}

/* Stores an option.  The last value of a repeated option wins (PETSc's
 * rule), so a wrapper may pass its defaults before the user's "$@"; a value
 * from a file never replaces one from the command line. */
static TlStatus tl_add_entry(TlOptions *o, const char *name, const char *value, const char *source,
                             int from_command_line)
{
  TlOptionEntry *e = tl_find(o, name);
  if (e) {
    if (e->from_command_line && !from_command_line) {
      tl_debug("option %s: the command-line value overrides %s", name, source);
      return TL_OK;
    }
    tl_debug("option %s %s (%s) replaces %s (%s)", name, value ? value : "", source, e->value ? e->value : "",
             e->source);
    char *v = tl_options_strdup(value), *src = tl_options_strdup(source);
    if ((value && !v) || !src) {
      free(v);
      free(src);
      TL_ERROR(TL_ERR_MEM, "out of memory storing option %s", name);
    }
    free(e->value);
    free(e->source);
    e->value = v;
    e->source = src;
    e->from_command_line = from_command_line;
    return TL_OK;
  }
  TL_CHECK(tl_array_reserve(&o->entry, &o->cap_entry, o->n_entry + 1, sizeof *o->entry));
  e = &o->entry[o->n_entry++];
  e->name = tl_options_strdup(name);
  e->value = tl_options_strdup(value);
  e->source = tl_options_strdup(source);
  e->from_command_line = from_command_line;
  e->used = 0;
  if (!e->name || (value && !e->value) || !e->source) TL_ERROR(TL_ERR_MEM, "out of memory storing option %s", name);
  return TL_OK;
}

static int tl_is_help(const char *s)
{
  return strcmp(s, "-help") == 0 || strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0;
}

static int tl_is_version(const char *s) { return strcmp(s, "-version") == 0 || strcmp(s, "--version") == 0; }

static TlStatus tl_parse_bool_text(const char *name, const char *text, int *value)
{
  static const char *const yes[] = {"1", "true", "yes", "on"}, *const no[] = {"0", "false", "no", "off"};
  for (int i = 0; i < 4; ++i) {
    if (strcasecmp(text, yes[i]) == 0) return (*value = 1), TL_OK;
    if (strcasecmp(text, no[i]) == 0) return (*value = 0), TL_OK;
  }
  TL_ERROR(TL_ERR_ARG, "option %s: '%s' is not a boolean (true/false, yes/no, on/off, 1/0)", name, text);
}

/* The options every program has, handled here rather than by a getter:
 * they are not part of a run's physics (not stored in checkpoints). */
static TlStatus tl_builtin(TlOptions *o, const char *name, const char *value, int *consumed, int *handled)
{
  *handled = 1;
  *consumed = 0;
  if (strcmp(name, "-options_left") == 0) {
    int v = 1, b = 1;
    if (value && tl_parse_bool_text(name, value, &b) == TL_OK) v = b, *consumed = 1;
    tl_error_clear();
    o->options_left = v;
    return TL_OK;
  }
  if (strcmp(name, "-log_level") == 0) {
    int level = value ? tl_log_level_from_name(value) : -1;
    if (level < 0)
      TL_ERROR(TL_ERR_ARG, "option -log_level: '%s' is not one of error|warn|info|debug", value ? value : "");
    tl_log_set_level((TlLogLevel)level);
    *consumed = 1;
    return TL_OK;
  }
  *handled = 0;
  return TL_OK;
}

TlStatus tl_options_create(int argc, char **argv, const char *description, TlOptions **options)
{
  TlOptions *o;
  TL_CHECK(TL_NEW(o));
  *options = o;
  const char *prog = argc > 0 ? argv[0] : "talus";
  const char *slash = strrchr(prog, '/');
  o->program = tl_options_strdup(slash ? slash + 1 : prog);
  o->description = tl_options_strdup(description ? description : "");
  size_t len = 1;
  for (int i = 0; i < argc; ++i) len += strlen(argv[i]) + 3;
  TL_CHECK(tl_calloc(&o->command_line, len, 1));
  for (int i = 0; i < argc; ++i) {
    /* Empty words and words with blanks quoted, so the line can be rerun. */
    int quote = argv[i][0] == '\0' || strpbrk(argv[i], " \t\"") != NULL;
    if (i) strcat(o->command_line, " ");
    if (quote) strcat(o->command_line, "'");
    strcat(o->command_line, argv[i]);
    if (quote) strcat(o->command_line, "'");
  }
  char group0[300];
  snprintf(group0, sizeof group0, "%s options", o->program ? o->program : "program");
  TlStatus s = tl_options_begin_group(o, group0);

  const char **files = NULL;
  size_t n_files = 0, cap_files = 0;
  for (int i = 1; s == TL_OK && i < argc; ++i) {
    const char *name = argv[i];
    if (tl_is_help(name)) {
      o->help = 1;
      continue;
    }
    if (tl_is_version(name)) {
      o->version = 1;
      continue;
    }
    if (!tl_is_option_name(name)) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "argument '%s' is not an option (options start with '-', e.g. -t_end 40)", name);
      break;
    }
    const char *value = NULL;
    if (i + 1 < argc && !tl_is_option_name(argv[i + 1]) && !tl_is_help(argv[i + 1]) && !tl_is_version(argv[i + 1]))
      value = argv[i + 1];
    if (strcmp(name, "-options_file") == 0) {
      if (!value) {
        s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "option -options_file needs a file name");
        break;
      }
      if ((s = tl_array_reserve(&files, &cap_files, n_files + 1, sizeof *files))) break;
      files[n_files++] = value;
      ++i;
      continue;
    }
    int consumed, handled;
    if ((s = tl_builtin(o, name, value, &consumed, &handled))) break;
    if (handled) {
      i += consumed;
      continue;
    }
    char source[64];
    snprintf(source, sizeof source, "command line, argument %d", i);
    s = tl_add_entry(o, name, value, source, 1);
    if (value) ++i;
  }
  /* Files in the order given: a later file overrides an earlier one, the
   * command line overrides both. */
  for (size_t k = 0; s == TL_OK && k < n_files; ++k) s = tl_options_insert_file(o, files[k]);
  free(files);
  if (s) {
    tl_options_destroy(options);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
}

void tl_options_destroy(TlOptions **options)
{
  TlOptions *o = *options;
  if (!o) return;
  if (tl_options_current() == o) tl_options_set_current(NULL);
  for (size_t i = 0; i < o->n_entry; ++i) {
    free(o->entry[i].name);
    free(o->entry[i].value);
    free(o->entry[i].source);
  }
  for (size_t i = 0; i < o->n_doc; ++i) {
    free(o->doc[i].name);
    free(o->doc[i].kind);
    free(o->doc[i].def);
    free(o->doc[i].unit);
    free(o->doc[i].help);
    free(o->doc[i].range);
    free(o->doc[i].value);
  }
  for (size_t i = 0; i < o->n_group; ++i) free(o->group[i]);
  free(o->group);
  for (size_t i = 0; i < o->n_restart_safe; ++i) free(o->restart_safe[i]);
  free(o->restart_safe);
  free(o->entry);
  free(o->doc);
  free(o->program);
  free(o->description);
  free(o->command_line);
  tl_free(options);
}

TlStatus tl_options_insert_file(TlOptions *o, const char *path)
{
  /* A directory opens (and reads as empty) on some systems: only a regular
   * file, or a pipe or device such as /dev/stdin, is an options file. */
  struct stat st;
  if (stat(path, &st) != 0) TL_ERROR(TL_ERR_IO, "cannot open options file '%s': %s", path, strerror(errno));
  if (S_ISDIR(st.st_mode)) TL_ERROR(TL_ERR_IO, "options file '%s' is a directory, not a file", path);
  FILE *f = fopen(path, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot open options file '%s': %s", path, strerror(errno));
  char line[4096];
  int lineno = 0;
  TlStatus s = TL_OK;
  while (fgets(line, sizeof line, f)) {
    ++lineno;
    char *hash = strchr(line, '#');
    if (hash) *hash = '\0';
    char *name = strtok(line, " \t\r\n");
    if (!name) continue;
    char *value = strtok(NULL, " \t\r\n");
    char *extra = strtok(NULL, " \t\r\n");
    char source[600];
    snprintf(source, sizeof source, "%.500s:%d", path, lineno);
    if (!tl_is_option_name(name) || extra) {
      s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                       "%s: expected '-name value', found '%s%s%s'", source, name, value ? " " : "",
                       value ? value : "");
      break;
    }
    if (strcmp(name, "-options_file") == 0) {
      s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                       "%s: -options_file inside an options file (give every file on the command line)", source);
      break;
    }
    int consumed, handled;
    if ((s = tl_builtin(o, name, value, &consumed, &handled))) break;
    if (handled) continue;
    /* Within a file, as on the command line, the last value wins. */
    if ((s = tl_add_entry(o, name, value, source, 0))) break;
  }
  if (s == TL_OK && ferror(f))
    s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "cannot read options file '%s' (after line %d)", path, lineno);
  fclose(f);
  return s;
}

TlStatus tl_options_begin_group(TlOptions *o, const char *title)
{
  if (o->group_depth >= TL_OPTIONS_GROUP_DEPTH)
    TL_ERROR(TL_ERR_STATE, "option groups nested deeper than %d (at '%s'): a begin without its end?",
             TL_OPTIONS_GROUP_DEPTH, title);
  size_t k = 0;
  while (k < o->n_group && strcmp(o->group[k], title) != 0) ++k;
  if (k == o->n_group) {
    TL_CHECK(tl_array_reserve(&o->group, &o->cap_group, o->n_group + 1, sizeof *o->group));
    o->group[k] = tl_options_strdup(title);
    if (!o->group[k]) TL_ERROR(TL_ERR_MEM, "no memory for option group '%s'", title);
    o->n_group++;
  }
  o->group_stack[o->group_depth++] = k;
  return TL_OK;
}

void tl_options_end_group(TlOptions *o)
{
  if (o->group_depth > 1) o->group_depth--;
}

static char *tl_format_range(double lo, double hi)
{
  char buf[128] = "";
  if (lo > -INFINITY && hi < INFINITY)
    snprintf(buf, sizeof buf, "[%.10g, %.10g]", lo, hi);
  else if (lo > -INFINITY)
    snprintf(buf, sizeof buf, ">= %.10g", lo);
  else if (hi < INFINITY)
    snprintf(buf, sizeof buf, "<= %.10g", hi);
  return tl_options_strdup(buf);
}

static TlStatus tl_document_range(TlOptions *o, const char *name, const char *kind, const char *def,
                                  const char *unit, const char *help, double lo, double hi)
{
  for (size_t i = 0; i < o->n_doc; ++i)
    if (strcmp(o->doc[i].name, name) == 0) return TL_OK;
  TL_CHECK(tl_array_reserve(&o->doc, &o->cap_doc, o->n_doc + 1, sizeof *o->doc));
  TlOptionDoc *d = &o->doc[o->n_doc++];
  memset(d, 0, sizeof *d);
  d->name = tl_options_strdup(name);
  d->kind = tl_options_strdup(kind);
  d->def = tl_options_strdup(def ? def : "");
  d->unit = tl_options_strdup(unit ? unit : "");
  d->help = tl_options_strdup(help ? help : "");
  d->range = tl_format_range(lo, hi);
  d->group = o->group_depth ? o->group_stack[o->group_depth - 1] : 0;
  if (!d->name || !d->kind || !d->def || !d->unit || !d->help || !d->range)
    TL_ERROR(TL_ERR_MEM, "no memory to document option %s", name);
  return TL_OK;
}

static TlStatus tl_document(TlOptions *o, const char *name, const char *kind, const char *def,
                            const char *unit, const char *help)
{
  return tl_document_range(o, name, kind, def, unit, help, -INFINITY, INFINITY);
}

/* Records the value in force of a documented option, in canonical text. */
static TlStatus tl_resolve(TlOptions *o, const char *name, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static TlStatus tl_resolve(TlOptions *o, const char *name, const char *fmt, ...)
{
  for (size_t i = 0; i < o->n_doc; ++i) {
    if (strcmp(o->doc[i].name, name) != 0) continue;
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    free(o->doc[i].value);
    o->doc[i].value = tl_options_strdup(buf);
    if (!o->doc[i].value) TL_ERROR(TL_ERR_MEM, "option %s: no memory for its value", name);
    return TL_OK;
  }
  return TL_OK;
}

/* The value of an option that was given, or NULL; marks it used. */
static TlStatus tl_lookup(TlOptions *o, const char *name, int needs_value, const char **value, int *given)
{
  TlOptionEntry *e = tl_find(o, name);
  *given = e != NULL;
  *value = NULL;
  if (!e) return TL_OK;
  e->used = 1;
  if (needs_value && !e->value)
    TL_ERROR(TL_ERR_ARG, "option %s (%s) needs a value", name, e->source);
  *value = e->value;
  return TL_OK;
}

static TlStatus tl_parse_real(const char *name, const char *text, double *value)
{
  char *end;
  errno = 0;
  double v = strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE || !isfinite(v))
    TL_ERROR(TL_ERR_ARG, "option %s: '%s' is not a finite real number", name, text);
  *value = v;
  return TL_OK;
}

static TlStatus tl_check_range(const char *name, double v, double lo, double hi, const char *unit)
{
  if (v < lo || v > hi) {
    if (hi == INFINITY)
      TL_ERROR(TL_ERR_ARG, "option %s = %g %s is below its lower limit %g", name, v, unit ? unit : "", lo);
    if (lo == -INFINITY)
      TL_ERROR(TL_ERR_ARG, "option %s = %g %s is above its upper limit %g", name, v, unit ? unit : "", hi);
    TL_ERROR(TL_ERR_ARG, "option %s = %g %s is outside [%g, %g]", name, v, unit ? unit : "", lo, hi);
  }
  return TL_OK;
}

TlStatus tl_options_get_real(TlOptions *o, const char *name, double def, double lo, double hi,
                             const char *unit, const char *help, double *value)
{
  char buf[64];
  snprintf(buf, sizeof buf, "%g", def);
  TL_CHECK(tl_document_range(o, name, "<real>", buf, unit, help, lo, hi));
  const char *text;
  int given;
  TL_CHECK(tl_lookup(o, name, 1, &text, &given));
  *value = def;
  if (given) TL_CHECK(tl_parse_real(name, text, value));
  TL_CHECK(tl_check_range(name, *value, lo, hi, unit));
  return tl_resolve(o, name, "%.17g", *value);
}

TlStatus tl_options_get_int(TlOptions *o, const char *name, long def, long lo, long hi, const char *help,
                            long *value)
{
  char buf[64];
  snprintf(buf, sizeof buf, "%ld", def);
  TL_CHECK(tl_document_range(o, name, "<int>", buf, NULL, help, lo == LONG_MIN ? -INFINITY : (double)lo,
                             hi == LONG_MAX ? INFINITY : (double)hi));
  const char *text;
  int given;
  TL_CHECK(tl_lookup(o, name, 1, &text, &given));
  *value = def;
  if (given) {
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (end == text || *end != '\0' || errno == ERANGE)
      TL_ERROR(TL_ERR_ARG, "option %s: '%s' is not an integer", name, text);
    *value = v;
  }
  if (*value < lo || *value > hi)
    TL_ERROR(TL_ERR_ARG, "option %s = %ld is outside [%ld, %ld]", name, *value, lo, hi);
  return tl_resolve(o, name, "%ld", *value);
}

TlStatus tl_options_get_bool(TlOptions *o, const char *name, int def, const char *help, int *value)
{
  TL_CHECK(tl_document(o, name, "[<bool>]", def ? "true" : "false", NULL, help));
  const char *text;
  int given;
  TL_CHECK(tl_lookup(o, name, 0, &text, &given));
  *value = def;
  if (!given) return tl_resolve(o, name, "%s", def ? "true" : "false");
  if (!text) {
    *value = 1;
    return tl_resolve(o, name, "true");
  }
  TL_CHECK(tl_parse_bool_text(name, text, value));
  return tl_resolve(o, name, "%s", *value ? "true" : "false");
}

TlStatus tl_options_get_string(TlOptions *o, const char *name, const char *def, const char *help,
                               const char **value)
{
  TL_CHECK(tl_document(o, name, "<string>", def, NULL, help));
  const char *text;
  int given;
  TL_CHECK(tl_lookup(o, name, 1, &text, &given));
  *value = given ? text : def;
  return tl_resolve(o, name, "%s", *value ? *value : "");
}

TlStatus tl_options_get_choice(TlOptions *o, const char *name, const char *def, const char *const *choices,
                               const char *help, int *index)
{
  char kind[512] = "<";
  for (int i = 0; choices[i]; ++i) {
    if (i) strncat(kind, "|", sizeof kind - strlen(kind) - 1);
    strncat(kind, choices[i], sizeof kind - strlen(kind) - 1);
  }
  strncat(kind, ">", sizeof kind - strlen(kind) - 1);
  TL_CHECK(tl_document(o, name, kind, def, NULL, help));
  const char *text;
  int given;
  TL_CHECK(tl_lookup(o, name, 1, &text, &given));
  const char *v = given ? text : def;
  for (int i = 0; choices[i]; ++i)
    if (strcmp(v, choices[i]) == 0) return (*index = i), tl_resolve(o, name, "%s", v);
  TL_ERROR(TL_ERR_ARG, "option %s: '%s' is not one of %s", name, v, kind);
}

static TlStatus tl_parse_scaled(const char *name, const char *text, const TlScale *scales, int n, double *value)
{
  char *end;
  errno = 0;
  double v = strtod(text, &end);
  if (end == text || errno == ERANGE || !isfinite(v))
    TL_ERROR(TL_ERR_ARG, "option %s: '%s' does not start with a finite real number", name, text);
  if (*end == '\0') return (*value = v), TL_OK;
  for (int i = 0; i < n; ++i)
    if (strcmp(end, scales[i].suffix) == 0) return (*value = v * scales[i].factor), TL_OK;
  char list[256] = "";
  for (int i = 0; i < n; ++i) {
    strncat(list, i ? ", " : "", sizeof list - strlen(list) - 1);
    strncat(list, scales[i].suffix, sizeof list - strlen(list) - 1);
  }
  TL_ERROR(TL_ERR_ARG, "option %s: unknown unit suffix '%s' in '%s' (known: %s)", name, end, text,
           n ? list : "none");
}

TlStatus tl_options_get_scaled(TlOptions *o, const char *name, const char *def, double lo, double hi,
                               const char *unit, const TlScale *scales, int n, const char *help,
                               double *value)
{
  char doc_unit[512];
  int len = snprintf(doc_unit, sizeof doc_unit, "%s", unit ? unit : "");
  for (int i = 0; i < n && len < (int)sizeof doc_unit; ++i)
    len += snprintf(doc_unit + len, sizeof doc_unit - (size_t)len, ", or suffix %s = %s", scales[i].suffix,
                    scales[i].meaning);
  TL_CHECK(tl_document_range(o, name, "<real[suffix]>", def, doc_unit, help, lo, hi));
  const char *text;
  int given;
  TL_CHECK(tl_lookup(o, name, 1, &text, &given));
  TL_CHECK(tl_parse_scaled(name, given ? text : def, scales, n, value));
  TL_CHECK(tl_check_range(name, *value, lo, hi, unit));
  return tl_resolve(o, name, "%.17g", *value);
}

TlStatus tl_options_get_real_list_range(TlOptions *o, const char *name, const char *def, double lo, double hi,
                                        const char *unit, const char *help, double *values, int max, int *count)
{
  TL_CHECK(tl_document_range(o, name, "<real,real,...>", def, unit, help, lo, hi));
  const char *text;
  int given;
  TL_CHECK(tl_lookup(o, name, 1, &text, &given));
  const char *src = given ? text : def;
  if (!src) src = "";
  *count = 0;
  if (!src[0]) TL_ERROR(TL_ERR_ARG, "option %s: an empty list (give values such as 0.1,0.2)", name);
  /* Field by field: an empty field (",", "0.005,,0.006", "1,") is an error,
   * not skipped. */
  for (const char *p = src;; ++p) {
    const char *comma = strchr(p, ',');
    size_t len = comma ? (size_t)(comma - p) : strlen(p);
    if (len == 0)
      TL_ERROR(TL_ERR_ARG, "option %s: value %d of '%s' is empty", name, *count + 1, src);
    if (*count >= max) TL_ERROR(TL_ERR_ARG, "option %s: more than %d values in '%s'", name, max, src);
    char tok[128];
    if (len >= sizeof tok) TL_ERROR(TL_ERR_ARG, "option %s: value %d of '%s' is too long", name, *count + 1, src);
    memcpy(tok, p, len);
    tok[len] = '\0';
    double v = 0.0;
    TL_CHECK(tl_parse_real(name, tok, &v));
    TL_CHECK(tl_check_range(name, v, lo, hi, unit));
    values[(*count)++] = v;
    if (!comma) break;
    p = comma;
  }
  char buf[1024];
  size_t len = 0;
  buf[0] = '\0';
  for (int i = 0; i < *count && len < sizeof buf; ++i)
    len += (size_t)snprintf(buf + len, sizeof buf - len, "%s%.17g", i ? "," : "", values[i]);
  return tl_resolve(o, name, "%s", buf);
}

TlStatus tl_options_get_real_list(TlOptions *o, const char *name, const char *def, const char *unit,
                                  const char *help, double *values, int max, int *count)
{
  return tl_options_get_real_list_range(o, name, def, 0.0, INFINITY, unit, help, values, max, count);
}

int tl_options_has(TlOptions *o, const char *name)
{
  TlOptionEntry *e = tl_find(o, name);
  if (e) e->used = 1;
  return e != NULL;
}

static const TlOptions *tl_options_current_db;

void tl_options_set_current(const TlOptions *o) { tl_options_current_db = o; }
const TlOptions *tl_options_current(void) { return tl_options_current_db; }

/* At -log_level debug: every option the program read, with the value in
 * force and where it came from, so a run's settings are in its log (before
 * an unknown option is refused too: the table shows what was meant). */
static void tl_options_debug_table(const TlOptions *o)
{
  if (!tl_log_enabled(TL_LOG_DEBUG)) return;
  tl_debug("%s: %zu options read", o->program, o->n_doc);
  for (size_t i = 0; i < o->n_doc; ++i) {
    const TlOptionDoc *d = &o->doc[i];
    const char *source = "default";
    for (size_t k = 0; k < o->n_entry; ++k)
      if (strcmp(o->entry[k].name, d->name) == 0) source = o->entry[k].source; /* the last one wins */
    tl_debug("option %s = %s (%s)", d->name, d->value ? d->value : "", source);
  }
}

TlStatus tl_options_finish(TlOptions *o, FILE *out)
{
  if (o->help) {
    tl_options_print_help(o, out);
    return TL_HELP;
  }
  if (o->version) {
    fprintf(out, "%s (Talus %s, revision %s)\n", o->program, tl_version(), tl_revision());
    return TL_HELP;
  }
  tl_options_debug_table(o);
  size_t n_unused = 0;
  for (size_t i = 0; i < o->n_entry; ++i) n_unused += !o->entry[i].used;
  if (o->options_left) {
    if (n_unused == 0) tl_info("-options_left: every option given was read");
    for (size_t i = 0; i < o->n_entry; ++i)
      if (!o->entry[i].used) {
        const char *best = tl_options_suggest(o, o->entry[i].name);
        tl_warn("option %s%s%s (%s) was given but never read%s%s", o->entry[i].name, o->entry[i].value ? " " : "",
                o->entry[i].value ? o->entry[i].value : "", o->entry[i].source, best ? "; did you mean " : "",
                best ? best : "");
      }
  } else if (n_unused) {
    /* Every unknown option in one message, each with its suggestion. */
    char msg[4096];
    size_t len = 0;
    msg[0] = '\0';
    for (size_t i = 0; i < o->n_entry && len < sizeof msg; ++i) {
      if (o->entry[i].used) continue;
      const char *best = tl_options_suggest(o, o->entry[i].name);
      len += (size_t)snprintf(msg + len, sizeof msg - len, "%s%s (%s)%s%s%s", len ? "; " : "", o->entry[i].name,
                              o->entry[i].source, best ? ", did you mean " : "", best ? best : "", best ? "?" : "");
    }
    TL_ERROR(TL_ERR_ARG, "unknown option%s %s; -help lists the options of %s (-options_left lists unknown options "
             "without refusing them)", n_unused > 1 ? "s" : "", msg, o->program);
  }
  tl_options_set_current(o);
  return TL_OK;
}

/* Options that only say how far to run, where and how often to write, and
 * with how many threads: a restart may change them. */
static int tl_builtin_restart_safe(const char *name)
{
  static const char *const exact[] = {"-t_end", "-restart", "-output_dir", "-checkpoint_every", "-stop_step",
                                      "-threads", "-check", "-tolerance", "-log_level", "-options_left", NULL};
  static const char *const prefix[] = {"-snapshot", "-table_", "-output_", "-progress", NULL};
  for (int i = 0; exact[i]; ++i)
    if (strcmp(name, exact[i]) == 0) return 1;
  for (int i = 0; prefix[i]; ++i)
    if (strncmp(name, prefix[i], strlen(prefix[i])) == 0) return 1;
  return 0;
}

TlStatus tl_options_set_restart_safe(TlOptions *o, const char *name)
{
  TL_CHECK(tl_array_reserve(&o->restart_safe, &o->cap_restart_safe, o->n_restart_safe + 1, sizeof *o->restart_safe));
  o->restart_safe[o->n_restart_safe] = tl_options_strdup(name);
  if (!o->restart_safe[o->n_restart_safe]) TL_ERROR(TL_ERR_MEM, "no memory for option name %s", name);
  o->n_restart_safe++;
  return TL_OK;
}

int tl_options_is_restart_safe(const TlOptions *o, const char *name)
{
  if (tl_builtin_restart_safe(name)) return 1;
  for (size_t i = 0; i < o->n_restart_safe; ++i)
    if (strcmp(o->restart_safe[i], name) == 0) return 1;
  return 0;
}

size_t tl_options_n_values(const TlOptions *o) { return o->n_doc; }

void tl_options_value_at(const TlOptions *o, size_t i, const char **name, const char **value)
{
  *name = o->doc[i].name;
  *value = o->doc[i].value;
}

const char *tl_options_value(const TlOptions *o, const char *name)
{
  for (size_t i = 0; i < o->n_doc; ++i)
    if (strcmp(o->doc[i].name, name) == 0) return o->doc[i].value;
  return NULL;
}

const char *tl_options_program(const TlOptions *o) { return o->program; }
const char *tl_options_command_line(const TlOptions *o) { return o->command_line; }
