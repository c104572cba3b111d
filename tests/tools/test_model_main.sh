#!/usr/bin/env bash
# The command-line simulator every generated model links (runtime/src/simulate/model_main.cpp),
# through the example simulators: options, exit codes, the CSV it writes, the integrators.
# Catches: a driver that ignores --param or --every, writes a wrong header or row count,
# mixes up integrators, exits 0 after a failed run, or accepts a bad option.
#   usage: test_model_main.sh BUILD_EXAMPLES_DIR PHYSICAL_PENDULUM_SIM
set -u
bin=$1; phys=$2
. "$(dirname "$0")/check.sh"
pend="$bin/pendulum_sim"; dp="$bin/double_pendulum_sim"

"$pend" --help | grep -q "usage: .*--integrator rk4|dopri|midpoint" && ok "--help" || bad "--help"
"$pend" --bogus 2>/dev/null; [ $? -eq 2 ] && ok "unknown option: exit 2" || bad "unknown option"
"$pend" --param nope=1 2>/dev/null; [ $? -eq 2 ] && ok "unknown parameter: exit 2" || bad "unknown parameter"
"$pend" --dt 2>/dev/null; [ $? -eq 2 ] && ok "option without value: exit 2" || bad "option without value"
"$pend" --dt -1 2>/dev/null; [ $? -eq 2 ] && ok "negative dt: exit 2" || bad "negative dt"
"$pend" --integrator euler 2>/dev/null; [ $? -eq 2 ] && ok "unknown integrator: exit 2" || bad "unknown integrator"
"$pend" --output "$work/no/such/dir.csv" 2>/dev/null; [ $? -eq 1 ] && ok "unwritable output: exit 1" || bad "unwritable output"

# strict numbers: a typo is a usage error, not a silent 0 or a truncated value
for bad in "--param g=abc" "--t-end 1e-2x" "--dt abc" "--every 0" "--every 2.5" "--init theta=1x" "--init nope=1" \
           "--fail-on-drift" "--energy-tolerance -1" "--param g"; do
  "$pend" $bad --t-end 0.01 >/dev/null 2>&1; rc=$?
  [ $rc -eq 2 ] && ok "usage error: $bad" || bad "usage error: $bad (exit $rc)"
done
"$pend" --help | grep -q "default 10" && "$pend" --help | grep -q "default 0.001" && "$pend" --help | grep -q "parameters: m, l, g" \
  && ok "--help shows the defaults and the parameters" || bad "--help defaults"

# the run ends exactly at --t-end with a shortened last step, always writes the last row, and
# t is k*dt (ten steps of 0.1 end at 1, not at the accumulated 0.9999999999999999)
"$pend" --t-end 1 --dt 0.1 --every 1 > "$work/t.csv"
[ "$(tail -1 "$work/t.csv" | cut -d, -f1)" = "1" ] && ok "t = k*dt exactly" || bad "t column: $(tail -1 "$work/t.csv" | cut -d, -f1)"
"$pend" --t-end 1 --dt 0.3 --every 2 > "$work/short.csv"
[ "$(cut -d, -f1 "$work/short.csv" | tr '\n' ' ')" = "t 0 0.59999999999999998 1 " ] && ok "last step shortened to end at t-end; last row written" \
  || bad "shortened last step: $(cut -d, -f1 "$work/short.csv" | tr '\n' ' ')"

# --init overrides the model's initial values (coordinates and velocities, comma-separated)
"$dp" --t-end 0 --init "th1=0.3, th2'=-0.5" > "$work/init.csv"
[ "$(sed -n 2p "$work/init.csv" | cut -d, -f1-5)" = "0,0.29999999999999999,1.5707963267948966,0,-0.5" ] && ok "--init" \
  || bad "--init: $(sed -n 2p "$work/init.csv")"

# the energy check: the midpoint rule at a coarse step drifts beyond 1e-9 but not 1e-2
"$dp" --t-end 2 --dt 0.01 --integrator midpoint --energy-tolerance 1e-9 --fail-on-drift >/dev/null 2>"$work/drift"; rc=$?
[ $rc -eq 3 ] && grep -q "the energy drifted by" "$work/drift" && ok "--energy-tolerance with --fail-on-drift: exit 3" || bad "drift check rc=$rc"
"$dp" --t-end 2 --dt 0.01 --integrator midpoint --energy-tolerance 1e-2 --fail-on-drift >/dev/null 2>"$work/drift"; rc=$?
[ $rc -eq 0 ] && [ ! -s "$work/drift" ] && ok "energy within the tolerance: exit 0, silent" || bad "drift within tolerance rc=$rc"
"$dp" --t-end 2 --dt 0.01 --integrator midpoint --energy-tolerance 1e-9 >/dev/null 2>"$work/drift"; rc=$?
[ $rc -eq 0 ] && grep -q "the energy drifted by" "$work/drift" && ok "--energy-tolerance alone reports, exit 0" || bad "drift report rc=$rc"

"$dp" --t-end 1 --dt 1e-3 --every 100 --output "$work/dp.csv"
[ "$(head -1 "$work/dp.csv")" = "t,th1,th2,th1',th2',E" ] && ok "CSV header: t, q..., q'..., E" || bad "CSV header [$(head -1 "$work/dp.csv")]"
[ "$(wc -l < "$work/dp.csv")" -eq 12 ] && ok "--every 100 over 1000 steps: 11 rows" || bad "row count $(wc -l < "$work/dp.csv")"
[ "$(sed -n 2p "$work/dp.csv" | cut -d, -f1-3)" = "0,1.5707963267948966,1.5707963267948966" ] && ok "first row: the model's initial state" \
  || bad "first row [$(sed -n 2p "$work/dp.csv")]"

