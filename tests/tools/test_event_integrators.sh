#!/usr/bin/env bash
# Events under every integrator of the simulators (docs/language.md, *Events*).
# Catches: a crossing located on an arc spanning the whole output interval (--dt) instead
# of the solver's own interpolant of its internal steps (CVODE, IDA, Bdf: crossings off by
# 1e-3 and more, a Van der Pol run that ends on the wrong branch); a solver restarted, or
# the world moved to the event, after an event whose actions changed nothing (the run then
# differs from the one without the event).
#   usage: test_event_integrators.sh OSCILLATOR_SIM OSCILLATOR_WATCHED_SIM VAN_DER_POL_SIM
set -u
plain=$1; watched=$2; vdp=$3
. "$(dirname "$0")/check.sh"

# |a - b| <= tol, as awk reads the numbers
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t) }'; }

# x = cos t: x falls through 0 at pi/2, 5pi/2, 9pi/2 before t = 20
exact="1.5707963267948966 7.853981633974483 14.137166941154069"
for integrator in rk4 dopri midpoint rattle cvode ida bdf; do
  for dt in 1 0.37 0.01; do
    what="$integrator --dt $dt"
    "$plain" --integrator $integrator --dt $dt --t-end 20 -o "$work/p.csv" 2>/dev/null; rc1=$?
    "$watched" --integrator $integrator --dt $dt --t-end 20 -o "$work/w.csv" --events "$work/e.csv" 2>/dev/null; rc2=$?
    [ $rc1 -eq 0 ] && [ $rc2 -eq 0 ] && cmp -s "$work/p.csv" "$work/w.csv" \
      && ok "$what: the observing event leaves the run as it is, bit for bit" \
      || bad "$what: exit $rc1/$rc2, the run with the observing event differs from the one without"
    # where the crossings are: to 1e-6 s on the variable-step solvers' interpolants at every
    # --dt; with the fixed steps at dt = 0.01 (midpoint and rattle: second order, 2e-4)
    tol=""
    case $integrator in
      dopri|cvode|ida|bdf) tol=1e-6 ;;
      rk4) [ "$dt" = 0.01 ] && tol=1e-6 ;;
      *) [ "$dt" = 0.01 ] && tol=2e-4 ;;
    esac
    [ -z "$tol" ] && continue
    got=$(awk -F, 'NR > 1 { printf "%s ", $1 }' "$work/e.csv")
    set -- $got; n=$#; i=0; far=""
    for e in $exact; do
      i=$((i + 1)); g=$(eval echo "\${$i:-x}")
      near "$g" "$e" "$tol" || far="$far $g (exact $e)"
    done
    [ "$n" -eq 3 ] && [ -z "$far" ] && ok "$what: 3 crossings at pi/2 + 2 pi k to $tol s" \
      || bad "$what: crossings $got; off:$far"
  done
done
# and the end state of the variable-step solvers at --dt 1 (the bug gave 1.6e-3)
for integrator in cvode ida bdf; do
  "$watched" --integrator $integrator --dt 1 --t-end 20 -o "$work/w.csv" 2>/dev/null
  x=$(tail -1 "$work/w.csv" | cut -d, -f2)
  near "$x" 0.40808206181339196 1e-6 && ok "$integrator --dt 1: x(20) = cos 20 to 1e-6" || bad "$integrator --dt 1: x(20) = $x"
done

# Van der Pol, mu = 1000, two observing events; SciPy's Radau at rtol = atol = 1e-12
# (tests/codegen/models/van_der_pol.lag): down at 807.08474082, up at 1614.28530373,
# x(2000) = 1.70616773. What is left is the solver's own error, which falls with its
# tolerance: at the defaults (rtol 1e-8) the crossings were seen within 2.2e-3 s and x(2000)
# within 1.6e-6; at rtol 1e-10 within 2.5e-5 s and 2e-7 (limits a few times those). The bug
# put them 0.1 s off, with an extra crossing at 1258 s and x(2000) = -1.42.
for integrator in cvode ida bdf; do
  for run in "0.5" "7" "7 --rtol 1e-10 --atol 1e-12"; do
    set -- $run; dt=$1; shift
    what="Van der Pol, $integrator --dt $dt $*"
    if [ $# -gt 0 ]; then tol=1e-4; xtol=1e-6; else tol=5e-3; xtol=1e-5; fi
    "$vdp" --integrator $integrator --dt $dt "$@" --t-end 2000 -o "$work/v.csv" --events "$work/ve.csv" 2>/dev/null; rc=$?
    rows=$(awk -F, 'NR > 1 { printf "%s:%s ", $2, $1 }' "$work/ve.csv")
    set -- $rows
    d=${1#down:}; u=${2:-}; u=${u#up:}
    x=$(tail -1 "$work/v.csv" | cut -d, -f2)
    [ $rc -eq 0 ] && [ $# -eq 2 ] && [ "${1%%:*}" = down ] && [ "${2%%:*}" = up ] \
      && near "$d" 807.08474082 $tol && near "$u" 1614.28530373 $tol \
      && ok "$what: crossings at $d and $u (Radau: 807.08474, 1614.28530; to $tol s)" \
      || bad "$what: exit $rc, crossings $rows"
    near "$x" 1.70616773 $xtol && ok "$what: x(2000) = $x (Radau: 1.70616773)" || bad "$what: x(2000) = $x"
  done
done
finish
