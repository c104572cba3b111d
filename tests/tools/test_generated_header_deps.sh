#!/usr/bin/env bash
# What a generated header pulls in: the runtime's headers and the standard library, no Boost
# (Boost.Units lives in core/unit_literal.hpp alone), no Eigen, no SUNDIALS headers — a model's
# users compile against it without them, and g++ reads less per file. And what a model kernel
# pulls in (--emit=kernel): no C++ standard header at all — most of a small model's build
# time went into reading them (docs/command-line.md, *Kernels*).
# Bugs caught: a std:: name printed into a kernel (std::to_string in a message, std::span in a
# signature, std::array in a core), a standard header included by kernel_support.hpp or the
# headers under it (lanes.hpp, factor_core.hpp).
#   usage: test_generated_header_deps.sh PATH/TO/phynjo-lagc CXX SOURCE_DIR
set -u
lagc=$1; cxx=$2; src=$3
. "$(dirname "$0")/check.sh"

# models with events, constraints and shapes: every part of the generated header
for model in bouncing_ball four_bar pendulum_wall; do
  "$lagc" "$src/examples/models/$model.lag" -o "$work/$model.cpp" --main || { bad "$model: phynjo-lagc failed"; continue; }
  for file in "$work/$model.hpp" "$work/$model.cpp"; do
    name=$(basename "$file")
    if ! "$cxx" -std=c++20 -M -I"$src/runtime/include" -I"$src/mpi/include" "$file" >"$work/deps" 2>"$work/err"; then
      bad "$name: the dependency scan failed: $(head -3 "$work/err")"
      continue
    fi
    # the scan must have reached the runtime (a header that includes nothing proves nothing)
    grep -q "phynjo/runtime/simulate/generated.hpp" "$work/deps" || { bad "$name: generated.hpp not among its includes"; continue; }
    found=$(tr ' \\' '\n\n' <"$work/deps" | grep -E '/(boost|eigen3|sundials|nvector|sunmatrix|sunlinsol)/' | head -3)
    [ -z "$found" ] && ok "$name: no Boost, Eigen or SUNDIALS header" || bad "$name includes: $found"
  done
done
# every held model's kernel compiles without the C++ standard library's headers
for model in "$src"/examples/models/*.lag "$src"/tests/codegen/models/*.lag "$src"/tests/rigid/models/*.lag; do
  name=$(basename "$model" .lag)
  "$lagc" "$model" --emit=kernel -o "$work/$name.kernel.cpp" 2>/dev/null || continue # a model meant to fail
  for flags in "" "-march=native -DPHYNJO_LIBMVEC=1"; do
    if ! "$cxx" -std=c++20 -fsyntax-only -nostdinc++ -w $flags -I"$src/runtime/include" "$work/$name.kernel.cpp" 2>"$work/err"; then
      bad "$name kernel ($flags): needs a standard header: $(grep -m2 error "$work/err")"
      continue 2
    fi
  done
  kernels=$((${kernels:-0} + 1))
done
[ "${kernels:-0}" -ge 40 ] && ok "$kernels kernels compile with -nostdinc++" || bad "only ${kernels:-0} kernels checked"
finish
