#!/usr/bin/env bash
# cmake --install, then an outside project finds phynjo with find_package(phynjo CONFIG),
# builds against it and runs.   usage: test_install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1; src=$2
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
test -x "$work/prefix/bin/phynjo-cas"
"$work/prefix/bin/phynjo-cas" simplify "sin(x)^2 + cos(x)^2" | grep -qx 1
launcher=(); command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$src/tests/install/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" \
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="${PHYNJO_CONSUMER_CXX_FLAGS:-}" "${launcher[@]}" >/dev/null
cmake --build "$work/consumer" >/dev/null
"$work/consumer/consumer"
"$work/consumer/app"
. "$(dirname "$0")/sweep_check.sh" "$work/consumer/pendulum_sweeper"
echo "1 passed, 0 failed"
