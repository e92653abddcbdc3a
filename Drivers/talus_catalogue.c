/* The catalogue of every registered type: contact-law parts, walls, element
 * types, materials, steppers, linear solvers, CG kernels, tangent operators,
 * couplings, wall outlines, and any kind a plug-in registers, each with its
 * description and its parameters (default, range, unit, meaning), read from
 * the registries (tl_registry.h) so it cannot go stale.  docs/catalogue.md
 * is this program's Markdown output; the test catalogue_current fails when
 * the two differ. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"

/* What a reader needs to know about each built-in kind: a title and how a
 * type of it is chosen.  A kind not listed here is still catalogued. */
static const struct {
  const char *kind, *title, *how;
} kinds[] = {
    {"contact_normal", "Contact law: normal parts",
     "`tl_contact_law_create(normal, friction, rolling, adhesion, &law)`, then `tl_contact_law_set(law, name, value)`; "
     "in a driver `-contact NAME` and `-contact_<parameter>`"},
    {"contact_friction", "Contact law: friction (tangential) parts", "the second argument of `tl_contact_law_create`; `-friction NAME`"},
    {"contact_rolling", "Contact law: rolling-resistance parts", "the third argument of `tl_contact_law_create`; `-rolling NAME`"},
    {"contact_adhesion", "Contact law: adhesion parts", "the fourth argument of `tl_contact_law_create`; `-adhesion NAME`"},
    {"wall", "Walls", "`tl_wall_create(type, n, settings, &wall)` with `{name, value}` settings, then `tl_dem_add_wall`"},
    {"wall_outline", "Wall outlines (how walls are drawn in the output)",
     "used by `tl_wall_writer_write` for walls of the type of the same name (tl_wall_snapshot.h)"},
    {"element", "Finite element types", "`tl_element_type_find(name, &type)`; mesh readers find them by Gmsh code"},
    {"material", "Materials (constitutive laws)",
     "`tl_material_create(name, &m)`, then `tl_material_set(m, name, value)`; every material also takes `density` "
     "(kg/m³), a parameter of the base type that the tables below do not list"},
    {"stepper", "Time steppers",
     "`tl_stepper_create(type, system, &options, &stepper)`; the parameters are the fields of `TlStepperOptions` "
     "(tl_stepper.h) each type reads: `tl_stepper_options_default` gives the defaults below, "
     "`tl_stepper_options_set(&options, type, name, value)` sets one within its range, and `tl_stepper_create` "
     "refuses a value outside it.  Switches, choices and counts take whole values.  The implicit steppers also read `solver`, the "
     "name of a linear solver (below; default NULL: cholmod for a symmetric Jacobian, else klu)"},
    {"linear_solver", "Linear solvers",
     "`tl_linear_solver_create(type, A, &solver)`, or the `solver` field of `TlStepperOptions`.  They take no "
     "settings: each analyses the pattern once with its library's default fill-reducing ordering and "
     "refactorises numerically on each factor (CHOLMOD: simplicial for small systems, "
     "else its own choice; KLU: reuses its pivot sequence while the condition estimate allows; UMFPACK: its "
     "default iterative refinement)"},
    {"cg_kernel", "Coarse-graining kernels",
     "`tl_cg_kernel_create(name, width, dim, &kernel)` (dim 1, 2 or 3: the kernel is normalised in that many "
     "dimensions); `-cg_kernel NAME` and `-cg_width` in drivers"},
    {"nhl_operator", "FEM x DEM tangent operators",
     "`tl_nhl_operator_create(name, &op)` and `tl_nhl_operator_set`; besides the parameters below, every operator "
     "takes the base parameters `eps`, `directions`, `sliding_kt` and `symmetrise` (tl_nhl_operator.h)"},
    {"coupling", "Couplings", "the coupling's own create function, its parameters as options (tl_bdm.h)"},
};

static const char *kind_title(const char *kind, const char **how)
{
  for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k)
    if (strcmp(kinds[k].kind, kind) == 0) return (*how = kinds[k].how), kinds[k].title;
  return (*how = NULL), kind;
}

static int by_kind_name(const void *a, const void *b)
{
  const TlTypeEntry *x = *(const TlTypeEntry *const *)a, *y = *(const TlTypeEntry *const *)b;
  int c = strcmp(x->kind, y->kind);
  return c ? c : strcmp(x->name, y->name);
}

/* A number as the catalogue prints it: 1e300 and beyond as infinity; NaN
 * (a default) as "required": the caller must give the value. */
