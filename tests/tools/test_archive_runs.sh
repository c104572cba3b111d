#!/usr/bin/env bash
# The simulators' archive (--archive, --resume, --at; docs/archive.md) end to end.
# Catches: a snapshot that leaves out what a step carries to the next (Dormand-Prince's step
# size, the events' arming and resting, the multistep restart, the output's length), so that a
# run killed with SIGKILL and resumed writes other bytes than the run without a stop (its
# rows, events, shapes, and its --html page, drawn from the rows); a state
# at T (--at) that is not the run's state at T bit for bit; a record cut short that stops a
# resume, a flipped byte not reported with its offset, an archive of another model or
# parameter continued, a write that fails not reported at that write.
#   usage: test_archive_runs.sh PHYNJO_RUN EXAMPLES_BIN_DIR SOURCE_DIR
set -u
run=$1; bin=$2; src=$3
. "$(dirname "$0")/check.sh"
. "$(dirname "$0")/kill_resume.sh"
cache="$work/cache"
rod_wall="$src/tests/codegen/models/rod_wall.lag"
pr() { "$run" --cache-dir "$cache" "$@"; }
RANDOM=20261204 # the kill times: fixed, as every seed in the tests

# ---- 1. a constrained model with events, Dormand-Prince (step size, arming): 20 kills -------
d="$work/rod"
mkdir -p "$d"
opts=(--t-end 60 --dt 1e-4 --integrator dopri --every 20)
pr "$rod_wall" --t-end 0.01 -o /dev/null 2>/dev/null # the kernel into the cache
reference rod pr "$rod_wall" "${opts[@]}" -o "$d/out.csv.ref" --events "$d/ev.csv.ref"
[ "$(wc -l < "$d/ev.csv.ref")" -gt 5 ] && ok "rod_wall: the wall is struck ($(($(wc -l < "$d/ev.csv.ref") - 1)) events)" \
  || bad "rod_wall: too few events to test their arming"
pr "$rod_wall" "${opts[@]}" -o "$d/plain.csv" --archive "$d/plain.par" --archive-every 7000 2>/dev/null
cmp -s "$d/plain.csv" "$d/out.csv.ref" && ok "rod_wall: --archive does not change the run's bytes" \
  || bad "rod_wall: the run with --archive writes other bytes"
# (the binary itself in the background, not a shell function: SIGKILL must reach the run)
killed rod "rod_wall, dopri with constraints and events" 20 "out.csv ev.csv" -- \
  "$run" --cache-dir "$cache" "$rod_wall" "${opts[@]}" -o "$d/out.csv" --events "$d/ev.csv" --archive-every 7000

# --at T: 40 times on the rows, 10 between them: bit for bit the run's state at T
at_ok=0; at_bad=""
for ((i = 0; i < 50; ++i)); do
  k=$(((RANDOM * 32768 + RANDOM) % 600000 / 20 * 20))
  if [ $i -lt 40 ]; then T=$(awk -v k=$k 'BEGIN { printf "%.17g", k * 0.0001 }')
    want=$(sed -n "$((k / 20 + 2))p" "$d/out.csv.ref")
  else T=$(awk -v k=$k 'BEGIN { printf "%.7f", k * 0.0001 + 0.00003 }')
    want=$(pr "$rod_wall" "${opts[@]}" --t-end "$T" -o /dev/stdout 2>/dev/null | tail -1)
  fi
  got=$(pr "$rod_wall" "${opts[@]}" --archive "$d/plain.par" --at "$T" -o /dev/stdout 2>"$d/at.err" | tail -1)
  if [ -n "$want" ] && [ "$got" = "$want" ]; then at_ok=$((at_ok + 1)); else at_bad="T = $T: got '${got:0:80}' want '${want:0:80}' $(head -c 200 "$d/at.err")"; fi
done
[ $at_ok -eq 50 ] && ok "rod_wall: --at T at 50 random times equals the run's state bit for bit" \
  || bad "rod_wall --at: $at_ok of 50 [$at_bad]"

# ---- 2. a bouncing ball coming to rest (resting events): 20 kills --------------------------
d="$work/ball"
mkdir -p "$d"
opts=(--t-end 40 --dt 1e-5 --rest-speed 0.05 --every 100)
reference ball "$bin/bouncing_ball_sim" "${opts[@]}" -o "$d/out.csv.ref" --events "$d/ev.csv.ref" --shapes "$d/sh.csv.ref"
killed ball "bouncing ball at rest, rk4" 20 "out.csv ev.csv sh.csv" -- \
  "$bin/bouncing_ball_sim" "${opts[@]}" -o "$d/out.csv" --events "$d/ev.csv" --shapes "$d/sh.csv" --archive-every 30000

