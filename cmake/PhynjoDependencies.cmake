# Third-party dependencies, all from Debian packages (scripts/install-deps).
# Also included by the installed phynjoConfig.cmake, so keep it self-contained.
include_guard(GLOBAL)
find_package(PkgConfig REQUIRED)
if(NOT TARGET PkgConfig::GMPXX)
  pkg_check_modules(GMPXX REQUIRED IMPORTED_TARGET GLOBAL gmpxx gmp)
endif()
find_package(Boost 1.74 REQUIRED)   # header-only: Spirit X3
find_package(Eigen3 3.3 REQUIRED NO_MODULE) # rigid bodies: rotation and inertia matrices
find_package(Threads REQUIRED)
find_package(SUNDIALS 6 REQUIRED CONFIG) # CVODE: stiff integration of generated models (libsundials-dev)