static void number(char *buf, size_t size, double v, int markdown)
{
  if (isnan(v)) snprintf(buf, size, "required");
  else if (v >= 1e300) snprintf(buf, size, "%s", markdown ? "∞" : "inf");
  else if (v <= -1e300) snprintf(buf, size, "%s", markdown ? "−∞" : "-inf");
  else snprintf(buf, size, "%.6g", v);
}

/* Table cells must not hold '|' or newlines. */
static void cell(FILE *out, const char *s)
{
  for (; s && *s; ++s) fputs(*s == '|' ? "\\|" : *s == '\n' ? " " : (char[2]){*s, 0}, out);
}

static void element_facts(FILE *out, const TlTypeEntry *e, int md)
{
  const TlElementType *t = e->ops;
  if (!t) return;
  fprintf(out, md ? "\n%d-D, %d nodes (%d corners), %d faces%s%s, Gmsh code %d, %s, output cell %s.\n"
                  : "    %d-D, %d nodes (%d corners), %d faces%s%s, Gmsh code %d, %s, output cell %s\n",
          t->dim, t->n_nodes, t->n_corners, t->n_faces, t->face_type ? " of type " : "",
          t->face_type ? t->face_type->header.name : "", t->gmsh_type, t->linear ? "linear" : "higher order",
          t->output ? tl_cell_type_name(t->output->cell) : "none");
}

typedef struct {
  size_t n_no_unit, n_no_help, n_no_description;
  TlText list;
} Gaps;

static void entry(FILE *out, const TlTypeEntry *e, int md, Gaps *g)
{
  const char *desc = e->description && e->description[0] ? e->description : NULL;
  if (!desc) {
    g->n_no_description++;
    tl_text_printf(&g->list, md ? "- %s `%s`: no description\n" : "  %s %s: no description\n", e->kind, e->name);
  }
  if (md) fprintf(out, "\n### `%s`\n\n%s\n", e->name, desc ? desc : "(no description)");
  else fprintf(out, "\n  %s: %s\n", e->name, desc ? desc : "(no description)");
  if (strcmp(e->kind, "element") == 0) element_facts(out, e, md);
  if (e->n_params == 0) {
    fprintf(out, md ? "\nNo parameters.\n" : "    no parameters\n");
    return;
  }
  if (md) fprintf(out, "\n| parameter | default | range | unit | meaning |\n|---|---|---|---|---|\n");
  for (int k = 0; k < e->n_params; ++k) {
    const TlParam *p = &e->params[k];
    char def[32], lo[32], hi[32];
    number(def, sizeof def, p->def, md);
    number(lo, sizeof lo, p->lo, md);
    number(hi, sizeof hi, p->hi, md);
    const char *unit = p->unit && p->unit[0] ? p->unit : NULL, *help = p->help && p->help[0] ? p->help : NULL;
    if (!unit) {
      g->n_no_unit++;
      tl_text_printf(&g->list, md ? "- %s `%s`, parameter `%s`: no unit (dimensionless, or unstated)\n"
                                  : "  %s %s, parameter %s: no unit (dimensionless, or unstated)\n",
                     e->kind, e->name, p->name);
    }
    if (!help) {
      g->n_no_help++;
      tl_text_printf(&g->list, md ? "- %s `%s`, parameter `%s`: no description\n" : "  %s %s, parameter %s: no description\n",
                     e->kind, e->name, p->name);
    }
    if (md) {
      fprintf(out, "| `%s` | %s | [%s, %s] | %s | ", p->name, def, lo, hi, unit ? unit : "—");
      cell(out, help ? help : "");
      fprintf(out, " |\n");
    } else {
      fprintf(out, "    %-18s default %-10s range [%s, %s]  unit %s\n", p->name, def, lo, hi, unit ? unit : "-");
      if (help) fprintf(out, "      %s\n", help);
    }
  }
}

