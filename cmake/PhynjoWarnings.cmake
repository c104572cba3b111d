include_guard(GLOBAL)
# phynjo_warnings(TARGET): the project's warning policy. -Werror=switch makes every pass over
# the expression node kinds exhaustive: a switch without `default` that misses a Kind fails
# to compile.
function(phynjo_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
    -Werror=switch -Werror=return-type)
endfunction()
