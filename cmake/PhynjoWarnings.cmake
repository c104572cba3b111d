include_guard(GLOBAL)
# phynjo_warnings(TARGET): the project's warning policy. -Werror=switch makes every pass over
# the expression node kinds exhaustive: a switch without `default` that misses a Kind fails
# to compile.
function(phynjo_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
    -Werror=switch -Werror=return-type
    # GCC 12 reports std::string concatenations as overlapping memcpy (its bug 105329)
    $<$<AND:$<CXX_COMPILER_ID:GNU>,$<VERSION_LESS:$<CXX_COMPILER_VERSION>,13>>:-Wno-restrict>)
endfunction()
