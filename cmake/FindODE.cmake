# Finds the Open Dynamics Engine through the pkg-config file Debian's libode-dev ships, and
# provides the imported target ODE::ODE.
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(PC_ODE QUIET ode)
endif()
find_path(ODE_INCLUDE_DIR ode/ode.h HINTS ${PC_ODE_INCLUDE_DIRS})
find_library(ODE_LIBRARY NAMES ode HINTS ${PC_ODE_LIBRARY_DIRS})
set(ODE_VERSION ${PC_ODE_VERSION})
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(ODE REQUIRED_VARS ODE_LIBRARY ODE_INCLUDE_DIR VERSION_VAR ODE_VERSION)
if(ODE_FOUND AND NOT TARGET ODE::ODE)
  add_library(ODE::ODE UNKNOWN IMPORTED)
  set_target_properties(ODE::ODE PROPERTIES
    IMPORTED_LOCATION "${ODE_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${ODE_INCLUDE_DIR}"
    INTERFACE_COMPILE_DEFINITIONS "${PC_ODE_CFLAGS_OTHER}")
endif()
mark_as_advanced(ODE_INCLUDE_DIR ODE_LIBRARY)
