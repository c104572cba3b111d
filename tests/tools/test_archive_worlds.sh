#!/usr/bin/env bash
# The archive of runs of the runtime's worlds (simulate/archived_run.hpp, docs/archive.md,
# *Worlds of the runtime*) end to end, through examples/archive/archived_world.cpp: a sphere
# pile (rigid bodies, contacts warm-started from the cache fields), a scene (a .lag double
# pendulum in the pile) and an N-body cluster. Every row holds the world's hash, so equal rows
# are equal worlds, bit for bit.
# Catches: a snapshot without the Stepper's clock (a continued run's times t_snap + j·dt, not
# t₀ + k·dt) or without a field (the warm-start cache), rows not flushed before the snapshot
# that counts them, a state at T (--at) that is not the run's, snapshots spaced by wall time
# that change the run, a continued run that depends on the thread count, an archive of another
# world continued, an output file shorter than the snapshot says not refused.
#   usage: test_archive_worlds.sh ARCHIVED_WORLD
set -u
aw=$1
. "$(dirname "$0")/check.sh"
. "$(dirname "$0")/kill_resume.sh"
RANDOM=20261205 # the kill times and the instants of --at: fixed, as every seed in the tests

# ---- 1. kill -9 at 20 random moments of each world ------------------------------------------
declare -A opts=(
  [pile]="pile --n 6 --t-end 2 --every 1"
  [scene]="scene --t-end 1.5 --every 1"
  [nbody]="nbody --n 128 --t-end 3 --every 1"
)
declare -A every=([pile]=20 [scene]=25 [nbody]=200)
for wld in pile scene nbody; do
  d="$work/$wld"
  # shellcheck disable=SC2086
  reference "$wld" "$aw" ${opts[$wld]} -o "$d/out.csv.ref"
  [ "$(wc -l < "$d/out.csv.ref")" -gt 300 ] || bad "$wld: the reference run wrote $(wc -l < "$d/out.csv.ref") rows"
  # shellcheck disable=SC2086
  killed "$wld" "$wld" 20 "out.csv" -- \
    "$aw" ${opts[$wld]} -o "$d/out.csv" --archive-every "${every[$wld]}"
done

# ---- 2. --at T: the run's row at T bit for bit ------------------------------------------------
d="$work/nbody"
"$aw" ${opts[nbody]} -o "$d/plain.csv" --archive "$d/plain.par" --archive-every 150 2>/dev/null
cmp -s "$d/plain.csv" "$d/out.csv.ref" && ok "nbody: --archive does not change the run's bytes" \
  || bad "nbody: the run with --archive writes other bytes"
at_ok=0; at_bad=""
for ((i = 0; i < 50; ++i)); do
  k=$((RANDOM % 3001))
  if [ $i -lt 40 ]; then T=$(awk -v k=$k 'BEGIN { printf "%.17g", k * 0.001 }'); want=$(sed -n "$((k + 2))p" "$d/out.csv.ref")
  else T=$(awk -v k=$k 'BEGIN { printf "%.7f", k * 0.001 + 0.0004 }') # between the steps: a shortened last one
    want=$("$aw" nbody --n 128 --t-end "$T" --every 100000 2>/dev/null | tail -1)
  fi
  got=$("$aw" nbody --n 128 --every 1 --archive "$d/plain.par" --at "$T" 2>"$d/at.err" | tail -1)
  if [ -n "$want" ] && [ "$got" = "$want" ]; then at_ok=$((at_ok + 1)); else at_bad="T = $T: got '$got' want '$want' $(head -c 200 "$d/at.err")"; fi
done
[ $at_ok -eq 50 ] && ok "nbody: --at T at 50 random times (10 between the steps) equals the run's row bit for bit" \
  || bad "nbody --at: $at_ok of 50 [$at_bad]"
# the pile and the scene: the warm-start cache and the models' coordinates come back too
for wld in pile scene; do
  d="$work/$wld"
  # shellcheck disable=SC2086
  "$aw" ${opts[$wld]} -o "$d/plain.csv" --archive "$d/plain.par" --archive-every 30 2>/dev/null
  at_ok=0; at_bad=""
  rows=$(($(wc -l < "$d/out.csv.ref") - 1))
  for ((i = 0; i < 10; ++i)); do
    k=$((RANDOM % rows))
    T=$(awk -v k=$k 'BEGIN { printf "%.17g", k / 240 }')
    want=$(sed -n "$((k + 2))p" "$d/out.csv.ref")
    # shellcheck disable=SC2086
    got=$("$aw" ${opts[$wld]} --archive "$d/plain.par" --at "$T" 2>"$d/at.err" | tail -1)
    if [ "$got" = "$want" ]; then at_ok=$((at_ok + 1)); else at_bad="T = $T: got '$got' want '$want' $(head -c 200 "$d/at.err")"; fi
  done
  [ $at_ok -eq 10 ] && ok "$wld: --at T at 10 random steps equals the run's row bit for bit" || bad "$wld --at: $at_ok of 10 [$at_bad]"
