#!/usr/bin/env bash
# What a generated header pulls in: the runtime's headers and the standard library, no Boost
# (Boost.Units lives in core/unit_literal.hpp alone), no Eigen, no SUNDIALS headers — a model's
# users compile against it without them, and g++ reads less per file.
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
finish
