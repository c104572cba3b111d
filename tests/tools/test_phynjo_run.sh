#!/usr/bin/env bash
# phynjo-run (tools/phynjo-run, docs/command-line.md): a model file run with no CMake project,
# through a kernel compiled into a cache.
# Catches: a kernel whose results differ from the CMake-built simulator's by a bit (another
# flag, another code path), a cache that never hits or serves a corrupt or stale kernel, two
# processes corrupting it, a model error without FILE:LINE:COL and caret, a missing compiler
# crashing or hanging instead of saying what to install, usage errors without exit 2.
#   usage: test_phynjo_run.sh PHYNJO_RUN EXAMPLES_BIN_DIR SOURCE_DIR
set -u
run=$1; bin=$2; src=$3
. "$(dirname "$0")/check.sh"
cache="$work/cache"
models="$src/examples/models"
pr() { "$run" --cache-dir "$cache" "$@"; }

# the same bytes as the CMake-built simulator, across integrators, constraints, events, shapes, sweeps
same() { # NAME SIM MODEL OPTIONS...
  local name=$1 sim=$2 model=$3; shift 3
  "$bin/$sim" "$@" -o "$work/ref.csv" 2>"$work/ref.err"; local r1=$?
  pr "$model" "$@" -o "$work/run.csv" 2>"$work/run.err"; local r2=$?
  if [ $r1 -eq 0 ] && [ $r2 -eq 0 ] && cmp -s "$work/ref.csv" "$work/run.csv"; then ok "$name: the same bytes as $sim"
  else bad "$name: rc $r1/$r2 [$(head -c 300 "$work/run.err")]"; fi
}
same "double pendulum, rk4" double_pendulum_sim "$models/double_pendulum.lag" --t-end 5 --every 7
same "double pendulum, midpoint" double_pendulum_sim "$models/double_pendulum.lag" --t-end 2 --integrator midpoint --param m2=2.5
same "four-bar, rattle (constraints)" four_bar_sim "$models/four_bar.lag" --t-end 2 --integrator rattle
same "rolling disk, cvode (nonholonomic)" rolling_disk_sim "$models/rolling_disk.lag" --t-end 2 --integrator cvode
same "slider-crank, dopri (inputs)" slider_crank_sim "$models/slider_crank.lag" --t-end 1 --dt 1e-4 --integrator dopri --param tau=0.7
"$bin/bouncing_ball_sim" --t-end 3 --events "$work/ev_ref.csv" --shapes "$work/sh_ref.csv" -o /dev/null 2>/dev/null
pr "$models/bouncing_ball.lag" --t-end 3 --events "$work/ev.csv" --shapes "$work/sh.csv" -o /dev/null 2>/dev/null
cmp -s "$work/ev_ref.csv" "$work/ev.csv" && cmp -s "$work/sh_ref.csv" "$work/sh.csv" \
  && ok "bouncing ball: the same events and shapes" || bad "bouncing ball: events or shapes differ"
"$bin/flip_pendulum_sim" --grid th1=-3:3:6 --grid th2=-3:3:5 --t-end 3 --summary "$work/sum_ref.csv" --threads 2 2>/dev/null
pr "$models/flip_pendulum.lag" --grid th1=-3:3:6 --grid th2=-3:3:5 --t-end 3 --summary "$work/sum.csv" --threads 2 2>/dev/null
cmp -s "$work/sum_ref.csv" "$work/sum.csv" && ok "a sweep in lanes: the same summary" || bad "sweep summary differs"

