/* XDMF sidecars: a growing text buffer, the XML pieces shared by particle
 * and mesh snapshots, and a temporal series file (<name>.xmf) that lists
 * every step written so far and is rewritten atomically after each step, so
 * ParaView opens the whole series at any moment of a run.
 *
 * The heavy data stay in HDF5 files; the XDMF file only points at datasets
 * ("<file>.h5:/particles/position") with paths relative to the .xmf file's
 * folder, so an output folder can be moved as a whole. */
#ifndef TL_XDMF_H
#define TL_XDMF_H

#include <stddef.h>

#include "tl_checkpoint.h"
#include "tl_error.h"

/* ---------------------------------------------------------------- text */
typedef struct {
  char *text; /* NUL-terminated */
  size_t length, capacity;
} TlText;

TlStatus tl_text_printf(TlText *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void tl_text_clear(TlText *t);
void tl_text_free(TlText *t);

/* ---------------------------------------------------------------- fields */
/* A named field attached to particles, mesh nodes or mesh cells. */
typedef struct {
  const char *name;   /* letters, digits, '_', '.', '-' */
  int components;     /* 1 scalar, 3 vector, 6 symmetric tensor, 9 tensor; other counts up to 64 are
                         written as an XDMF Matrix */
  const double *data; /* n x components, row-major */
} TlField;

/* Checks a field's name and component count; `owner` names it in errors. */
TlStatus tl_field_check(const TlField *field, const char *owner);
/* XDMF AttributeType for a component count: Scalar, Vector, Tensor6, Tensor, Matrix. */
const char *tl_xdmf_attribute_type(int components);
/* Appends an <Attribute> whose data is the dataset `dataset` of `h5file`
 * with n rows of `components` values of `precision` bytes (Float).
 * center is "Node" or "Cell". */
TlStatus tl_xdmf_attribute(TlText *xml, const char *indent, const char *name, int components, const char *center,
                           size_t n, const char *h5file, const char *dataset);
/* Appends a <DataItem> for an HDF5 dataset of n rows x cols (cols 0: 1-D). */
TlStatus tl_xdmf_data_item(TlText *xml, const char *indent, size_t n, size_t cols, const char *number_type,
                           int precision, const char *h5file, const char *dataset);

/* ---------------------------------------------------------------- series */
typedef struct TlXdmfSeries TlXdmfSeries;

/* A series written to `path` (e.g. "results/run/particles.xmf"). */
TlStatus tl_xdmf_series_create(const char *path, TlXdmfSeries **series);
/* What every snapshot writer (particles, meshes) holds: its folder, base
 * name, the <dir>/<name>.xmf series, the step count and last file written,
 * and a reused buffer for each step's XML. */
typedef struct {
  char *dir, *name, *xmf_path;
  TlXdmfSeries *series;
  TlText grid;
  size_t count;
  char last_path[4096];
} TlSeriesOutput;

/* Checks the base name `name` (non-empty, no '/', ':', space, quotes or <>&;
 * `what` names the writer in the error), creates the folder `dir` and opens
 * the series.  Close releases everything, also after a failed open. */
TlStatus tl_series_output_open(TlSeriesOutput *out, const char *dir, const char *name, const char *what);
void tl_series_output_close(TlSeriesOutput *out);
/* Writes any steps not yet in the file, then frees. */
void tl_xdmf_series_destroy(TlXdmfSeries **series);
/* Adds one step: `grid` is the XML of one <Grid> element that already
 * contains its <Time Value=.../>; then rewrites the .xmf atomically.  While
 * the file is under 1 MB (some 600 particle steps) this happens at every
 * step; beyond, the rewrite waits until 20 times its last duration has passed (the steps are kept and written by the next
 * rewrite, tl_xdmf_series_flush or destroy), so rewriting the sidecar never
 * takes more than about 5% of the run. */
TlStatus tl_xdmf_series_add(TlXdmfSeries *series, const char *grid);
/* Rewrites the .xmf now with every step added so far. */
TlStatus tl_xdmf_series_flush(TlXdmfSeries *series);
size_t tl_xdmf_series_steps(const TlXdmfSeries *series);
/* Saves the steps listed so far (a restarted run continues the same series);
 * load replaces the list and rewrites the file. */
extern const TlCheckpointOps tl_xdmf_series_checkpoint_ops;

#endif
