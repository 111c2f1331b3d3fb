# Finds CHOLMOD (SuiteSparse) for Eigen's CholmodSupport: defines the imported target
# RbaaCholmod::cholmod (headers in /usr/include/suitesparse on Debian).
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(RbaaCholmod DEFAULT_MSG CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR)
if(RbaaCholmod_FOUND AND NOT TARGET RbaaCholmod::cholmod)
  add_library(RbaaCholmod::cholmod UNKNOWN IMPORTED)
  set_target_properties(RbaaCholmod::cholmod PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}")
endif()