# the three integrators agree on the double pendulum after 1 s (RK4, Dormand-Prince, midpoint at dt = 1e-4)
for i in rk4 dopri midpoint; do "$dp" --t-end 1 --dt 1e-4 --integrator $i | tail -1 > "$work/$i.row"; done
close() { awk -F, -v tol="$3" 'NR==FNR{for(i=1;i<=NF;i++)a[i]=$i; next} {for(i=1;i<=NF;i++){d=$i-a[i]; if(d<0)d=-d; if(d>tol){exit 1}}}' "$1" "$2"; }
close "$work/rk4.row" "$work/dopri.row" 1e-6 && ok "rk4 and dopri agree" || bad "rk4 vs dopri: $(cat "$work/rk4.row") / $(cat "$work/dopri.row")"
close "$work/rk4.row" "$work/midpoint.row" 1e-4 && ok "rk4 and midpoint agree" || bad "rk4 vs midpoint: $(cat "$work/midpoint.row")"
! cmp -s "$work/rk4.row" "$work/midpoint.row" && ok "the integrators are different schemes" || bad "midpoint gave rk4's bits"

# --param takes effect: a pendulum with g = 4 g swings with half the period (theta(T/2) = -theta0 at T = 2 pi sqrt(l/g) * f(theta0))
"$pend" --t-end 3 --dt 1e-3 --every 1 > "$work/g1.csv"
"$pend" --t-end 3 --dt 1e-3 --every 1 --param g=39.24 > "$work/g4.csv"
t1=$(awk -F, 'NR>2 && prev>0 && $2<=0 {print $1; exit} NR>1{prev=$2}' "$work/g1.csv")
t4=$(awk -F, 'NR>2 && prev>0 && $2<=0 {print $1; exit} NR>1{prev=$2}' "$work/g4.csv")
awk -v a="$t1" -v b="$t4" 'BEGIN{r=a/b; exit !(r>1.99 && r<2.01)}' && ok "--param g=4g halves the time to the first swing through 0 ($t1 s -> $t4 s)" \
  || bad "--param: $t1 s -> $t4 s"

# a parameter defined from others (I = 1/2*Mp*R^2) follows --param Mp unless set itself
"$phys" --t-end 1 --param Mp=4 > "$work/follow.csv"
"$phys" --t-end 1 --param Mp=4 --param I=0.5 > "$work/set_same.csv"
"$phys" --t-end 1 --param Mp=4 --param I=0.25 > "$work/set_old.csv"
cmp -s "$work/follow.csv" "$work/set_same.csv" && ! cmp -s "$work/follow.csv" "$work/set_old.csv" \
  && ok "--param Mp=4: I follows (= 1/2*4*0.5^2), --param I fixes it" || bad "derived parameter with --param"

# a run that fails says when, and exits 1
"$dp" --param m1=0 --param m2=0 --t-end 1 >/dev/null 2>"$work/err"; rc=$?
[ $rc -eq 1 ] && grep -q "simulation stopped at t = 0: .*singular" "$work/err" && ok "singular mass matrix: exit 1, message with the time" \
  || bad "singular run rc=$rc [$(cat "$work/err")]"
# --html (docs/viewer.md): an unwritable path is refused before the run (exit 2, the path
# named, nothing written); --html with a sweep or a rate that is not positive is a usage error;
# three.js missing is a failure saying what to install; a failed run still writes its page,
# the reason on it. Catches: a page checked only at the end (an hour's run lost), a sweep
# silently ignoring --html, a page missing after a failure.
"$pend" --t-end 1 --html /nonexistent-dir/run.html -o "$work/never.csv" 2>"$work/err"; rc=$?
[ $rc -eq 2 ] && grep -q "cannot write /nonexistent-dir/run.html" "$work/err" && [ ! -e "$work/never.csv" ] \
  && ok "--html unwritable: exit 2 before the run, the path named" || bad "--html unwritable rc=$rc [$(cat "$work/err")]"
"$pend" --grid l=1:2:2 --summary "$work/s.csv" --html "$work/s.html" 2>"$work/err"; rc=$?
[ $rc -eq 2 ] && grep -q -- "--html" "$work/err" && ok "--html with a sweep: exit 2" || bad "--html with a sweep rc=$rc"
"$pend" --html "$work/p.html" --html-fps 0 2>/dev/null; [ $? -eq 2 ] && ok "--html-fps 0: exit 2" || bad "--html-fps 0"
PHYNJO_THREE_DIR="$work/none" "$pend" --t-end 0.1 --html "$work/p.html" -o /dev/null 2>"$work/err"; rc=$?
[ $rc -eq 1 ] && grep -q "libjs-three" "$work/err" && ok "three.js missing: exit 1, says to install libjs-three" \
  || bad "three.js missing rc=$rc [$(cat "$work/err")]"
"$dp" --param m1=0 --param m2=0 --t-end 1 --html "$work/failed.html" >/dev/null 2>&1; rc=$?
[ $rc -eq 1 ] && grep -q '"stop":"the simulation failed at t = 0' "$work/failed.html" \
  && ok "a failed run still writes its page, the reason on it" || bad "failed run's page rc=$rc"
finish