done

# ---- 3. snapshots by wall time; another thread count; a finished run continued --------------
d="$work/scene"
"$aw" ${opts[scene]} -o "$d/wall.csv" --archive "$d/wall.par" --archive-every 0.02s 2>/dev/null
"$aw" ${opts[scene]} -o "$d/one.csv" --archive "$d/one.par" --archive-every 100000 2>/dev/null # the last snapshot only
one=$(stat -c %s "$d/one.par") wall=$(stat -c %s "$d/wall.par")
cmp -s "$d/wall.csv" "$d/out.csv.ref" && [ "$wall" -gt $((3 * one)) ] \
  && ok "scene: snapshots every 0.02 s of wall time ($((wall / one)) times the archive of one) leave the run's bytes as they were" \
  || bad "scene: --archive-every 0.02s: $(cmp "$d/wall.csv" "$d/out.csv.ref" 2>&1), $wall bytes against $one for one snapshot"
# a run killed on one thread continued on two: the same bytes (the threads change no bit)
rm -f "$d/t.par"; "$aw" ${opts[scene]} -o "$d/t.csv" --archive "$d/t.par" --archive-every 25 --t-end 1 2>/dev/null
"$aw" ${opts[scene]} -o "$d/t.csv" --resume "$d/t.par" --archive-every 25 --threads 2 2>"$d/t.err"
cmp -s "$d/t.csv" "$d/out.csv.ref" && grep -q "continuing from the snapshot at step 240" "$d/t.err" \
  && ok "scene: a run to 1 s on one thread continued to 1.5 s on two: the bytes of the run never stopped" \
  || bad "scene: continued on two threads: $(cmp "$d/t.csv" "$d/out.csv.ref" 2>&1) $(cat "$d/t.err")"

# ---- 4. refused -----------------------------------------------------------------------------
d="$work/pile"
cp "$d/plain.csv" "$d/p2.csv"
"$aw" nbody --n 128 --t-end 3 --every 1 -o "$d/p2.csv" --resume "$d/plain.par" 2>"$d/err"; rc=$?
[ $rc -eq 1 ] && grep -q "another run: .*world" "$d/err" && ok "the archive of a pile continued as an N-body run: exit 1 ($(head -c 120 "$d/err"))" \
  || bad "another world continued: rc $rc $(cat "$d/err")"
"$aw" pile --n 5 --t-end 2 --every 1 -o "$d/p2.csv" --resume "$d/plain.par" 2>"$d/err"; rc=$?
[ $rc -eq 1 ] && grep -q "n: '6' in the archive, '5' in this run" "$d/err" && ok "another size: exit 1, naming it" \
  || bad "another size continued: rc $rc $(cat "$d/err")"
head -c 100 "$d/plain.csv" > "$d/short.csv"
# shellcheck disable=SC2086
"$aw" ${opts[pile]} -o "$d/short.csv" --resume "$d/plain.par" 2>"$d/err"; rc=$?
[ $rc -eq 1 ] && grep -q "shorter" "$d/err" && ok "an output shorter than the snapshot says: exit 1 ($(head -c 120 "$d/err"))" \
  || bad "a short output continued: rc $rc $(cat "$d/err")"
"$aw" pile --archive "$d/plain.par" -o "$d/x.csv" 2>"$d/err"; rc=$?
[ $rc -eq 2 ] && grep -q "exists" "$d/err" && ok "--archive of an existing file: exit 2, never overwritten" || bad "--archive over a file: rc $rc"
"$aw" pile --at 1 2>/dev/null; rc=$?
"$aw" pile --archive "$d/y.par" 2>/dev/null; rc2=$?
"$aw" pile --archive "$d/y.par" -o "$d/y.csv" --archive-every 2q 2>/dev/null; rc3=$?
[ $rc -eq 2 ] && [ $rc2 -eq 2 ] && [ $rc3 -eq 2 ] && ok "usage errors: exit 2" || bad "usage errors: $rc $rc2 $rc3"
finish
