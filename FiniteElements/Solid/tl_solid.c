/* Life cycle of a solid, and what the other files of the solid share:
 * block lookup, the set-up guard, errors raised from worker threads, dof
 * maps. */
#include "tl_solid_private.h"

#include <stdio.h>
#include <string.h>

#include "tl_memory.h"

/* ----------------------------------------------------------- utilities */

int tl_solid_block_of_name(const TlSolid *s, const char *name, int *b)
{
  if (!name) {
    *b = -1;
    return 1;
  }
  return tl_mesh_find_block(s->mesh, name, b) == TL_OK;
}

TlStatus tl_solid_not_after_setup(const TlSolid *s, const char *what)
{
  if (s->ready)
    TL_ERROR(TL_ERR_STATE, "solid: %s after tl_solid_setup (conditions are frozen)", what);
  return TL_OK;
}

void tl_solid_parallel_error_record(ParallelError *pe, TlStatus s)
{
#pragma omp critical(tl_solid_error)
  {
    if (pe->status == TL_OK) {
      snprintf(pe->message, sizeof pe->message, "%s", tl_error_message());
      pe->status = s;
    }
  }
}

TlStatus tl_solid_parallel_error_raise(const ParallelError *pe)
{
  if (pe->status == TL_OK) return TL_OK;
  return tl_error_set(pe->status, __FILE__, __LINE__, "%s", pe->message);
}

/* ----------------------------------------------------- create / config */

TlStatus tl_solid_create(const TlMesh *mesh, TlSolid **solid)
{
  if (!mesh || !solid) TL_ERROR(TL_ERR_ARG, "tl_solid_create: NULL argument");
  if (!mesh->finalized) TL_ERROR(TL_ERR_STATE, "tl_solid_create: mesh not finalized");
  TlSolid *s = NULL;
  TL_CHECK(TL_NEW(s));
  s->base.ops = &tl_solid_ops_stateful;
  s->mesh = mesh;
  s->dim = mesh->dim;
  s->n_nodes = mesh->n_nodes;
  TlStatus st = TL_OK;
  TL_CHECK_GOTO(st, tl_calloc(&s->blocks, mesh->n_blocks, sizeof *s->blocks), fail);
  TL_CHECK_GOTO(st, tl_calloc(&s->constraint, s->n_nodes * s->dim, 1), fail);
  *solid = s;
  return TL_OK;
fail:
  tl_free(&s->blocks);
  tl_free(&s);
  return st;
}

TlMechSystem *tl_solid_system(TlSolid *solid) { return &solid->base; }

void tl_solid_destroy_content(TlMechSystem *sys)
{
  TlSolid *s = (TlSolid *)sys;
  for (int b = 0; b < s->mesh->n_blocks && s->blocks; ++b) {
    SolidBlock *B = &s->blocks[b];
    tl_free(&B->grad);
    tl_free(&B->grad_t);
    tl_free(&B->grad_n);
    tl_free(&B->wdet);
    tl_free(&B->Nm);
    tl_free(&B->wdetm);
    tl_free(&B->lumped);
    tl_free(&B->state_old);
    tl_free(&B->state_new);
    tl_free(&B->colour_ptr);
    tl_free(&B->colour_elements);
    tl_free(&B->pw);
    tl_free(&B->pw_mass);
    tl_free(&B->w_nodes);
    tl_free(&B->wdet_plain);
    tl_solid_points_free(B);
  }
  for (int i = 0; i < s->n_dead; ++i) tl_free(&s->dead[i].f);
  for (int t = 0; t < s->n_threads && s->scratch; ++t) {
    Scratch *w = &s->scratch[t];
    tl_free(&w->F);
    tl_free(&w->S);
    tl_free(&w->Hsoa);
    tl_free(&w->Ssoa);
    tl_free(&w->D);
    tl_free(&w->W);
    tl_free(&w->state_old);
    tl_free(&w->state_new);
    tl_free(&w->fe);
    tl_free(&w->Ke);
    tl_free(&w->B);
    tl_free(&w->DB);
    tl_free(&w->ue);
    tl_free(&w->dofs);
  }
  tl_solid_free_wrappers(s);
  tl_free(&s->scratch);
  tl_free(&s->blocks);
  tl_free(&s->constraint);
  tl_free(&s->tie_master);
  tl_free(&s->prescribed);
  tl_free(&s->body);
  tl_free(&s->surface);
  tl_free(&s->points);
  tl_free(&s->dead);
  tl_free(&s->dof);
  tl_free(&s->elem_ptr);
  tl_free(&s->elem_dofs);
  tl_free(&s->lumped_nodes);
  tl_free(&s->lumped_weights);
  tl_free(&s->un);
  tl_free(&s->fn);
  tl_free(&s->gn);
  tl_free(&s->base.dirichlet_dofs);
}

void tl_solid_destroy(TlSolid **solid)
{
  if (!solid || !*solid) return;
  TlMechSystem *sys = &(*solid)->base;
  tl_mech_system_destroy(&sys);
  *solid = NULL;
}

TlStatus tl_solid_set_material(TlSolid *s, const char *block, TlMaterial *material)
{
  TL_CHECK(tl_solid_not_after_setup(s, "set_material"));
  if (!material) TL_ERROR(TL_ERR_ARG, "solid: NULL material for block %s", block ? block : "(all)");
  int b;
  if (!tl_solid_block_of_name(s, block, &b))
    TL_ERROR(TL_ERR_NOT_FOUND, "solid: no element block '%s' for the material", block);
  for (int k = 0; k < s->mesh->n_blocks; ++k)
    if (b < 0 || k == b) s->blocks[k].material = material;
  return TL_OK;
}

/* ------------------------------------------------------------ dof maps */

void tl_solid_dofs_to_nodes(const TlSolid *s, const double *u, double *u_nodes)
{
  size_t nc = s->n_nodes * s->dim;
  for (size_t i = 0; i < nc; ++i) u_nodes[i] = s->dof[i] >= 0 ? u[s->dof[i]] : 0.0;
}

void tl_solid_nodes_to_dofs(const TlSolid *s, const double *f_nodes, double *f)
{
  /* Summed: tied nodes (tl_solid_tie) share their dofs. */
  size_t nc = s->n_nodes * s->dim;
  memset(f, 0, (size_t)s->base.ndof * sizeof *f);
  for (size_t i = 0; i < nc; ++i)
    if (s->dof[i] >= 0) f[s->dof[i]] += f_nodes[i];
}

TlSparseIndex tl_solid_dof(const TlSolid *s, size_t node, int component)
{
  if (!s->ready || node >= s->n_nodes || component < 0 || component >= s->dim) return -1;
  return s->dof[node * s->dim + component];
}

const TlMesh *tl_solid_mesh(const TlSolid *s) { return s->mesh; }