# ---- 2b. --html with --resume: the page of the whole run, drawn from its rows ----------------
d="$work/page"
mkdir -p "$d"
opts=(--t-end 5 --dt 1e-4 --every 1 --rest-speed 0.05)
reference page "$bin/bouncing_ball_sim" "${opts[@]}" -o "$d/out.csv.ref" --html "$d/page.html.ref"
killed page "bouncing ball, --html with a row every step: the page of the run never stopped" 6 "out.csv page.html" -- \
  "$bin/bouncing_ball_sim" "${opts[@]}" -o "$d/out.csv" --html "$d/page.html" --archive-every 5000

# ---- 3. CVODE (the restart rule): the run with the same snapshots, 20 kills ----------------
d="$work/cvode"
mkdir -p "$d"
opts=(--t-end 600 --dt 1e-3 --integrator cvode --every 50)
reference cvode "$bin/stiff_chain_sim" "${opts[@]}" -o "$d/out.csv.ref" --archive "$d/ref.par" --archive-every 1000
killed cvode "stiff chain, cvode restarting at each snapshot" 20 "out.csv" -- \
  "$bin/stiff_chain_sim" "${opts[@]}" -o "$d/out.csv" --archive-every 1000
"$bin/stiff_chain_sim" "${opts[@]}" --archive "$d/ref.par" --at 12.345 -o "$d/at.csv" 2>/dev/null
"$bin/stiff_chain_sim" "${opts[@]}" --t-end 12.345 --archive "$d/to.par" --archive-every 1000 -o "$d/to.csv" 2>/dev/null
[ "$(tail -1 "$d/at.csv")" = "$(tail -1 "$d/to.csv")" ] && ok "cvode: --at T is the archived run's state at T" \
  || bad "cvode --at: $(tail -1 "$d/at.csv" | head -c 80) vs $(tail -1 "$d/to.csv" | head -c 80)"

# ---- 4. a snapshot just before each event: the step after it finds the event as the run did --
# (what the monitor carries — arming, resting, the recent firing times — matters in that step)
boundary() { # LABEL COMMAND...
  local label=$1; shift
  local dir="$work/boundary"; rm -rf "$dir"; mkdir -p "$dir"
  "$@" --t-end 6 --dt 1e-3 --every 1 -o "$dir/ref.csv" --events "$dir/ev.csv" 2>/dev/null
  local n=0 wrong="" te k want got
  while IFS=, read -r te _; do
    # the event's step k (it ends after te); an archive whose snapshots are every k - 1 steps
    # has one at the step before (and the next at 2k - 2 > k): --at k*dt starts from it
    k=$(awk -v t="$te" 'BEGIN { k = int(t / 0.001); if (k * 0.001 < t) k++; print k }')
    [ "$k" -lt 3 ] && continue
    rm -f "$dir/a.par"
    "$@" --t-end 6 --dt 1e-3 --every 1 -o "$dir/out.csv" --archive "$dir/a.par" --archive-every $((k - 1)) 2>/dev/null
    want=$(sed -n "$((k + 2))p" "$dir/ref.csv")
    got=$("$@" --t-end 6 --dt 1e-3 --every 1 -o /dev/stdout --archive "$dir/a.par" --at "$(awk -v k=$k 'BEGIN { printf "%.17g", k * 0.001 }')" 2>"$dir/at.err" | tail -1)
    n=$((n + 1))
    grep -q "from the snapshot at step $((k - 1))," "$dir/at.err" || wrong="$wrong t = $te: not from the snapshot at step $((k - 1)) [$(head -c 200 "$dir/at.err")];"
    [ "$got" = "$want" ] || wrong="$wrong t = $te: '${got:0:60}' != '${want:0:60}';"
  done < <(tail -n +2 "$dir/ev.csv")
  if [ $n -ge 3 ] && [ -z "$wrong" ]; then ok "$label: --at the end of each of the $n event steps, from the snapshot just before it: the run's state"
  else bad "$label: $n events;$wrong"; fi
}
boundary "bouncing ball coming to rest, rk4" "$bin/bouncing_ball_sim" --rest-speed 0.5
boundary "rod_wall, dopri" "$run" --cache-dir "$cache" "$rod_wall" --integrator dopri

