#!/usr/bin/env bash
# cmake --install, then an outside project finds phynjo with find_package(phynjo CONFIG),
# builds against it and runs; with PYTHON3, the installed Python package (found where that
# python3 looks, PREFIX/lib/python3.X/dist-packages) compiles a model with PREFIX/include alone.
#   usage: test_install.sh BUILD_DIR SOURCE_DIR [PYTHON3]
set -euo pipefail
build=$1; src=$2; py=${3:-}
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
if [ -n "$py" ]; then
  site=$(ls -d "$work"/prefix/lib/python3*/dist-packages)
  test -f "$site/phynjo/__init__.py"
  # the source tree's headers hidden: the kernel must build from PREFIX/include
  PYTHONPATH="$site" PHYNJO_CACHE_DIR="$work/cache" "$py" - "$src/examples/models/pendulum.lag" 2>"$work/py.err" <<'PY'
import math, sys, phynjo
m = phynjo.compile(sys.argv[1], verbose=True)
assert not m.cache_hit and m.accelerations([1.0], [0.0])[0] == -9.81 * math.sin(1.0)
PY
  grep -q "with the headers in $work/prefix/include" "$work/py.err" || \
    { cat "$work/py.err"; echo "FAIL the installed package did not build its kernel with $work/prefix/include"; exit 1; }
fi
echo "1 passed, 0 failed"
