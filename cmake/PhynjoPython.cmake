# phynjo_find_python3(VAR IMPORTS DOC): unless VAR is set, the first python3 that runs
# `import IMPORTS` — Debian's /usr/bin/python3 first (where apt's python3-* packages are), then
# the first on PATH — into the cache variable VAR; VAR stays empty when none does.
include_guard(GLOBAL)
function(phynjo_find_python3 var imports doc)
  set(${var} "${${var}}" CACHE FILEPATH "${doc}")
  if(${var})
    return()
  endif()
  find_program(PHYNJO_DEBIAN_PYTHON3 python3 PATHS /usr/bin NO_DEFAULT_PATH)
  find_program(PHYNJO_PATH_PYTHON3 python3)
  foreach(py IN ITEMS ${PHYNJO_DEBIAN_PYTHON3} ${PHYNJO_PATH_PYTHON3})
    execute_process(COMMAND ${py} -c "import ${imports}" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
    if(rc EQUAL 0)
      set(${var} ${py} CACHE FILEPATH "${doc}" FORCE)
      return()
    endif()
  endforeach()
endfunction()
