#include "tl_fem.h"

#include "tl_element.h"
#include "tl_material.h"

TlStatus tl_fem_register_all(void)
{
  TL_CHECK(tl_element_register_all());
  TL_CHECK(tl_material_register_all());
  return TL_OK;
}
