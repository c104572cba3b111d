#!/usr/bin/env bash
# Sweeps over MPI ranks (phynjo::mpi): a generated simulator started by
# `mpirun --allow-run-as-root --oversubscribe -np K`, on the double pendulum with flip events.
# Catches: a summary that depends on the rank count (rows out of order, a batch written twice
# or lost, a rank that runs another rank's batch, a rank's rows dropped when it finishes after
# rank 0), a resume under MPI that loses or repeats runs (each rank must start where rank 0
# found the file), a worker rank that also writes or speaks (a usage error printed twice), one
# run under several ranks accepted (every rank would write the same output), trajectories that
# depend on the rank count, ranks that disagree on the exit status.
#   usage: test_sweep_mpi.sh FLIP_SIM MPIEXEC
set -u
sim=$1
mpiexec=${2:-mpirun}
. "$(dirname "$0")/check.sh"
# --timeout: ranks that disagree on the batches wait for each other forever; fail instead.
# Under AddressSanitizer (make test-sanitize) the ranks run without leak detection: Open MPI's
# components keep memory at exit and are unloaded by then (LeakSanitizer cannot suppress them
# by name). The sweep's own code is leak-checked by test_sweep_main.sh: the same run_sweep in
# one process.
mpi() {
  local np=$1; shift
  ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" \
    "$mpiexec" --allow-run-as-root --oversubscribe --timeout 180 -np "$np" "$sim" "$@"
}
# the same in the background: `mpi_bg ... &` puts mpiexec itself behind $! (not a subshell
# that a kill would end while mpiexec and its ranks go on writing)
mpi_bg() {
  local np=$1; shift
  ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" \
    exec "$mpiexec" --allow-run-as-root --oversubscribe --timeout 180 -np "$np" "$sim" "$@"
}
# 17 x 23 = 391 runs: 7 batches of 64 (the last short), dealt 0 1 0 1 ... / 0 1 2 0 1 2 0
grid=(--grid th1=-3:3:17 --grid th2=-3:3:23 --t-end 4)

"$sim" "${grid[@]}" --summary "$work/s1.csv"; rc=$?
[ $rc -eq 0 ] && [ "$(wc -l < "$work/s1.csv")" -eq 393 ] && ok "one process: 391 rows" || bad "one process: rc $rc"
mpi 2 "${grid[@]}" --summary "$work/s2.csv"; rc=$?
[ $rc -eq 0 ] && cmp -s "$work/s1.csv" "$work/s2.csv" && ok "2 ranks: the same bytes as one process" || bad "2 ranks: rc $rc, differ"
mpi 3 "${grid[@]}" --summary "$work/s3.csv" --threads 2; rc=$?
[ $rc -eq 0 ] && cmp -s "$work/s1.csv" "$work/s3.csv" && ok "3 ranks of 2 threads: the same bytes" || bad "3 ranks: rc $rc, differ"
# more ranks than batches: the idle ranks send nothing, the summary is whole
mpi 4 --grid th1=-3:3:10 --t-end 1 --summary "$work/few.csv"; rc=$?
"$sim" --grid th1=-3:3:10 --t-end 1 --summary "$work/few1.csv"
[ $rc -eq 0 ] && cmp -s "$work/few.csv" "$work/few1.csv" && ok "4 ranks, one batch: the same bytes" || bad "4 ranks, one batch: rc $rc"

# Resume under MPI: from a summary cut after 100 rows and inside row 101, and after a kill.
{ head -102 "$work/s1.csv"; sed -n 103p "$work/s1.csv" | head -c 30; } > "$work/p.csv"
mpi 2 "${grid[@]}" --summary "$work/p.csv" 2> "$work/p.err"; rc=$?
[ $rc -eq 0 ] && cmp -s "$work/s1.csv" "$work/p.csv" && ok "2 ranks resume after 100 rows and a partial one: the same bytes" \
  || bad "resume: rc $rc $(cat "$work/p.err")"
[ "$(grep -c "resuming .* after its 100 of 391 runs" "$work/p.err")" -eq 1 ] && ok "the resume message, once (rank 0)" \
  || bad "resume message: $(cat "$work/p.err")"
