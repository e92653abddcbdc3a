/* The Gmsh reader on hostile files (each refused by name, no mesh, nothing
 * read or written out of bounds, nothing leaked: the sanitizer run checks):
 *  - a second $Nodes section after $Elements (it used to replace the node
 *    numbering the elements refer to: a heap overflow), a second $Elements
 *    or $Entities section;
 *  - a file cut inside a node block (the block's tag list used to leak);
 *  - headers announcing more nodes or elements than the file can hold
 *    (refused before they size an allocation). */
#include <string.h>

#include "talus.h"
#include "tl_mesh.h"
#include "tl_test.h"

/* A plane 8-node-quadrilateral mesh written by gmsh 4.8 (msh 4.1), the one
 * of test_fem_mesh. */
static const char quad8_msh[] =
    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
    "$PhysicalNames\n3\n0 3 \"corner\"\n1 2 \"bottom\"\n2 1 \"plate\"\n$EndPhysicalNames\n"
    "$Entities\n4 4 1 0\n1 0 0 0 1 3 \n2 1 0 0 0 \n3 1 0.5 0 0 \n4 0 0.5 0 0 \n"
    "1 0 0 0 1 0 0 1 2 2 1 -2 \n2 1 0 0 1 0.5 0 0 2 2 -3 \n3 0 0.5 0 1 0.5 0 0 2 3 -4 \n"
    "4 0 0 0 0 0.5 0 0 2 4 -1 \n1 0 0 0 1 0.5 0 1 1 4 1 2 3 4 \n$EndEntities\n"
    "$Nodes\n9 21 1 21\n0 1 0 1\n1\n0 0 0\n0 2 0 1\n2\n1 0 0\n0 3 0 1\n3\n1 0.5 0\n0 4 0 1\n4\n0 0.5 0\n"
    "1 1 0 3\n5\n6\n7\n0.499999999998694 0 0\n0.2499999999994194 0 0\n0.749999999999347 0 0\n"
    "1 2 0 3\n8\n9\n10\n1 0.249999999999347 0\n1 0.1249999999997097 0\n1 0.3749999999996735 0\n"
    "1 3 0 3\n11\n12\n13\n0.5000000000020591 0.5 0\n0.7500000000009891 0.5 0\n0.2500000000010296 0.5 0\n"
    "1 4 0 3\n14\n15\n16\n0 0.2500000000010296 0\n0 0.3750000000004945 0\n0 0.1250000000005148 0\n"
    "2 1 0 5\n17\n18\n19\n20\n21\n0.5000000000003766 0.2500000000001883 0\n"
    "0.4999999999995353 0.1250000000000941 0\n0.2500000000001883 0.250000000000609 0\n"
    "0.5000000000012179 0.3750000000000941 0\n0.7500000000001883 0.2499999999997676 0\n$EndNodes\n"
    "$Elements\n3 7 1 7\n0 1 15 1\n1 1 \n1 1 8 2\n2 1 5 6 \n3 5 2 7 \n2 1 16 4\n"
    "4 1 5 17 14 6 18 19 16 \n5 14 17 11 4 19 20 13 15 \n6 5 2 8 17 7 9 21 18 \n"
    "7 17 8 3 11 21 10 12 20 \n$EndElements\n";

static void write_file(const char *path, const char *text, size_t n)
{
  FILE *f = fopen(path, "wb");
  if (!f) return;
  fwrite(text, 1, n, f);
  fclose(f);
}

/* Reads `text` (n bytes) and expects a format error whose message holds
 * `fragment`. */
static void refused(const char *what, const char *text, size_t n, const char *fragment)
{
  write_file("hostile.msh", text, n);
  TlMesh *m = NULL;
  TlStatus s = tl_mesh_read_gmsh("hostile.msh", &m);
  TL_TEST_ASSERT(s == TL_ERR_FORMAT && strstr(tl_error_message(), fragment), "%s: status %d, message '%s' (expected '%s')",
                 what, (int)s, tl_error_message(), fragment);
  TL_TEST_ASSERT(m == NULL, "%s: no mesh on error", what);
  tl_mesh_destroy(&m);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  char text[sizeof quad8_msh + 512];
  /* The file itself reads. */
  TlMesh *m = NULL;
  write_file("good.msh", quad8_msh, strlen(quad8_msh));
  TL_TEST_STATUS(tl_mesh_read_gmsh("good.msh", &m), TL_OK);
  TL_TEST_ASSERT(m && m->n_nodes == 21, "the good file gives 21 nodes");
  tl_mesh_destroy(&m);

  /* A second, smaller $Nodes section after $Elements. */
  snprintf(text, sizeof text, "%s$Nodes\n1 1 1 1\n0 1 0 1\n1\n0 0 0\n$EndNodes\n", quad8_msh);
  refused("second $Nodes", text, strlen(text), "second $Nodes");
  snprintf(text, sizeof text, "%s$Elements\n1 1 1 1\n0 1 15 1\n1 1\n$EndElements\n", quad8_msh);
  refused("second $Elements", text, strlen(text), "second $Elements");
  const char *ent = strstr(quad8_msh, "$Entities"), *ent_end = strstr(quad8_msh, "$EndEntities\n");
  size_t pre = (size_t)(ent_end + strlen("$EndEntities\n") - quad8_msh);
  memcpy(text, quad8_msh, pre);
  memcpy(text + pre, ent, pre - (size_t)(ent - quad8_msh));
  strcpy(text + pre + (pre - (size_t)(ent - quad8_msh)), quad8_msh + pre);
  refused("second $Entities", text, strlen(text), "second $Entities");

  /* Cut inside every node block: after each block header and inside the
   * coordinates. */
  const char *nodes = strstr(quad8_msh, "$Nodes"), *end_nodes = strstr(quad8_msh, "$EndNodes");
  int cuts = 0;
  for (const char *p = nodes + 20; p < end_nodes; p += 7, ++cuts) refused("cut node block", quad8_msh, (size_t)(p - quad8_msh), "line");
  TL_TEST_ASSERT(cuts > 20, "%d cuts", cuts);

  /* Counts beyond what the file holds. */
  const char *hdr = "$Nodes\n9 21 1 21\n";
  const char *at = strstr(quad8_msh, hdr);
  pre = (size_t)(at - quad8_msh);
  memcpy(text, quad8_msh, pre);
  snprintf(text + pre, sizeof text - pre, "$Nodes\n9 900000000 1 21\n%s", at + strlen(hdr));
  refused("huge node count", text, strlen(text), "number of nodes");
  hdr = "$Elements\n3 7 1 7\n";
  at = strstr(quad8_msh, hdr);
  pre = (size_t)(at - quad8_msh);
  memcpy(text, quad8_msh, pre);
  snprintf(text + pre, sizeof text - pre, "$Elements\n3 900000000 1 7\n%s", at + strlen(hdr));
  refused("huge element count", text, strlen(text), "number of elements");
  return tl_test_report();
}
