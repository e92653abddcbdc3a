#include "tl_options_checkpoint.h"

#include <stdlib.h>
#include <string.h>

#include "tl_memory.h"

/* The options are stored as two newline-separated lists, names and values
 * (a value holding a newline has it replaced by a space: option values are
 * single tokens or file lines). */
static TlStatus options_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlOptions *o = object;
  size_t n = tl_options_n_values(o), len_names = 1, len_values = 1;
  for (size_t i = 0; i < n; ++i) {
    const char *name, *value;
    tl_options_value_at(o, i, &name, &value);
    len_names += strlen(name) + 1;
    len_values += (value ? strlen(value) : 0) + 1;
  }
  char *names = NULL, *values = NULL;
  TlStatus s = tl_calloc(&names, len_names, 1);
  if (s == TL_OK) s = tl_calloc(&values, len_values, 1);
  if (s == TL_OK) {
    for (size_t i = 0; i < n; ++i) {
      const char *name, *value;
      tl_options_value_at(o, i, &name, &value);
      strcat(names, name);
      strcat(names, "\n");
      size_t at = strlen(values);
      strcat(values, value ? value : "");
      for (char *c = values + at; *c; ++c)
        if (*c == '\n') *c = ' ';
      strcat(values, "\n");
    }
    s = tl_checkpoint_write_string(w, group, "names", names);
  }
  if (s == TL_OK) s = tl_checkpoint_write_string(w, group, "values", values);
  tl_free(&names);
  tl_free(&values);
  return s;
}

/* The next line of *p (NUL-terminated in place), or NULL at the end. */
static char *next_line(char **p)
{
  if (!*p || !**p) return NULL;
  char *line = *p, *nl = strchr(line, '\n');
  if (nl) {
    *nl = '\0';
    *p = nl + 1;
  } else {
    *p = line + strlen(line);
  }
  return line;
}

static TlStatus options_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlOptions *o = object;
  char *names = NULL, *values = NULL;
  TlStatus s = tl_checkpoint_read_string(r, group, "names", &names);
  if (s == TL_OK) s = tl_checkpoint_read_string(r, group, "values", &values);
  char *pn = names, *pv = values, *name;
  size_t stored = 0;
  while (s == TL_OK && (name = next_line(&pn))) {
    char *then = next_line(&pv);
    ++stored;
    if (!then) {
      s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "checkpoint options: no value for %s", name);
      break;
    }
    if (tl_options_is_restart_safe(o, name)) continue;
    const char *now = tl_options_value(o, name);
    if (!now)
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "the checkpoint was made with %s %s, an option this run does not use: a restart continues "
                       "the same run",
                       name, then);
    else if (strcmp(now, then) != 0)
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "restart with %s %s, but the checkpoint was made with %s %s: a restart continues the same "
                       "physics (only the end time, output folder and cadence, threads and checks may change)",
                       name, now, name, then);
  }
  /* An option this run uses that the checkpoint does not know. */
  for (size_t i = 0; s == TL_OK && i < tl_options_n_values(o); ++i) {
    const char *now_name, *now_value;
    tl_options_value_at(o, i, &now_name, &now_value);
    if (tl_options_is_restart_safe(o, now_name)) continue;
    int found = 0;
    for (char *c = names; c && *c && !found; c += strlen(c) + 1)
      found = strcmp(c, now_name) == 0;
    if (!found)
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "this run uses %s %s, which the checkpoint (%zu options) does not record: it was made by "
                       "another driver or version",
                       now_name, now_value ? now_value : "", stored);
  }
  tl_free(&names);
  tl_free(&values);
  return s;
}

const TlCheckpointOps tl_options_checkpoint_ops = {
    .header = {"checkpoint", "options_v1", "the options in force, compared on restart"},
    .save = options_save,
    .load = options_load};
