# phynjo_module(NAME SOURCES file… [LINK target…]): the library of one module — target
# phynjo_NAME, alias phynjo::NAME (exported as phynjo::NAME), public headers under
# NAME/include/phynjo/NAME/, C++20, project warnings, installed with its headers; with
# PHYNJO_PYTHON, position-independent (the Python module links it).
include_guard(GLOBAL)
include(GNUInstallDirs)
function(phynjo_module name)
  cmake_parse_arguments(M "" "" "SOURCES;LINK" ${ARGN})
  set(t phynjo_${name})
  add_library(${t} ${M_SOURCES})
  add_library(phynjo::${name} ALIAS ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME ${t})
  target_include_directories(${t} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${t} PUBLIC ${M_LINK})
  target_compile_features(${t} PUBLIC cxx_std_20)
  phynjo_warnings(${t})
  if(PHYNJO_PYTHON)
    # linked into the Python module, a shared object: position-independent code, without the
    # cost of interposable calls between the library's own functions
    set_target_properties(${t} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    target_compile_options(${t} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-fno-semantic-interposition>)
  endif()
  install(TARGETS ${t} EXPORT phynjoTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
