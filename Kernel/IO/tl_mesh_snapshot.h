/* Mesh snapshots: HDF5 files plus an XDMF series, like particle snapshots.
 *
 * The mesh itself (reference coordinates and the connectivity of every
 * element block) goes to <dir>/<name>_mesh_<m>.h5, written once and again
 * only when it changes (the writer compares a checksum of coordinates and
 * connectivity at each step).  Each step writes <dir>/<name>_<k>.h5 with the
 * displacement and the nodal and cell fields, and rewrites <dir>/<name>.xmf.
 * The geometry is the reference configuration; open <name>.xmf in ParaView
 * and apply "Warp By Vector" with the "displacement" array to see the
 * deformed body.  One block becomes a Uniform grid; several blocks become a
 * Spatial collection (a multiblock data set), one grid per block.
 *
 * Cell types and node ordering: connectivity follows VTK's node ordering for
 * each type (the order ParaView expects), zero-based node indices:
 *   tri3   Triangle        corners counter-clockwise
 *   tri6   Triangle_6      corners, then mid-edges 01 12 20
 *   quad4  Quadrilateral   corners counter-clockwise
 *   quad8  Quadrilateral_8 corners, then mid-edges 01 12 23 30
 *   quad9  Quadrilateral_9 quad8, then the centre
 *   tet4   Tetrahedron     corners 0 1 2 (base, counter-clockwise seen from 3), 3
 *   tet10  Tetrahedron_10  corners, then mid-edges 01 12 20 03 13 23
 *   hex8   Hexahedron      bottom face 0 1 2 3, top face 4 5 6 7 above them
 *   hex20  Hexahedron_20   corners, mid-edges 01 12 23 30, 45 56 67 74, 04 15 26 37
 *   hex27  Hexahedron_27   hex20, then face centres x-, x+, y-, y+, z-, z+
 *                          (faces 0473, 1265, 0154, 3762, 0321, 4567), then the body centre
 *   wedge6   Wedge         triangle 0 1 2, then 3 4 5 above them
 *   wedge15  Wedge_15      corners, mid-edges 01 12 20, 34 45 53, 03 14 25
 *   wedge18  Wedge_18      wedge15, then the centres of the quadrilaterals 0143, 1254, 2035
 *   pyramid5 Pyramid       base 0 1 2 3, apex 4
 *   pyramid13 Pyramid_13   corners, mid-edges 01 12 23 30, 04 14 24 34
 * An element type names its cell and the map from its own node order to
 * this one (tl_element.h), so the writers need no list of element types.
 *
 * Layout of <name>_mesh_<m>.h5:
 *   /                                 attributes format = "talus-mesh", format_version
 *   /mesh/reference_coordinates       n_nodes x 3
 *   /mesh/blocks/<block>/connectivity n_cells x nodes_per_cell (int32); attribute cell_type
 * Layout of <name>_<k>.h5:
 *   /                                 attributes format = "talus-mesh-step", format_version,
 *                                     time, step, mesh_file (the mesh file's name)
 *   /mesh/displacement                n_nodes x 3 (optional)
 *   /mesh/node_fields/<field>         n_nodes [x c]
 *   /mesh/blocks/<block>/cell_fields/<field>  n_cells [x c]
 * Groups holding fields list them in an attribute "names". */
#ifndef TL_MESH_SNAPSHOT_H
#define TL_MESH_SNAPSHOT_H

#include <stddef.h>
#include <stdint.h>

#include "tl_checkpoint.h"
#include "tl_error.h"
#include "tl_math.h"
#include "tl_xdmf.h"

#define TL_MESH_FORMAT_VERSION 1

typedef enum {
  TL_CELL_TRI3,
  TL_CELL_TRI6,
  TL_CELL_QUAD4,
  TL_CELL_QUAD8,
  TL_CELL_QUAD9,
  TL_CELL_TET4,
  TL_CELL_TET10,
  TL_CELL_HEX8,
  TL_CELL_HEX20,
  TL_CELL_HEX27,
  TL_CELL_WEDGE6,
  TL_CELL_WEDGE15,
  TL_CELL_WEDGE18,
  TL_CELL_PYRAMID5,
  TL_CELL_PYRAMID13,
  TL_CELL_TYPE_COUNT
} TlCellType;

/* Short name ("hex27"), XDMF topology name ("Hexahedron_27"), VTK cell
 * code (29; 0 for an invalid type), nodes per cell. */
const char *tl_cell_type_name(TlCellType type);
const char *tl_cell_type_xdmf(TlCellType type);
int tl_cell_type_vtk(TlCellType type);
int tl_cell_type_nodes(TlCellType type);
/* Finds a cell type by short name; error lists the known names. */
TlStatus tl_cell_type_from_name(const char *name, TlCellType *type);

typedef struct {
  const char *name;         /* letters, digits, '_', '.', '-' */
  TlCellType type;
  size_t n_cells;
  const int *connectivity;  /* n_cells x nodes per cell, zero-based, VTK order */
  size_t n_fields;          /* cell fields of this block */
  const TlField *fields;
} TlMeshBlock;

typedef struct {
  size_t n_nodes;
  const TlVec3 *reference;     /* required */
  const TlVec3 *displacement;  /* optional */
  size_t n_node_fields;
  const TlField *node_fields;
  size_t n_blocks;
  const TlMeshBlock *blocks;
} TlMeshView;

typedef struct TlMeshWriter TlMeshWriter;

TlStatus tl_mesh_writer_create(const char *dir, const char *name, TlMeshWriter **writer);
void tl_mesh_writer_destroy(TlMeshWriter **writer);
/* Checks the view (node indices in range, field names, ...), then writes. */
TlStatus tl_mesh_writer_write(TlMeshWriter *writer, int64_t step, double time, const TlMeshView *view);
size_t tl_mesh_writer_count(const TlMeshWriter *writer);
/* The last step file written ("" before any), and the current mesh file. */
const char *tl_mesh_writer_last_path(const TlMeshWriter *writer);
const char *tl_mesh_writer_mesh_path(const TlMeshWriter *writer);
/* Counter, mesh-file index, checksum and XDMF list, for restarts. */
extern const TlCheckpointOps tl_mesh_writer_checkpoint_ops;

/* ---------------------------------------------------------------- reading */
typedef struct {
  char *name;
  TlCellType type;
  size_t n_cells;
  int *connectivity;
  size_t n_fields;
  char **field_names;
  int *field_components;
  double **field_data;
} TlMeshSnapshotBlock;

typedef struct {
  double time;
  int64_t step;
  size_t n_nodes;
  TlVec3 *reference;
  TlVec3 *displacement; /* NULL when absent */
  size_t n_node_fields;
  char **node_field_names;
  int *node_field_components;
  double **node_field_data;
  size_t n_blocks;
  TlMeshSnapshotBlock *blocks;
} TlMeshSnapshot;

/* Reads a step file and the mesh file it names (in the same folder). */
TlStatus tl_mesh_snapshot_read(const char *path, TlMeshSnapshot *snapshot);
void tl_mesh_snapshot_free(TlMeshSnapshot *snapshot);

#endif
