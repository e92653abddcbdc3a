# Finds the SuiteSparse components Talus uses (CHOLMOD, KLU, UMFPACK and their
# ordering and configuration libraries).  Debian's SuiteSparse 5.x ships no
# CMake package, so the headers and libraries are located directly.
# Defines SuiteSparse_FOUND and the imported target SuiteSparse::SuiteSparse.
find_path(SuiteSparse_INCLUDE_DIR NAMES cholmod.h klu.h umfpack.h
  PATH_SUFFIXES suitesparse)
set(_ss_libs cholmod klu umfpack btf amd colamd camd ccolamd suitesparseconfig)
set(SuiteSparse_LIBRARIES)
foreach(lib IN LISTS _ss_libs)
  find_library(SuiteSparse_${lib}_LIBRARY NAMES ${lib})
  if(SuiteSparse_${lib}_LIBRARY)
    list(APPEND SuiteSparse_LIBRARIES ${SuiteSparse_${lib}_LIBRARY})
  endif()
endforeach()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparse REQUIRED_VARS SuiteSparse_INCLUDE_DIR
  SuiteSparse_cholmod_LIBRARY SuiteSparse_klu_LIBRARY SuiteSparse_umfpack_LIBRARY
  SuiteSparse_suitesparseconfig_LIBRARY)
if(SuiteSparse_FOUND AND NOT TARGET SuiteSparse::SuiteSparse)
  add_library(SuiteSparse::SuiteSparse INTERFACE IMPORTED)
  set_target_properties(SuiteSparse::SuiteSparse PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${SuiteSparse_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${SuiteSparse_LIBRARIES}")
endif()
