#!/usr/bin/env bash
# add_subdirectory(phynjo) from an outside project whose targets are named like phynjo's own
# examples and tests (pendulum, contact_sensor, test_cas): phynjo, not the top level, must
# define only its libraries, tools and phynjo_add_model.
# Catches: examples, tests, benchmarks or fuzzers defined in someone else's build (a target
# name clash stops their configure), the Python module built in their build (PHYNJO_PYTHON is
# for phynjo's own), or phynjo_add_model missing in the subproject case.
#   usage: test_subproject.sh SOURCE_DIR
set -euo pipefail
src=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
launcher=(); command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$src/tests/install/consumer" -B "$work/consumer" -DPHYNJO_SOURCE_DIR="$src" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_CXX_FLAGS="${PHYNJO_CONSUMER_CXX_FLAGS:-}" "${launcher[@]}" >"$work/configure.log" \
  || { cat "$work/configure.log"; exit 1; }
targets=$(cmake --build "$work/consumer" --target help)
for t in double_pendulum_sim sphere_pile test_runtime test_generated fuzz_lag_replay bench_pile _phynjo; do
  if grep -qw "$t" <<<"$targets"; then echo "FAIL phynjo defined its own target '$t' in a subproject build"; exit 1; fi
done
cmake --build "$work/consumer" -j "$(nproc)" >"$work/build.log" || { tail -40 "$work/build.log"; exit 1; }
"$work/consumer/consumer" >/dev/null
"$work/consumer/app" >/dev/null
. "$(dirname "$0")/sweep_check.sh" "$work/consumer/pendulum_sweeper"
"$work/consumer/test_cas" >/dev/null
echo "1 passed, 0 failed"
