#!/usr/bin/env bash
# The simulators of models with events (docs/generated-code.md: --events FILE): the events CSV,
# a stop, Zeno as exit 1 with a message naming the event, the rest-speed remedy, usage errors.
# Catches: no --events file or a wrong header, rows before their crossing, a Zeno run that
# exits 0 or hangs, a stop that does not end the output at the crossing.
#   usage: test_events_main.sh BUILD_EXAMPLES_DIR
set -u
bin=$1
. "$(dirname "$0")/check.sh"
ball="$bin/bouncing_ball_sim"; wall="$bin/pendulum_wall_sim"

"$ball" --help | grep -q "the model's events: bounce" && ok "--help names the events" || bad "--help events"
"$ball" --t-end 2 --events "$work/ev.csv" -o "$work/ball.csv"; rc=$?
[ $rc -eq 0 ] && ok "ball 2 s: exit 0" || bad "ball 2 s: exit $rc"
[ "$(head -1 "$work/ev.csv")" = "t,event,y,y'" ] && ok "events header" || bad "events header: $(head -1 "$work/ev.csv")"
# impacts at 0.4515, 1.1740, 1.7519 s (closed form), speeds 0.8^n * 4.4294 m/s after them
awk -F, 'NR > 1 { printf "%.6f %s %.6f\n", $1, $2, $4 }' "$work/ev.csv" > "$work/ev.txt"
[ "$(tr '\n' ' ' < "$work/ev.txt")" = "0.451524 bounce 3.543558 1.173961 bounce 2.834846 1.751912 bounce 2.267877 " ] \
  && ok "three impacts at the closed-form times" || bad "impacts: $(tr '\n' ' ' < "$work/ev.txt")"
awk -F, 'NR > 1 && $2 < -1e-9 { bad = 1 } END { exit bad }' "$work/ball.csv" && ok "never below the floor" || bad "below the floor"

"$ball" --t-end 6 -o "$work/zeno.csv" 2>"$work/zeno.err"; rc=$?
[ $rc -eq 1 ] && grep -q "event 'bounce' at t = 4.06.*Zeno" "$work/zeno.err" && ok "Zeno: exit 1, the event and the time" \
  || bad "Zeno: exit $rc, $(cat "$work/zeno.err")"
"$ball" --t-end 6 --rest-speed 0.05 -o "$work/rest.csv" 2>"$work/rest.err"; rc=$?
[ $rc -eq 0 ] && [ "$(tail -1 "$work/rest.csv" | cut -d, -f1,3)" = "6,0" ] && ok "--rest-speed: at rest at the end" \
  || bad "--rest-speed: exit $rc, $(tail -1 "$work/rest.csv")"
# which impact brings it to rest, and when (closed form): the speed after impact n is
# e^n v0, v0 = sqrt(2 g h) = 4.42945 m/s; the first n with e^n v0 < 0.05 is 21 (0.8^20 v0 =
# 0.0511 is still above); impact n comes at t1 + (2 v0/g) (e + ... + e^(n-1)), t1 = sqrt(2h/g)
"$ball" --t-end 6 --rest-speed 0.05 --events "$work/rest_ev.csv" -o /dev/null 2>/dev/null
read -r n t_last v_last v_before < <(awk -F, 'NR > 1 { n++; prev = v; v = $4; t = $1 } END { print n, t, v, prev }' "$work/rest_ev.csv")
want_t=$(awk 'BEGIN { g = 9.81; e = 0.8; v0 = sqrt(2 * g); t = sqrt(2 / g); for (k = 1; k < 21; k++) t += 2 * v0 * e^k / g; printf "%.12f", t }')
[ "$n" = 21 ] && awk -v a="$t_last" -v b="$want_t" 'BEGIN { d = a - b; exit !(d < 1e-9 && d > -1e-9) }' \
  && [ "$v_last" = 0 ] && awk -v v="$v_before" 'BEGIN { exit !(v > 0.0510 && v < 0.0512) }' \
  && ok "--rest-speed 0.05: at rest at impact 21, t = $want_t (closed form), after 0.8^20 v0 = 0.0511" \
  || bad "--rest-speed 0.05: $n impacts, the last at $t_last (closed form: 21 at $want_t), speeds $v_before then $v_last"
for bad in "--rest-speed 0" "--rest-speed -1" "--max-events-per-step 0" "--max-events-per-step x" "--events"; do
  "$ball" $bad --t-end 0.01 >/dev/null 2>&1; rc=$?
  [ $rc -eq 2 ] && ok "usage error: $bad" || bad "usage error: $bad (exit $rc)"
done
"$ball" --t-end 1 --events "$work/no/such/dir.csv" >/dev/null 2>&1; [ $? -eq 1 ] && ok "unwritable events file: exit 1" || bad "unwritable events file"

# a stop event ends the run as the model asks: exit 0 (the help's exit codes), the output
# ending at the crossing, stderr naming the event
flip="$bin/flip_pendulum_sim"
"$flip" --init th1=2.5,th2=2.5 --t-end 20 -o "$work/flip.csv" --events "$work/fe.csv" 2>"$work/flip.err"; rc=$?
[ $rc -eq 0 ] && grep -q "the run stopped at t = 1.92083.*: event 'flip1_back'" "$work/flip.err" \
  && [ "$(tail -1 "$work/flip.csv" | cut -d, -f1)" = "$(tail -1 "$work/fe.csv" | cut -d, -f1)" ] \
  && ok "stop event: exit 0, the output ends at the crossing, stderr names the event" \
  || bad "stop event: exit $rc, $(cat "$work/flip.err")"
"$flip" --help | grep -q "0 done (also when a stop event ended the run)" && ok "--help: a stop event exits 0" \
  || bad "--help does not say what a stop event exits with"

# the pendulum at the wall: every impact at th = th_wall, with every integrator
for integrator in rk4 dopri midpoint rattle cvode ida bdf; do
  "$wall" --t-end 8 --integrator $integrator --events "$work/w.csv" -o /dev/null 2>/dev/null; rc=$?
  n=$(awk -F, 'NR > 1 && ($3 + 0.3 > 1e-8 || $3 + 0.3 < -1e-8) { bad++ } NR > 1 { n++ } END { print (bad ? -1 : n) }' "$work/w.csv")
  [ $rc -eq 0 ] && [ "$n" -ge 5 ] && ok "pendulum-wall with $integrator: $n impacts at the wall" || bad "pendulum-wall $integrator: exit $rc, $n"
done
finish