# the killed sweep runs ten times as long (--t-end 40: about 2 s on two ranks), so that the kill
# lands midway whatever this host's speed (at --t-end 4 the whole sweep takes 0.2 s: it could end
# between the first row and the kill)
kgrid=(--grid th1=-3:3:17 --grid th2=-3:3:23 --t-end 40)
"$sim" "${kgrid[@]}" --summary "$work/ks1.csv"
mpi_bg 2 "${kgrid[@]}" --summary "$work/k.csv" > /dev/null 2>&1 & pid=$!
for _ in $(seq 1 1000); do [ -f "$work/k.csv" ] && [ "$(wc -l < "$work/k.csv")" -ge 3 ] && break; sleep 0.01; done
# the whole job killed at once, as a scheduler ends it (mpiexec takes a second to pass a
# SIGTERM on: long enough for these ranks to finish); every process's arguments name k.csv
pkill -9 -f -- "$work/k.csv"; wait $pid 2>/dev/null
for _ in $(seq 1 500); do pgrep -f -- "$work/k.csv" > /dev/null || break; sleep 0.02; done
rows=$(($(wc -l < "$work/k.csv") - 2))
[ $rows -lt 391 ] && ! pgrep -f -- "$work/k.csv" > /dev/null && ok "the job killed (kill -9) after $rows of 391 rows" \
  || bad "the kill did not stop the sweep midway (rows $rows)"
mpi 3 "${kgrid[@]}" --summary "$work/k.csv" 2> "$work/k.err"
grep -q "after its $rows of 391 runs" "$work/k.err" && cmp -s "$work/ks1.csv" "$work/k.csv" \
  && ok "killed after $rows rows, resumed on 3 ranks: the same bytes" || bad "resume after kill: $(cat "$work/k.err")"

# Trajectories: the same files for any rank count.
tr=(--grid th1=-3:3:9 --grid th2=-3:3:9 --t-end 1 --every 100)
"$sim" "${tr[@]}" --summary "$work/t1.csv" --trajectories "$work/t1"
mpi 2 "${tr[@]}" --summary "$work/t2.csv" --trajectories "$work/t1"
cmp -s "$work/t1.csv" "$work/t2.csv" && [ "$(ls "$work/t1" | wc -l)" -eq 81 ] && ok "trajectories: 81 files" || bad "trajectories"
mkdir "$work/t2" && mpi 2 "${tr[@]}" --summary "$work/t2b.csv" --trajectories "$work/t2" > /dev/null
diff -r "$work/t1" "$work/t2" > /dev/null && ok "trajectories: the same files on 2 ranks" || bad "trajectories differ on 2 ranks"

# Errors: said once (rank 0), the same exit status from every rank.
out=$(mpi 2 --t-end 1 -o "$work/one.csv" 2>&1); rc=$?
[ $rc -eq 2 ] && [ "$(printf '%s\n' "$out" | grep -c "only a sweep (--grid, --uniform) runs on several MPI ranks")" -eq 1 ] \
  && [ ! -e "$work/one.csv" ] && ok "one run on 2 ranks: refused once, exit 2" || bad "one run on 2 ranks: rc $rc '$out'"
out=$(mpi 2 --grid th1=-3:3:21 --t-end 4 --summary "$work/s1.csv" 2>&1); rc=$?
[ $rc -eq 2 ] && [ "$(printf '%s\n' "$out" | grep -c "written by another command")" -eq 1 ] && cmp -s "$work/s1.csv" "$work/s2.csv" \
  && ok "another command's summary: refused once, exit 2, untouched" || bad "other command: rc $rc '$out'"
out=$(mpi 2 --grid foo=0:1:3 --summary "$work/x.csv" 2>&1); rc=$?
[ $rc -eq 2 ] && [ "$(printf '%s\n' "$out" | grep -c "'foo' is not a parameter")" -eq 1 ] && [ ! -e "$work/x.csv" ] \
  && ok "an unknown name: said once, exit 2" || bad "unknown name: rc $rc '$out'"
out=$(mpi 2 --help 2>&1); rc=$?
[ $rc -eq 0 ] && [ "$(printf '%s\n' "$out" | grep -c "^usage:")" -eq 1 ] && ok "--help printed once" || bad "--help: rc $rc"
finish
