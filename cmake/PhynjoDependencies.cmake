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
# MPI (libopenmpi-dev): sweeps shared among ranks (phynjo::mpi). PHYNJO_MPI is an option of the
# build (default ON) and recorded in the installed package.
if(PHYNJO_MPI)
  set(MPI_CXX_SKIP_MPICXX ON) # the C API only: no deprecated C++ bindings
  find_package(MPI COMPONENTS CXX)
  if(NOT MPI_CXX_FOUND)
    message(FATAL_ERROR "phynjo: MPI not found: install Debian's libopenmpi-dev and openmpi-bin "
                        "(scripts/install-deps does), or configure with -DPHYNJO_MPI=OFF")
  endif()
endif()
