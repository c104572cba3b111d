#!/usr/bin/env bash
# The command-line simulator every generated model links (runtime/models/model_main.cpp),
# through the example simulators: options, exit codes, the CSV it writes, the integrators.
# Catches: a driver that ignores --param or --every, writes a wrong header or row count,
# mixes up integrators, exits 0 after a failed run, or accepts a bad option.
#   usage: test_model_main.sh BUILD_EXAMPLES_DIR PHYSICAL_PENDULUM_SIM
set -u
bin=$1; phys=$2
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
pass=0; fail=0
ok() { echo "ok   $1"; pass=$((pass+1)); }
bad() { echo "FAIL $1"; fail=$((fail+1)); }
pend="$bin/pendulum_sim"; dp="$bin/double_pendulum_sim"

"$pend" --help | grep -q "usage: .*--integrator rk4|dopri|midpoint" && ok "--help" || bad "--help"
"$pend" --bogus 2>/dev/null; [ $? -eq 2 ] && ok "unknown option: exit 2" || bad "unknown option"
"$pend" --param nope=1 2>/dev/null; [ $? -eq 2 ] && ok "unknown parameter: exit 2" || bad "unknown parameter"
"$pend" --dt 2>/dev/null; [ $? -eq 2 ] && ok "option without value: exit 2" || bad "option without value"
"$pend" --dt -1 2>/dev/null; [ $? -eq 2 ] && ok "negative dt: exit 2" || bad "negative dt"
"$pend" --integrator euler 2>/dev/null; [ $? -eq 2 ] && ok "unknown integrator: exit 2" || bad "unknown integrator"
"$pend" --output "$work/no/such/dir.csv" 2>/dev/null; [ $? -eq 1 ] && ok "unwritable output: exit 1" || bad "unwritable output"

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
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
