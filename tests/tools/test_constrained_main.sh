#!/usr/bin/env bash
# A constrained model through phynjo-lagc and its command-line simulator: --emit=eom/latex
# show G, gamma and the multipliers; inconsistent initial values stop the run with the
# constraint named (exit 1) unless --project-initial projects them (and says what changed);
# every integrator (IDA and CVODE included) keeps the rod length; the CSV carries the multiplier column.
# Catches: a simulator that starts from a state off the constraints silently, a projection
# that does not report or does not land on the manifold, a missing lambda column.
#   usage: test_constrained_main.sh PHYNJO-LAGC MODEL.lag SIMULATOR
set -u
lagc=$1; model=$2; sim=$3
. "$(dirname "$0")/check.sh"

eom=$("$lagc" "$model" --emit=eom)
echo "$eom" | grep -qx 'G(1,1) = 2\*x' && echo "$eom" | grep -qx "gamma(1) = -2\*x'^2 - 2\*y'^2" \
  && echo "$eom" | grep -q "lambda = (lambda_rod)" && ok "--emit=eom: G, gamma, lambda" || bad "--emit=eom: $eom"
"$lagc" "$model" --emit=latex | grep -q 'lambda_{\\mathrm{rod}}' && ok "--emit=latex: the multiplier" || bad "--emit=latex"

"$sim" --t-end 0.1 -o "$work/a.csv" && head -1 "$work/a.csv" | grep -qx "t,x,y,x',y',E,lambda_rod" \
  && ok "CSV header with the multiplier" || bad "CSV header: $(head -1 "$work/a.csv")"
# the tension at rest at the bottom is m g: lambda = -m g / (2 l)
"$sim" --t-end 0 --init x=0,y=-1 -o "$work/b.csv" && tail -1 "$work/b.csv" | awk -F, '{exit !($7 > -4.9051 && $7 < -4.9049)}' \
  && ok "lambda at rest = -m g / (2 l)" || bad "lambda at rest: $(tail -1 "$work/b.csv")"

"$sim" --init x=0.5,y=0 --t-end 0.1 >/dev/null 2>"$work/err"; rc=$?
[ $rc -eq 1 ] && grep -q "the state at t = 0 violates constraint 'rod' at position level: its residual is -0.75 " "$work/err" \
  && grep -q -- "--project-initial" "$work/err" && ok "inconsistent initial values: exit 1, the constraint named" \
  || bad "inconsistent initial values (exit $rc): $(cat "$work/err")"
"$sim" --init "x=0.5,x'=1" --project-initial --t-end 1 -o "$work/c.csv" 2>"$work/err"; rc=$?
[ $rc -eq 0 ] && grep -q "projected the initial state onto the constraints" "$work/err" && grep -q "^  x: 0.5 -> " "$work/err" \
  && grep -q "^  x': 1 -> " "$work/err" && ok "--project-initial: projected, changes printed" \
  || bad "--project-initial (exit $rc): $(cat "$work/err")"
"$sim" --project-initial --t-end 0 >/dev/null 2>"$work/err" && grep -q "nothing changed" "$work/err" \
  && ok "--project-initial on a consistent state: nothing changed" || bad "--project-initial consistent: $(cat "$work/err")"

for integ in rk4 dopri midpoint rattle cvode ida; do
  "$sim" --integrator $integ --t-end 5 -o "$work/$integ.csv" 2>"$work/err"
  worst=$(awk -F, 'NR > 1 { r = $2*$2 + $3*$3 - 1; if (r < 0) r = -r; if (r > w) w = r } END { printf "%.3g", w }' "$work/$integ.csv")
  awk -v w="$worst" 'BEGIN { exit !(w < 1e-11) }' && ok "$integ keeps x^2 + y^2 = 1 (worst $worst)" || bad "$integ: rod drift $worst"
done
"$sim" --integrator ida --rtol 1e-9 --atol 1e-11 --t-end 1 -o /dev/null 2>"$work/err" \
  && grep -Eq "^ida: [0-9]+ steps, [0-9]+ Jacobians" "$work/err" && ok "ida: --rtol/--atol taken, step counts on stderr" \
  || bad "ida step counts: $(cat "$work/err")"
"$sim" --integrator bdf --t-end 1 -o /dev/null 2>"$work/err"; rc=$?
# a usage error (exit 2, as the help says), not a failed run
[ $rc -eq 2 ] && grep -q "\-\-integrator bdf takes models without constraints; this one has 1 (use cvode or ida)" "$work/err" \
  && ok "bdf on a constrained model: usage error (exit 2), cvode or ida named" || bad "bdf on a constrained model (exit $rc): $(cat "$work/err")"
"$sim" --integrator rk4 --rtol 1e-9 2>"$work/err"; [ $? -eq 2 ] && grep -q "dopri, cvode, ida or bdf" "$work/err" \
  && ok "--rtol without dopri, cvode, ida or bdf: usage error" || bad "--rtol with rk4: $(cat "$work/err")"
"$sim" --projection-tolerance 0 2>/dev/null; [ $? -eq 2 ] && ok "--projection-tolerance 0: usage error" || bad "--projection-tolerance 0"
finish
