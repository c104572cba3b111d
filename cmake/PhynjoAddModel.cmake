include_guard(GLOBAL)
# phynjo_add_model(TARGET name MODEL file.lag [MAIN] [LAGC_OPTIONS option...])
#
# Runs phynjo-lagc at build time (again whenever the .lag file or the compiler changes) and
# makes a target whose include path holds the generated header, so that `#include
# "name.hpp"` works: a static library, or with MAIN an executable whose main() simulates the
# model (see `name --help`; built with MPI, it shares a sweep among the ranks of `mpirun`). The generated files are named after TARGET. Works in the phynjo
# build tree (add_subdirectory) and after find_package(phynjo CONFIG).
function(phynjo_add_model)
  cmake_parse_arguments(PHYNJO "MAIN" "TARGET;MODEL" "LAGC_OPTIONS" ${ARGN})
  if(NOT PHYNJO_TARGET OR NOT PHYNJO_MODEL)
    message(FATAL_ERROR "phynjo_add_model: TARGET and MODEL are required")
  endif()
  if(NOT TARGET phynjo::phynjo-lagc)
    message(FATAL_ERROR "phynjo_add_model: phynjo::phynjo-lagc not found (find_package(phynjo CONFIG) first)")
  endif()
  get_filename_component(model "${PHYNJO_MODEL}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  set(dir "${CMAKE_CURRENT_BINARY_DIR}/phynjo_generated/${PHYNJO_TARGET}")
  set(src "${dir}/${PHYNJO_TARGET}.cpp")
  set(hdr "${dir}/${PHYNJO_TARGET}.hpp")
  # a big model's largest functions go to three more files that compile in parallel; a small
  # model's hold a comment only (phynjo-lagc --parts)
  set(parts "${dir}/${PHYNJO_TARGET}.part2.cpp" "${dir}/${PHYNJO_TARGET}.part3.cpp" "${dir}/${PHYNJO_TARGET}.part4.cpp")
  set(flags --parts 4 ${PHYNJO_LAGC_OPTIONS})
  if(PHYNJO_MAIN)
    list(APPEND flags --main)
  endif()
  file(MAKE_DIRECTORY "${dir}")
  add_custom_command(
    OUTPUT "${src}" "${hdr}" ${parts}
    COMMAND $<TARGET_FILE:phynjo::phynjo-lagc> "${model}" -o "${src}" ${flags}
    DEPENDS "${model}" $<TARGET_FILE:phynjo::phynjo-lagc>
    COMMENT "phynjo-lagc ${PHYNJO_MODEL} -> ${PHYNJO_TARGET}.cpp"
    VERBATIM)
  if(PHYNJO_MAIN)
    add_executable(${PHYNJO_TARGET} "${src}" ${parts} "${hdr}")
  else()
    add_library(${PHYNJO_TARGET} STATIC "${src}" ${parts} "${hdr}")
  endif()
  target_include_directories(${PHYNJO_TARGET} PUBLIC "${dir}")
  target_link_libraries(${PHYNJO_TARGET} PUBLIC phynjo::runtime)
  if(PHYNJO_MAIN AND TARGET phynjo::mpi)
    # the simulator shares sweeps among MPI ranks when mpirun starts it (phynjo/mpi/mpi_sweep.hpp)
    target_link_libraries(${PHYNJO_TARGET} PRIVATE phynjo::mpi)
    target_compile_definitions(${PHYNJO_TARGET} PRIVATE PHYNJO_MPI=1)
  endif()
  target_compile_features(${PHYNJO_TARGET} PUBLIC cxx_std_20)
  # the contract: the generated pair compiles warning-free
  target_compile_options(${PHYNJO_TARGET} PRIVATE -Wall -Wextra -Werror)
  # GCC's SLP vectorizer is the costliest -O2/-O3 pass on long straight-line bodies and buys
  # them next to nothing (nlink_cart(40): 23.2 -> 20.2 s of build on two cores; nlink_cart(10)'s
  # functions within +-3% at run time; bench/RESULTS.md)
  target_compile_options(${PHYNJO_TARGET} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-fno-tree-slp-vectorize>)
  # every operation rounded once, whatever -march: the fused kernels (rk4_step,
  # accelerations_energy_guards) give the bits of the functions they fuse, which a multiply-add
  # contracted in one of them and not in the other would break (docs/generated-code.md)
  target_compile_options(${PHYNJO_TARGET} PRIVATE $<$<CXX_COMPILER_ID:GNU,Clang>:-ffp-contract=off>)
  # a build for this machine (PHYNJO_NATIVE) compiles its models as its kernels (jit/src/compile.cpp):
  # a model run by phynjo-run or from Python and the same model built here give the same bits
  if(PHYNJO_NATIVE)
    target_compile_options(${PHYNJO_TARGET} PRIVATE -march=native)
  endif()
endfunction()