# ---- 5. a finished run continued to a later end ---------------------------------------------
d="$work/longer"
mkdir -p "$d"
"$bin/pendulum_wall_sim" --t-end 20 --integrator dopri --archive "$d/a.par" --archive-every 1000 -o "$d/out.csv" 2>/dev/null
"$bin/pendulum_wall_sim" --t-end 20 --integrator dopri -o "$d/first.csv" 2>/dev/null
cmp -s "$d/out.csv" "$d/first.csv" || bad "pendulum_wall: --archive changed the output"
"$bin/pendulum_wall_sim" --t-end 35.5 --integrator dopri --every 4 --resume "$d/a.par" -o "$d/out.csv" 2>"$d/err"
"$bin/pendulum_wall_sim" --t-end 35.5 --integrator dopri --every 4 -o "$d/ref.csv" 2>/dev/null
cmp -s "$d/out.csv" "$d/ref.csv" && ok "a finished run continued to a later --t-end: the longer run's bytes" \
  || bad "continued run differs [$(head -c 300 "$d/err")]"

# the default spacing (a snapshot a second of wall time, and at the last whole step): a
# finished run continued from its last whole step to the longer run's bytes
"$bin/pendulum_wall_sim" --t-end 20 --integrator dopri --archive "$d/w.par" -o "$d/w.csv" 2>/dev/null
"$bin/pendulum_wall_sim" --t-end 35.5 --integrator dopri --every 4 --resume "$d/w.par" -o "$d/w.csv" 2>"$d/err"
cmp -s "$d/w.csv" "$d/ref.csv" && grep -q "continuing from the snapshot at step 20000," "$d/err" \
  && ok "the default spacing (wall time): a finished run continued from its last whole step to the longer run's bytes" \
  || bad "default spacing: $(cmp "$d/w.csv" "$d/ref.csv" 2>&1) [$(head -c 300 "$d/err")]"
# snapshots every 0.02 s of wall time in a run of about a second: many of them, the same bytes
"$bin/pendulum_wall_sim" --t-end 40 --integrator dopri --dt 1e-5 --every 100 --archive "$d/x.par" --archive-every 0.02s -o "$d/x.csv" 2>/dev/null
"$bin/pendulum_wall_sim" --t-end 40 --integrator dopri --dt 1e-5 --every 100 -o "$d/xr.csv" 2>/dev/null
records=$(grep -a -o PJAR "$d/x.par" | wc -l) # the header and the snapshots (a record's first bytes)
[ "$records" -ge 5 ] && cmp -s "$d/x.csv" "$d/xr.csv" \
  && ok "--archive-every 0.02s: $((records - 1)) snapshots, the run's bytes" \
  || bad "--archive-every 0.02s: $((records - 1)) snapshots; $(cmp "$d/x.csv" "$d/xr.csv" 2>&1)"

# ---- 6. damage, other runs, failing writes --------------------------------------------------
d="$work/rod"
a="$d/plain.par"
opts=(--t-end 60 --dt 1e-4 --integrator dopri --every 20)
size=$(stat -c %s "$a")
cp "$a" "$d/torn.par"; truncate -s $((size - 13)) "$d/torn.par"
cp "$d/plain.csv" "$d/torn.csv"
pr "$rod_wall" "${opts[@]}" -o "$d/torn.csv" --resume "$d/torn.par" 2>"$d/err"
cmp -s "$d/torn.csv" "$d/out.csv.ref" && ok "a last record cut short: ignored, the run resumed from the one before" \
  || bad "torn record [$(head -c 300 "$d/err")]"
cp "$a" "$d/flip.par"
off=$((size / 2))
printf '\x5a' | dd of="$d/flip.par" bs=1 seek=$off conv=notrunc 2>/dev/null
pr "$rod_wall" "${opts[@]}" -o "$d/flip.csv" --resume "$d/flip.par" 2>"$d/err"; r=$?
[ $r -eq 1 ] && grep -q "at byte [0-9]" "$d/err" && grep -q "checksum" "$d/err" \
  && ok "a flipped byte: exit 1, the record's offset named ($(head -c 160 "$d/err"))" || bad "flipped byte: rc $r [$(head -c 300 "$d/err")]"
pr "$rod_wall" "${opts[@]}" --param e=0.5 -o "$d/other.csv" --archive "$a" --at 3 2>"$d/err"; r=$?
[ $r -eq 1 ] && grep -q "another run: param.e" "$d/err" && ok "another parameter: refused, naming it" \
  || bad "other parameter: rc $r [$(head -c 300 "$d/err")]"