static TlStatus write_catalogue(FILE *out, int md, size_t *n_types, size_t *n_kinds, size_t *n_gaps)
{
  size_t n = 0;
  while (tl_registry_at(n)) ++n;
  const TlTypeEntry **all = NULL;
  TL_CHECK(tl_calloc(&all, n ? n : 1, sizeof *all));
  for (size_t i = 0; i < n; ++i) all[i] = tl_registry_at(i);
  qsort(all, n, sizeof *all, by_kind_name);
  size_t nk = 0;
  for (size_t i = 0; i < n; ++i) nk += i == 0 || strcmp(all[i]->kind, all[i - 1]->kind) != 0;

  if (md) {
    fprintf(out, "# Catalogue of registered types\n\n"
                 "Every type the library registers by name, with its parameters: %zu types of %zu kinds.\n"
                 "Generated from the registries by `build/bin/talus_catalogue -output docs/catalogue.md`;\n"
                 "do not edit by hand: the test `catalogue_current` fails when this file differs from the\n"
                 "program's output.  A type added from outside the library (`Examples/`) registers the same way\n"
                 "and appears in the catalogue of a program that registered it.  Ranges are closed; ∞ marks no\n"
                 "limit; a unit `1` is a dimensionless number or a switch (0 or 1); a default `required` is a value\n"
                 "the caller must give.\n\n## Kinds\n\n",
            n, nk);
    for (size_t i = 0; i < n; ++i) {
      if (i && strcmp(all[i]->kind, all[i - 1]->kind) == 0) continue;
      size_t c = 0;
      for (size_t j = i; j < n && strcmp(all[j]->kind, all[i]->kind) == 0; ++j) ++c;
      const char *how, *title = kind_title(all[i]->kind, &how);
      fprintf(out, "- [%s](#%s) (`%s`, %zu)\n", title, all[i]->kind, all[i]->kind, c);
    }
  } else {
    fprintf(out, "Talus: %zu registered types of %zu kinds\n", n, nk);
  }
  Gaps g = {0};
  for (size_t i = 0; i < n; ++i) {
    if (i == 0 || strcmp(all[i]->kind, all[i - 1]->kind) != 0) {
      const char *how, *title = kind_title(all[i]->kind, &how);
      if (md) {
        fprintf(out, "\n<a id=\"%s\"></a>\n\n## %s (`%s`)\n", all[i]->kind, title, all[i]->kind);
        if (how) fprintf(out, "\nChosen by %s.\n", how);
      } else {
        fprintf(out, "\n%s (kind %s)\n", title, all[i]->kind);
      }
    }
    entry(out, all[i], md, &g);
  }
  size_t gaps = g.n_no_unit + g.n_no_help + g.n_no_description;
  if (md)
    fprintf(out, "\n## Gaps\n\n%zu parameters without a unit (most are dimensionless numbers or switches), %zu without "
                 "a description, %zu types without a description.\n\n%s",
            g.n_no_unit, g.n_no_help, g.n_no_description, g.list.text ? g.list.text : "");
  else
    fprintf(out, "\nGaps: %zu parameters without a unit, %zu without a description, %zu types without a description\n%s",
            g.n_no_unit, g.n_no_help, g.n_no_description, g.list.text ? g.list.text : "");
  tl_text_free(&g.list);
  tl_free(&all);
  *n_types = n, *n_kinds = nk, *n_gaps = gaps;
  return TL_OK;
}

static TlStatus run(int argc, char **argv)
{
  double wall0 = tl_wtime();
  TL_CHECK(tl_initialize());
  TlOptions *opt;
  TL_CHECK(tl_options_create(argc, argv,
                             "Lists every registered type (contact-law parts, walls, element types, materials, "
                             "steppers, solvers, CG kernels, ...) with its parameters, units, defaults and ranges. "
                             "docs/catalogue.md is its Markdown output.",
                             &opt));
  static const char *const formats[] = {"markdown", "text", NULL};
  int format;
  const char *output;
  TlStatus s = tl_options_get_choice(opt, "-format", "markdown", formats, "markdown (docs/catalogue.md) or plain text",
                                     &format);
  if (s == TL_OK)
    s = tl_options_get_string(opt, "-output", "-", "file to write the catalogue to ('-': standard output, the summary "
                                                   "then goes to standard error)", &output);
  if (s == TL_OK) s = tl_options_finish(opt, stdout);
  if (s != TL_OK) {
    tl_options_destroy(&opt);
    return s;
  }
  size_t n_types = 0, n_kinds = 0, n_gaps = 0;
  FILE *summary_out = stdout;
  if (strcmp(output, "-") == 0) {
    s = write_catalogue(stdout, format == 0, &n_types, &n_kinds, &n_gaps);
    summary_out = stderr;
  } else {
    TlAtomicFile *f;
    s = tl_atomic_file_open(output, &f);
    if (s == TL_OK) {
      s = write_catalogue(tl_atomic_file_stream(f), format == 0, &n_types, &n_kinds, &n_gaps);
      if (s == TL_OK) s = tl_atomic_file_commit(&f);
      else tl_atomic_file_abort(&f);
    }
  }
  tl_options_destroy(&opt);
  TL_CHECK(s);
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "types", (long)n_types);
  tl_summary_int(&sum, "kinds", (long)n_kinds);
  tl_summary_int(&sum, "gaps", (long)n_gaps);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  TL_CHECK(tl_summary_print(&sum, summary_out));
  return TL_OK;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
