#!/usr/bin/env bash
# phynjo-archive list|verify|extract (docs/archive.md) against an independent reader of the
# documented format (read_archive.py: Python's struct and zlib).
# Catches: a snapshot listed with another step, time or offset than the file holds; a world
# extracted with a value rounded, a field or component shifted, the wrong snapshot for --at;
# a damaged record passed by verify, or its offset not named; a record cut short (a killed
# run) reported as damage; usage errors not exit 2.
#   usage: test_phynjo_archive.sh PHYNJO_ARCHIVE ARCHIVED_WORLD EXAMPLES_BIN_DIR PYTHON3
set -u
pa=$1; aw=$2; bin=$3; py=$4
reader="$(dirname "$0")/read_archive.py"
. "$(dirname "$0")/check.sh"

# an N-body run's archive (4 snapshots) and a generated model's (bouncing ball, rest events)
"$aw" nbody --n 16 --t-end 1 --every 100 -o "$work/n.csv" --archive "$work/n.par" --archive-every 250 2>/dev/null
"$bin/bouncing_ball_sim" --t-end 2 --dt 1e-4 -o "$work/b.csv" --archive "$work/b.par" --archive-every 5000 2>/dev/null

# ---- list: every snapshot where the reader finds it --------------------------------------------
"$pa" list "$work/n.par" > "$work/list.txt"; rc=$?
"$py" "$reader" list "$work/n.par" > "$work/want.txt"
got=$(awk '/^snapshots:/ { on = 1; getline; next } on { print $1, $3 }' "$work/list.txt")
want=$(awk '{ print $1, $3 }' "$work/want.txt")
times_ok=$(awk '/^snapshots:/ { on = 1; getline; next } on { print $2 }' "$work/list.txt" | paste -sd' ')
[ $rc -eq 0 ] && [ "$got" = "$want" ] && [ "$(echo "$want" | wc -l)" -eq 4 ] && [ "$times_ok" = "0.25 0.5 0.75 1" ] \
  && grep -q "^  world.fields x,y,z,vx,vy,vz,m" "$work/list.txt" \
  && ok "list: the header and 4 snapshots, steps, times and offsets as the file holds them" \
  || bad "list: rc $rc, got [$got] want [$want] times [$times_ok]"

# ---- verify -------------------------------------------------------------------------------------
out=$("$pa" verify "$work/n.par"); rc=$?
[ $rc -eq 0 ] && echo "$out" | grep -q "good: the header and 4 snapshots" && ok "verify: a whole archive is good" || bad "verify: rc $rc $out"
# a byte flipped inside the third snapshot's payload: named by that record's offset
third=$(sed -n 3p "$work/want.txt" | cut -d' ' -f3)
cp "$work/n.par" "$work/flip.par"
printf '\x55' | dd of="$work/flip.par" bs=1 seek=$((third + 100)) conv=notrunc 2>/dev/null
out=$("$pa" verify "$work/flip.par" 2>&1); rc=$?
[ $rc -eq 1 ] && echo "$out" | grep -q "byte $third" && ok "verify: a flipped byte: exit 1 at the record's offset ($out)" \
  || bad "verify of a flipped byte: rc $rc $out"
# the last record cut short, as by a kill while writing it: reported, not an error
last=$(sed -n 4p "$work/want.txt" | cut -d' ' -f3)
head -c $((last + 300)) "$work/n.par" > "$work/torn.par"
out=$("$pa" verify "$work/torn.par" 2>&1); rc=$?
[ $rc -eq 0 ] && echo "$out" | grep -q "3 snapshots" && echo "$out" | grep -q "cut short at byte $last" \
  && ok "verify: a last record cut short: good, 3 snapshots, the torn record named" || bad "verify of a torn archive: rc $rc $out"
out=$("$pa" verify "$work/none.par" 2>&1); rc=$?
[ $rc -eq 1 ] && ok "verify: a file that is not there: exit 1 ($out)" || bad "verify of no file: rc $rc"
head -c 2000 /dev/urandom > "$work/noise.par"
out=$("$pa" verify "$work/noise.par" 2>&1); rc=$?
[ $rc -eq 1 ] && ok "verify: not an archive: exit 1 ($out)" || bad "verify of noise: rc $rc $out"

# ---- extract: the world bit for bit --------------------------------------------------------------
"$pa" extract "$work/n.par" --step 750 -o "$work/w750.csv" 2>/dev/null
r=$("$py" "$reader" world "$work/n.par" 750 "$work/w750.csv" 2>&1) && ok "extract --step 750: $r" || bad "extract --step 750: $r"
"$pa" extract "$work/n.par" --at 0.7 > "$work/at.csv" 2>"$work/at.err"
r=$("$py" "$reader" world "$work/n.par" 500 "$work/at.csv" 2>&1) && grep -q "step 500, t = 0.5 s" "$work/at.err" \
  && ok "extract --at 0.7: the snapshot at step 500 (the latest at or before), $r" || bad "extract --at 0.7: $r $(cat "$work/at.err")"
second=$("$py" "$reader" list "$work/b.par" | sed -n 2p | cut -d' ' -f1)
"$pa" extract "$work/b.par" --step "$second" -o "$work/b.csv" 2>/dev/null
r=$("$py" "$reader" world "$work/b.par" "$second" "$work/b.csv" 2>&1) && ok "extract of a generated model's snapshot (step $second): its fields named, $r" \
  || bad "extract of the ball: $r"
"$pa" extract "$work/n.par" --step 333 > /dev/null 2>"$work/err"; rc=$?
"$pa" extract "$work/n.par" --at 0.1 > /dev/null 2>>"$work/err"; rc2=$?
[ $rc -eq 1 ] && [ $rc2 -eq 1 ] && ok "extract of a step or time without a snapshot: exit 1 ($(head -1 "$work/err"))" || bad "extract without a snapshot: $rc $rc2"

# ---- usage ------------------------------------------------------------------------------------
codes=""
for args in "" "list" "frobnicate $work/n.par" "extract $work/n.par" "extract $work/n.par --step 1 --at 2" \
            "list $work/n.par --step 3" "extract $work/n.par --at x" "list a b"; do
  # shellcheck disable=SC2086
  "$pa" $args > /dev/null 2>&1; codes="$codes $?"
done
[ "$codes" = " 2 2 2 2 2 2 2 2" ] && ok "usage errors: exit 2" || bad "usage errors: exit codes$codes"
"$pa" --help | grep -q "usage: phynjo-archive list FILE" && ok "--help" || bad "--help"
finish
