/* -help of the options database (grouped, wrapped at TL_OPTIONS_HELP_WIDTH)
 * and suggestions for a mistyped option name. */
#include <stdio.h>
#include <string.h>

#include "tl_options_private.h"

/* Edit distance with adjacent transpositions counted as one edit (optimal
 * string alignment), to suggest the intended name of a mistyped option. */
static size_t tl_edit_distance(const char *a, const char *b)
{
  size_t na = strlen(a), nb = strlen(b);
  if (na > 63 || nb > 63) return 64;
  size_t d[64][64];
  for (size_t i = 0; i <= na; ++i) d[i][0] = i;
  for (size_t j = 0; j <= nb; ++j) d[0][j] = j;
  for (size_t i = 1; i <= na; ++i)
    for (size_t j = 1; j <= nb; ++j) {
      size_t sub = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);
      size_t del = d[i - 1][j] + 1, ins = d[i][j - 1] + 1;
      size_t best = sub < del ? (sub < ins ? sub : ins) : (del < ins ? del : ins);
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && d[i - 2][j - 2] + 1 < best)
        best = d[i - 2][j - 2] + 1;
      d[i][j] = best;
    }
  return d[na][nb];
}

/* A suggestion only when the names are close for their length: one edit in
 * a name of up to 4 letters, two up to 8, three beyond; so -t_ned finds
 * -t_end but -foo does not find -rho. */
static size_t tl_edits_allowed(const char *name)
{
  size_t n = strlen(name) > 0 ? strlen(name) - 1 : 0; /* without the '-' */
  return n <= 4 ? 1 : n <= 8 ? 2 : 3;
}

const char *tl_options_suggest(const TlOptions *o, const char *name)
{
  static const char *const builtin[] = {"-help", "-version", "-options_file", "-options_left", "-log_level", NULL};
  const char *best = NULL;
  size_t best_d = tl_edits_allowed(name) + 1;
  for (size_t k = 0; k < o->n_doc; ++k) {
    size_t d = tl_edit_distance(name, o->doc[k].name);
    if (d < best_d) best_d = d, best = o->doc[k].name;
  }
  for (int k = 0; builtin[k]; ++k) {
    size_t d = tl_edit_distance(name, builtin[k]);
    if (d < best_d) best_d = d, best = builtin[k];
  }
  return best;
}

/* Writes `text` from column `col` (the cursor's), wrapping words at
 * TL_OPTIONS_HELP_WIDTH with continuation lines indented to `indent`. */
static void tl_wrap(FILE *out, int col, int indent, const char *text)
{
  const char *p = text;
  int first = 1;
  while (*p) {
    while (*p == ' ') ++p;
    if (!*p) break;
    size_t w = strcspn(p, " ");
    if (!first && col + 1 + (int)w > TL_OPTIONS_HELP_WIDTH && col > indent) {
      fprintf(out, "\n%*s", indent, "");
      col = indent;
      first = 1;
    }
    if (!first) {
      fputc(' ', out);
      ++col;
    }
    fwrite(p, 1, w, out);
    col += (int)w;
    p += w;
    first = 0;
  }
  fputc('\n', out);
}

/* One option of -help: the name column, then the description wrapped. */
static void tl_help_line(FILE *out, const char *head, const char *text)
{
  enum { COLUMN = 30 };
  int col = fprintf(out, "  %s", head);
  if (col + 2 > COLUMN) {
    fprintf(out, "\n%*s", COLUMN, "");
  } else {
    fprintf(out, "%*s", COLUMN - col, "");
  }
  tl_wrap(out, COLUMN, COLUMN, text);
}

void tl_options_print_help(const TlOptions *o, FILE *out)
{
  fprintf(out, "usage: %s [options]\n\n", o->program);
  /* The description keeps its own line breaks; long lines are wrapped. */
  const char *p = o->description;
  while (*p) {
    size_t n = strcspn(p, "\n");
    char line[4096];
    size_t m = n < sizeof line - 1 ? n : sizeof line - 1;
    memcpy(line, p, m);
    line[m] = '\0';
    if (m == 0)
      fputc('\n', out);
    else
      tl_wrap(out, 0, 0, line);
    p += n;
    if (*p == '\n') ++p;
  }
  fprintf(out, "\nGeneral options:\n");
  tl_help_line(out, "-help, --help", "print this help and exit");
  tl_help_line(out, "-version, --version", "print the program, the Talus version and the git revision it was built from, and exit");
  tl_help_line(out, "-options_file <path>", "read options from a file, one '-name value' a line, '#' a comment (repeatable; "
                                            "a later file overrides an earlier one, the command line overrides both)");
  tl_help_line(out, "-options_left [<bool>]", "list the options given but never read, as warnings, instead of refusing "
                                              "them (default: false)");
  tl_help_line(out, "-log_level <error|warn|info|debug>",
               "the messages printed: error and warn silence the informational lines on stdout and stderr and "
               "the progress bar, debug adds the options read; the final summary line is printed at every "
               "level (default: info, or the environment variable TALUS_LOG_LEVEL)");
  fprintf(out, "A repeated option takes its last value.\n");
  for (size_t g = 0; g < o->n_group; ++g) {
    int any = 0;
    for (size_t i = 0; i < o->n_doc; ++i) {
      const TlOptionDoc *d = &o->doc[i];
      if (d->group != g) continue;
      if (!any) fprintf(out, "\n%s:\n", o->group[g]);
      any = 1;
      char head[600], text[4096];
      snprintf(head, sizeof head, "%s %s", d->name, d->kind);
      int n = snprintf(text, sizeof text, "%s", d->help);
      if (d->unit[0] && n < (int)sizeof text) n += snprintf(text + n, sizeof text - (size_t)n, " [%s]", d->unit);
      if (n < (int)sizeof text)
        n += snprintf(text + n, sizeof text - (size_t)n, " (default: %s%s%s)", d->def[0] ? d->def : "none",
                      d->range[0] ? "; range " : "", d->range);
      tl_help_line(out, head, text);
    }
  }
}