sed 's/m = 1,/m = 2,/' "$rod_wall" > "$d/heavier.lag"
pr "$d/heavier.lag" "${opts[@]}" -o "$d/other.csv" --archive "$a" --at 3 2>"$d/err"; r=$?
[ $r -eq 1 ] && grep -q "model.fingerprint" "$d/err" && ok "another model (other default mass): refused" \
  || bad "other model: rc $r [$(head -c 300 "$d/err")]"
pr "$rod_wall" "${opts[@]}" --integrator rk4 -o "$d/other.csv" --resume "$a" 2>"$d/err"; r=$?
[ $r -eq 1 ] && grep -q "integrator: 'dopri' in the archive, 'rk4' in this run" "$d/err" && ok "another integrator: refused" \
  || bad "other integrator: rc $r [$(head -c 300 "$d/err")]"
cp "$a" "$d/v2.par"
python3 - "$d/v2.par" <<'PY'
import struct, sys, zlib
p = sys.argv[1]; b = bytearray(open(p, 'rb').read())
n = struct.unpack_from('<Q', b, 8)[0]
payload = bytes(b[20:20 + n]).replace(b'format 1\n', b'format 7\n', 1)
b[20:20 + n] = payload; struct.pack_into('<I', b, 20 + n, zlib.crc32(payload))
open(p, 'wb').write(b)
PY
pr "$rod_wall" "${opts[@]}" -o "$d/other.csv" --resume "$d/v2.par" 2>"$d/err"; r=$?
[ $r -eq 1 ] && grep -q "format 7" "$d/err" && ok "another format version: refused ($(head -c 120 "$d/err"))" \
  || bad "format version: rc $r [$(head -c 300 "$d/err")]"
(trap '' XFSZ; ulimit -f 64; exec "$bin/bouncing_ball_sim" --t-end 40 --dt 1e-4 -o /dev/null --archive "$d/full.par" --archive-every 5) 2>"$d/err"; r=$?
[ $r -eq 1 ] && grep -q "full.par" "$d/err" && grep -q "at byte" "$d/err" && ok "a write that fails (file size limit): exit 1 at that write" \
  || bad "failed write: rc $r [$(head -c 300 "$d/err")]"

# a second process continuing an archive that a run still writes: refused, nothing touched
"$run" --cache-dir "$cache" "$rod_wall" "${opts[@]}" --t-end 600 -o "$d/busy.csv" --archive "$d/busy.par" 2>/dev/null &
busy=$!
sleep 0.4
pr "$rod_wall" "${opts[@]}" --t-end 600 -o "$d/busy.csv" --resume "$d/busy.par" 2>"$d/err"; r=$?
kill -9 $busy 2>/dev/null; wait $busy 2>/dev/null
[ $r -eq 1 ] && grep -q "being written by another process" "$d/err" && ok "--resume while the run still writes: refused" \
  || bad "concurrent resume: rc $r [$(head -c 300 "$d/err")]"

# usage
"$bin/bouncing_ball_sim" --archive "$a" -o /dev/null 2>"$d/err"; r=$?
[ $r -eq 2 ] && grep -q "exists (continue its run with --resume" "$d/err" && ok "--archive of an existing file: exit 2" || bad "existing archive: rc $r"
"$bin/bouncing_ball_sim" --resume "$a" --html "$d/p.html" 2>"$d/err"; r=$?
[ $r -eq 2 ] && grep -q "give --output FILE" "$d/err" && ok "--html with --resume and no --output: exit 2" || bad "--html --resume without rows: rc $r"
"$bin/bouncing_ball_sim" --at 3 2>"$d/err"; r=$?
[ $r -eq 2 ] && ok "--at without an archive: exit 2" || bad "--at alone: rc $r"
"$bin/bouncing_ball_sim" --archive-every 0 --archive "$d/x.par" 2>"$d/err"; r=$?
[ $r -eq 2 ] && ok "--archive-every 0: exit 2" || bad "--archive-every 0: rc $r"
"$bin/stiff_chain_sim" --integrator cvode --archive "$d/z.par" --archive-every 2s 2>"$d/err"; r=$?
[ $r -eq 2 ] && grep -q "restarts at each snapshot" "$d/err" && ok "cvode with snapshots by wall time: exit 2 (its run would depend on them)" \
  || bad "cvode --archive-every 2s: rc $r $(cat "$d/err")"
"$bin/bouncing_ball_sim" --grid e=0.1:0.9:3 --summary "$d/s.csv" --archive "$d/y.par" 2>"$d/err"; r=$?
[ $r -eq 2 ] && ok "--archive with a sweep: exit 2" || bad "sweep archive: rc $r"
finish
