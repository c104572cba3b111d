#!/usr/bin/env bash
# g++ time and peak memory of generated code: nlink_cart(N) with every Jacobian, as
# phynjo_add_model builds it (--parts 4, bodies in pieces, the files compiled two at a time:
# the machine has 2 cores) against the same model emitted as one file of whole bodies
# (--parts 1 --pieces-above huge), compiled alone. Flags: -O3 -DNDEBUG -std=c++20 (Release),
# and for the parts -fno-tree-slp-vectorize as phynjo_add_model adds for GCC.
# Ends with `ratio gxx_build_nlink_N = one-file wall time / parts wall time` per N.
#   usage: gxx_build.sh LAGC SOURCE_DIR CXX     N from PHYNJO_GXX_BUILD_N (default "10 20";
#          the one-file reference only up to PHYNJO_GXX_REFERENCE_MAX_N (default 20): at N = 40 it
#          takes about 25 minutes and 8 GB)
set -euo pipefail
lagc=$1; src=$2; cxx=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
flags=(-O3 -DNDEBUG -std=c++20 -I"$src/runtime/include" -isystem /usr/include/eigen3)
# wall seconds and the largest peak RSS (MB) of compiling FILES with J jobs
build() {
  local jobs=$1 dir=$2 extra=$3; shift 3
  local start end
  start=$(date +%s.%N)
  printf '%s\n' "$@" | xargs -P "$jobs" -I{} /usr/bin/time -f '%M' -o {}.mem "$cxx" "${flags[@]}" $extra -I"$dir" -c {} -o {}.o
  end=$(date +%s.%N)
  local peak=0
  for f in "$@"; do m=$(cat "$f.mem"); [ "$m" -gt "$peak" ] && peak=$m; done
  echo "$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }') $((peak / 1024))"
}
gnu_extra=""
"$cxx" --version | head -1 | grep -qi clang || gnu_extra=-fno-tree-slp-vectorize
for N in ${PHYNJO_GXX_BUILD_N:-10 20}; do
  mkdir -p "$work/parts$N" "$work/one$N"
  python3 "$src/examples/models/nlink_cart.py" "$N" > "$work/nlink_$N.lag"
  "$lagc" "$work/nlink_$N.lag" -o "$work/parts$N/nlink.cpp" --parts 4
  read -r tp mp < <(build 2 "$work/parts$N" "$gnu_extra" "$work/parts$N"/nlink*.cpp)
  kb=$(cat "$work/parts$N"/nlink*.cpp | wc -c)
  if [ "$N" -gt "${PHYNJO_GXX_REFERENCE_MAX_N:-20}" ]; then
    printf 'nlink_cart(%d), %d KB of C++: 4 files, 2 at a time: %.1f s, peak %d MB (no one-file reference)\n' \
      "$N" $((kb / 1024)) "$tp" "$mp"
    continue
  fi
  "$lagc" "$work/nlink_$N.lag" -o "$work/one$N/nlink.cpp" --pieces-above 1000000000
  read -r t1 m1 < <(build 1 "$work/one$N" "" "$work/one$N/nlink.cpp")
  printf 'nlink_cart(%d), %d KB of C++: 4 files, 2 at a time: %.1f s, peak %d MB; one file: %.1f s, peak %d MB\n' \
    "$N" $((kb / 1024)) "$tp" "$mp" "$t1" "$m1"
  printf 'ratio gxx_build_nlink_%d = %.2f\n' "$N" "$(awk -v a="$t1" -v b="$tp" 'BEGIN { print a / b }')"
done
