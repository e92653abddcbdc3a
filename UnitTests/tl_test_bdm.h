/* Test support for the bridging-domain coupling: the couple of a bar of
 * elements and a DEM region made the same way by every bridging test, and
 * its teardown. */
#ifndef TL_TEST_BDM_H
#define TL_TEST_BDM_H

#include "tl_bdm.h"
#include "tl_dem.h"
#include "tl_material.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_stepper.h"

/* Couples block 0 of solid to dem over one zone with options o, sets the
 * solid up and makes its central-difference stepper at rest at t = 0; the
 * caller then sets the DEM up and calls tl_bdm_setup(*bdm, *st). */
static inline TlStatus test_bdm_couple(TlSolid *solid, TlDem *dem, const TlBdmZone *zone, const TlBdmOptions *o,
                                       TlBdm **bdm, TlStepper **st)
{
  TL_CHECK(tl_bdm_create(solid, 0, dem, zone, 1, o, bdm));
  TL_CHECK(tl_solid_setup(solid));
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  TL_CHECK(tl_stepper_create("central_difference", tl_solid_system(solid), &so, st));
  TL_CHECK(tl_stepper_set_state(*st, 0.0, NULL, NULL));
  return TL_OK;
}

/* Destroys what a bridging test made, the coupling first (any may be NULL). */
static inline void test_bdm_destroy(TlBdm **bdm, TlStepper **st, TlSolid **solid, TlMaterial **mat, TlMesh **mesh,
                                    TlDem **dem)
{
  tl_bdm_destroy(bdm);
  tl_stepper_destroy(st);
  tl_solid_destroy(solid);
  tl_material_destroy(mat);
  tl_mesh_destroy(mesh);
  tl_dem_destroy(dem);
}

#endif
