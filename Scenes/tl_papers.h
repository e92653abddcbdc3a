/* The papers Talus reproduces, cited in full once here for the drivers'
 * -help texts (string literals, to be concatenated); comments elsewhere cite
 * them by authors and year. */
#ifndef TL_PAPERS_H
#define TL_PAPERS_H

/* Surface and volume coupling with coarse-graining; the S1 particle-cantilever
 * and V1 wave tests (§6.1, §6.2). */
#define TL_PAPER_CHENG_2022                                                                              \
  "H. Cheng, A. R. Thornton, S. Luding, A. L. Hazel, T. Weinhart, \"Concurrent multi-scale modeling of " \
  "granular materials: role of coarse-graining in FEM-DEM coupling\", Computer Methods in Applied "      \
  "Mechanics and Engineering 403 (2023) 115651, doi:10.1016/j.cma.2022.115651"

/* The bridging domain method for a pre-stressed gouge; its packings and
 * elastic tensors (§3), the B1 gouge scene (§4-5). */
#define TL_PAPER_VOISIN_LEPRINCE_2023                                                                    \
  "M. Voisin-Leprince, J. Garcia-Suarez, G. Anciaux, J.-F. Molinari, \"Finite element method-discrete " \
  "element method bridging coupling for the modeling of gouge\", International Journal for Numerical "  \
  "Methods in Engineering (2023), doi:10.1002/nme.7171"

/* FEM x DEM (cited by its open-archive handle, whose record names the
 * journal and date): a periodic DEM cell at every Gauss point (the numerically
 * homogenised law, its tangent operators, the biaxial test). */
#define TL_PAPER_DESRUES_2019                                                                            \
  "J. Desrues, A. Argilaga, D. Caillerie, G. Combe, T. K. Nguyen, V. Richefeu, S. dal Pont, \"From "    \
  "discrete to continuum modelling of boundary value problems in geomechanics: an integrated FEM-DEM "  \
  "approach\", International Journal for Numerical and Analytical Methods in Geomechanics (2019), "     \
  "hdl:2268/233597"

#endif
