#!/usr/bin/env bash
# g++ time and peak memory of generated code: nlink_cart(N) with every Jacobian, as
# phynjo_add_model builds it (--parts 4, bodies in pieces, the files compiled two at a time:
# the machine has 2 cores) against the same model emitted as one file of whole bodies
# (--parts 1 --pieces-above huge), compiled alone. Flags: -O3 -DNDEBUG -std=c++20 (Release).
# Ends with `ratio gxx_build_nlink_N = one-file wall time / parts wall time` per N.
#   usage: gxx_build.sh LAGC SOURCE_DIR CXX     N from PHYNJO_GXX_BUILD_N (default "10 20";
#          "10 20 40" takes about 10 minutes and 8 GB for the one-file reference at N = 40)
set -euo pipefail
lagc=$1; src=$2; cxx=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
flags=(-O3 -DNDEBUG -std=c++20 -I"$src/runtime/include" -isystem /usr/include/eigen3)
# wall seconds and the largest peak RSS (MB) of compiling FILES with J jobs
build() {
  local jobs=$1 dir=$2; shift 2
  local start end
  start=$(date +%s.%N)
  printf '%s\n' "$@" | xargs -P "$jobs" -I{} /usr/bin/time -f '%M' -o {}.mem "$cxx" "${flags[@]}" -I"$dir" -c {} -o {}.o
  end=$(date +%s.%N)
  local peak=0
  for f in "$@"; do m=$(cat "$f.mem"); [ "$m" -gt "$peak" ] && peak=$m; done
  echo "$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }') $((peak / 1024))"
}
for N in ${PHYNJO_GXX_BUILD_N:-10 20}; do
  mkdir -p "$work/parts$N" "$work/one$N"
  python3 "$src/examples/models/nlink_cart.py" "$N" > "$work/nlink_$N.lag"
  "$lagc" "$work/nlink_$N.lag" -o "$work/parts$N/nlink.cpp" --parts 4
  "$lagc" "$work/nlink_$N.lag" -o "$work/one$N/nlink.cpp" --pieces-above 1000000000
  read -r tp mp < <(build 2 "$work/parts$N" "$work/parts$N"/nlink*.cpp)
  read -r t1 m1 < <(build 1 "$work/one$N" "$work/one$N/nlink.cpp")
  kb=$(cat "$work/parts$N"/nlink*.cpp | wc -c)
  printf 'nlink_cart(%d), %d KB of C++: 4 files, 2 at a time: %.1f s, peak %d MB; one file: %.1f s, peak %d MB\n' \
    "$N" $((kb / 1024)) "$tp" "$mp" "$t1" "$m1"
  printf 'ratio gxx_build_nlink_%d = %.2f\n' "$N" "$(awk -v a="$t1" -v b="$tp" 'BEGIN { print a / b }')"
done