# the cache: a second run is a hit; a corrupt kernel is rebuilt; the key follows the model text
pr --verbose "$models/double_pendulum.lag" --t-end 0.1 -o /dev/null 2>"$work/err"
grep -q "the kernel is in the cache" "$work/err" && ok "second run: a cache hit" || bad "second run not a hit [$(cat "$work/err")]"
so=$(ls "$cache"/kernels/*.so | head -1)
printf 'garbage' | dd of="$so" bs=1 seek=2000 conv=notrunc 2>/dev/null
for so in "$cache"/kernels/*.so; do printf 'XX' | dd of="$so" bs=1 seek=1000 conv=notrunc 2>/dev/null; done
pr --verbose "$models/double_pendulum.lag" --t-end 5 --every 7 -o "$work/again.csv" 2>"$work/err"
"$bin/double_pendulum_sim" --t-end 5 --every 7 -o "$work/ref.csv"
grep -q "compiled its kernel" "$work/err" && cmp -s "$work/again.csv" "$work/ref.csv" \
  && ok "a corrupted kernel is detected and rebuilt" || bad "corrupt kernel [$(cat "$work/err")]"
for so in "$cache"/kernels/*.so; do : > "$so"; done # cut short (a crash while writing)
pr --verbose "$models/double_pendulum.lag" --t-end 0.1 -o /dev/null 2>"$work/err"
grep -q "compiled its kernel" "$work/err" && ok "an empty kernel is rebuilt" || bad "empty kernel [$(cat "$work/err")]"
sed 's/m2 = 1/m2 = 2/' "$models/double_pendulum.lag" > "$work/heavier.lag"
pr --verbose "$work/heavier.lag" --t-end 0.1 -o /dev/null 2>"$work/err"
grep -q "compiled its kernel" "$work/err" && ok "another model text: another kernel" || bad "changed text served from cache"

# two processes compiling the same model at once, on an empty cache: both right
rm -rf "$cache"
for k in 1 2 3; do pr "$models/four_bar.lag" --t-end 1 --integrator rattle -o "$work/par$k.csv" 2>"$work/par$k.err" & done
wait
"$bin/four_bar_sim" --t-end 1 --integrator rattle -o "$work/ref.csv"
cmp -s "$work/par1.csv" "$work/ref.csv" && cmp -s "$work/par2.csv" "$work/ref.csv" && cmp -s "$work/par3.csv" "$work/ref.csv" \
  && [ "$(ls "$cache"/kernels/*.so | wc -l)" -eq 1 ] && [ -z "$(ls "$cache"/kernels/ | grep tmp)" ] \
  && ok "three processes compiling one model at once: one kernel, the same bytes" || bad "concurrent compiles [$(cat "$work"/par*.err)]"

# bad input
printf 'model bad\ncoordinates x\nlagrangian 1/2*x\x27^2 - k*x^2\n' > "$work/bad.lag"
pr "$work/bad.lag" --t-end 1 2>"$work/err"; rc=$?
[ $rc -eq 1 ] && grep -q "bad.lag:3:[0-9]*: error: .*k" "$work/err" && grep -q '\^' "$work/err" \
  && ok "a model error: exit 1, FILE:LINE:COL and a caret" || bad "model error rc=$rc [$(cat "$work/err")]"
CXX=/nonexistent/g++ "$run" --cache-dir "$work/other" "$models/pendulum.lag" 2>"$work/err"; rc=$?
[ $rc -eq 1 ] && grep -q "install Debian's g++" "$work/err" && ok "no compiler: exit 1, says what to install" \
  || bad "no compiler rc=$rc [$(cat "$work/err")]"
"$run" 2>/dev/null; [ $? -eq 2 ] && ok "no model: exit 2" || bad "no model"
"$run" --bogus "$models/pendulum.lag" 2>/dev/null; [ $? -eq 2 ] && ok "unknown option before the model: exit 2" || bad "unknown option"
pr "$models/pendulum.lag" --bogus 2>/dev/null; [ $? -eq 2 ] && ok "unknown simulator option: exit 2" || bad "unknown simulator option"
pr "$work/missing.lag" 2>"$work/err"; rc=$?
[ $rc -eq 1 ] && grep -q "cannot read" "$work/err" && ok "a missing model file: exit 1" || bad "missing file rc=$rc"
pr "$models/pendulum.lag" --help | grep -q "usage: phynjo-run .*pendulum.lag" && ok "--help after the model: the simulator's" \
  || bad "--help after the model"
finish
