#!/usr/bin/env bash
# Sweeps (--grid, --uniform, --samples, --seed, --summary, --trajectories, --threads) of a generated
# simulator, on the double pendulum with flip events (examples/models/flip_pendulum.lag).
# Catches: a summary that depends on the thread count (rows out of order, a shared RNG, a
# model shared between threads), a resume that loses, repeats or garbles runs (after a kill
# -9 or a partly written row), a summary of another command taken over, grid points off their
# formula, Monte Carlo values outside their range or not reproducible from the seed, a failing
# run that ends the sweep instead of being recorded, malformed options accepted, trajectory files
# that differ from one run's --output, depend on the thread count or go missing on a resume.
#   usage: test_sweep_main.sh FLIP_SIM
set -u
sim=$1
. "$(dirname "$0")/check.sh"
grid=(--grid th1=-3:3:20 --grid th2=-3:3:20 --t-end 10)

"$sim" --help | grep -q -- "--grid NAME=LO:HI:N" && ok "--help lists --grid" || bad "--help"

# The same summary on 1 and 3 threads, byte for byte.
"$sim" "${grid[@]}" --summary "$work/s1.csv"; rc1=$?
"$sim" "${grid[@]}" --summary "$work/s3.csv" --threads 3; rc3=$?
[ $rc1 -eq 0 ] && [ $rc3 -eq 0 ] && ok "exit 0" || bad "exit $rc1 / $rc3"
cmp -s "$work/s1.csv" "$work/s3.csv" && ok "1 and 3 threads: the same bytes" || bad "1 and 3 threads differ"
[ "$(wc -l < "$work/s1.csv")" -eq 402 ] && ok "400 rows, a signature line and a header" || bad "rows: $(wc -l < "$work/s1.csv")"
[ "$(head -1 "$work/s1.csv")" = "# phynjo sweep: flip_pendulum --grid th1=-3:3:20 --grid th2=-3:3:20 --t-end 10 --lanes" ] \
  && ok "signature line (without --summary and --threads; --lanes, the default, last)" || bad "signature: $(head -1 "$work/s1.csv")"
want="run,th1,th2,status,t,end_th1,end_th2,end_th1',end_th2',first_flip1,first_flip1_back,first_flip2,first_flip2_back,max_energy_error,reason"
[ "$(sed -n 2p "$work/s1.csv")" = "$want" ] && ok "header" || bad "header: $(sed -n 2p "$work/s1.csv")"
# grid points: run k = (i, j), th1 = -3 + 6 i/19 (slowest), th2 = -3 + 6 j/19; a stopped run's
# t is its first flip, and |end angle| = pi for the arm that flipped; finished runs end at 10 s
awk -F, 'NR > 2 {
    k = $1; i = int(k / 20); j = k % 20
    if (abs($2 - (-3 + 6 * i / 19)) > 1e-15 || abs($3 - (-3 + 6 * j / 19)) > 1e-15) bad = "grid point of run " k
    if ($4 == "stopped") {
      first = 1e9; for (c = 10; c <= 13; ++c) if ($c != "" && $c + 0 < first) first = $c + 0
      if (abs($5 - first) > 1e-12) bad = "run " k ": t is not its first flip"
      if (abs(abs($6) - 3.141592653589793) > 1e-9 && abs(abs($7) - 3.141592653589793) > 1e-9) bad = "run " k ": no arm at pi"
      ++stopped
    } else if ($4 == "finished") { if ($5 != 10) bad = "run " k " finished at " $5; ++finished }
    else bad = "run " k ": status " $4
    if ($14 > 1e-6) bad = "run " k ": energy error " $14
  }
  END { if (stopped < 100 || finished < 10) bad = "stopped " stopped ", finished " finished; if (bad != "") { print bad; exit 1 } }
  function abs(v) { return v < 0 ? -v : v }' "$work/s1.csv" && ok "grid points, flip times, energy errors" || bad "rows"
# the corner (-3, -3) is near the top: it flips within a second; (0, 0) never moves
awk -F, '$1 == 0 && $4 == "stopped" && $5 < 1 { f = 1 } END { exit !f }' "$work/s1.csv" && ok "run 0 flips early" || bad "run 0"

# Resume after kill -9 (once a batch is written) and after a partly written row: the same bytes.
"$sim" "${grid[@]}" --summary "$work/k.csv" & pid=$!
for _ in $(seq 1 500); do [ -f "$work/k.csv" ] && [ "$(wc -l < "$work/k.csv")" -ge 3 ] && break; sleep 0.01; done
kill -9 $pid 2>/dev/null; wait $pid 2>/dev/null
rows=$(($(wc -l < "$work/k.csv") - 2))
"$sim" "${grid[@]}" --summary "$work/k.csv" --threads 2 2> "$work/k.err"
cmp -s "$work/s1.csv" "$work/k.csv" && ok "killed after $rows rows, resumed: the same bytes" || bad "resume after kill"
if [ $rows -lt 400 ]; then
  grep -q "resuming .* after its $rows of 400 runs" "$work/k.err" && ok "resume message" || bad "resume message: $(cat "$work/k.err")"
fi
{ head -12 "$work/s1.csv"; sed -n 13p "$work/s1.csv" | head -c 40; } > "$work/p.csv"
"$sim" "${grid[@]}" --summary "$work/p.csv" 2> "$work/p.err"
cmp -s "$work/s1.csv" "$work/p.csv" && ok "a partly written row dropped and redone" || bad "partial row"
grep -q "after its 10 of 400" "$work/p.err" && ok "... after its 10 complete rows" || bad "partial: $(cat "$work/p.err")"
"$sim" --grid th1=-3:3:21 --grid th2=-3:3:20 --t-end 10 --summary "$work/s1.csv" 2> "$work/o.err"; rc=$?
[ $rc -eq 2 ] && grep -q "written by another command" "$work/o.err" && cmp -s "$work/s1.csv" "$work/s3.csv" \
  && ok "another command's summary refused, untouched" || bad "other command: rc $rc $(cat "$work/o.err")"

# Monte Carlo: values in their ranges, reproducible from the seed, other with another seed;
# the same bytes on 1 and 4 threads; grid x samples.
mc=(--uniform th1=-1:1 --uniform "th2'=0:0.5" --samples 30 --seed 7 --t-end 1)
"$sim" "${mc[@]}" --summary "$work/m1.csv"
"$sim" "${mc[@]}" --summary "$work/m4.csv" --threads 4
cmp -s "$work/m1.csv" "$work/m4.csv" && ok "Monte Carlo: the same bytes on 1 and 4 threads" || bad "Monte Carlo threads"
awk -F, 'NR > 2 { if ($2 < -1 || $2 >= 1 || $3 < 0 || $3 >= 0.5) bad = 1; if ($2 == prev) bad = 1; prev = $2; n++ }
  END { exit bad || n != 30 }' "$work/m1.csv" && ok "30 draws in [-1, 1) x [0, 0.5), all different" || bad "draws"
"$sim" --uniform th1=-1:1 --uniform "th2'=0:0.5" --samples 30 --seed 8 --t-end 1 --summary "$work/m8.csv"
[ "$(sed -n 3p "$work/m1.csv" | cut -d, -f2)" != "$(sed -n 3p "$work/m8.csv" | cut -d, -f2)" ] && ok "another seed, other draws" || bad "seed"
"$sim" --grid g=9:10:2 --uniform th1=0:1 --samples 3 --t-end 0.1 --summary "$work/gm.csv"
awk -F, 'NR > 2 { g[NR - 3] = $2 } END { exit !(g[0] == 9 && g[2] == 9 && g[3] == 10 && g[5] == 10 && NR == 8) }' "$work/gm.csv" \
  && ok "grid x samples: 2 x 3 runs, samples innermost" || bad "grid x samples"

# A failing run is a row with its reason; the sweep goes on.
"$sim" --param m1=0 --init th2=0.5 --grid m2=0:1:2 --t-end 0.1 --summary "$work/f.csv"; rc=$?
# (one swept axis: status is field 3, the reason field 14)
[ $rc -eq 0 ] && [ "$(sed -n 3p "$work/f.csv" | cut -d, -f3)" = failed ] \
  && sed -n 3p "$work/f.csv" | cut -d, -f14- | grep -q "mass matrix is singular" \
  && [ "$(sed -n 4p "$work/f.csv" | cut -d, -f3)" = finished ] && ok "m1 = m2 = 0: failed with a reason, the next run finished" \
  || bad "failing run: rc $rc; $(sed -n 3,4p "$work/f.csv")"

# --trajectories: the same files on 1 and 3 threads; a resumed sweep writes the files of the
# runs it adds. The runs go in SIMD lanes by default (libmvec's sines): each run's file is one
# run's --output to rounding, and bit for bit a sweep of that run alone (a run's bits do not
# depend on its neighbours); with --no-lanes, bit for bit one run's --output.
tr=(--grid th1=-3:3:7 --grid th2=-3:3:7 --t-end 2 --every 50)
"$sim" "${tr[@]}" --summary "$work/t1.csv" --trajectories "$work/t1"
"$sim" "${tr[@]}" --summary "$work/t1b.csv" --trajectories "$work/t3" --threads 3
[ "$(ls "$work/t1" | wc -l)" -eq 49 ] && [ -f "$work/t1/run_00.csv" ] && [ -f "$work/t1/run_48.csv" ] \
  && ok "49 trajectory files, run_00 ... run_48" || bad "trajectory files: $(ls "$work/t1" | head -3)"
diff -r "$work/t1" "$work/t3" > /dev/null && cmp -s <(tail -n +2 "$work/t1.csv") <(tail -n +2 "$work/t1b.csv") \
  && ok "trajectories and summary: the same bytes on 1 and 3 threads" || bad "trajectories differ with threads"
"$sim" --t-end 2 --every 50 --init th1=-3,th2=-3 -o "$work/one0.csv" 2> /dev/null
"$sim" --t-end 2 --every 50 --init th1=-1,th2=1 -o "$work/one18.csv"
"$sim" "${tr[@]}" --no-lanes --summary "$work/n1.csv" --trajectories "$work/n1"
cmp -s "$work/one0.csv" "$work/n1/run_00.csv" && ok "--no-lanes: run 0 (stopped by a flip) is one run's --output" || bad "--no-lanes: run_00 differs from one run"
grep -q "^18,-1,1,finished," "$work/n1.csv" && cmp -s "$work/one18.csv" "$work/n1/run_18.csv" \
  && ok "--no-lanes: run 18 (th1 = -1, th2 = 1, finished) is one run's --output" || bad "--no-lanes: run_18 differs from one run"
[ "$(cut -d, -f1-4 "$work/n1.csv" | tail -n +3)" = "$(cut -d, -f1-4 "$work/t1.csv" | tail -n +3)" ] \
  && ok "lanes: the statuses of the sweep without them" || bad "lanes: other statuses"
# in lanes, one run's --output to rounding: the same rows and times, every number within 1e-9
# (relative to max(1, |x|)) after 2 s — and not bit for bit (else the lanes are not in use)
close() { # FILE_A FILE_B: same shape, numbers within 1e-9, at least one differing
  paste -d, "$1" "$2" | awk -F, 'NR == 1 { next } { n = NF / 2; for (i = 1; i <= n; ++i) { a = $i; b = $(i + n)
      d = a - b; d = d < 0 ? -d : d; s = a < 0 ? -a : a; s = s < 1 ? 1 : s; if (d > 1e-9 * s) far = 1; if (a != b) differ = 1 } }
    END { exit far || !differ }' && [ "$(wc -l < "$1")" -eq "$(wc -l < "$2")" ]
}
close "$work/one0.csv" "$work/t1/run_00.csv" && close "$work/one18.csv" "$work/t1/run_18.csv" \
  && ok "lanes: runs 0 and 18 are one run's --output to rounding (1e-9), not bit for bit" || bad "lanes: runs 0 and 18 vs --output"
"$sim" --grid th1=-1:-1:1 --grid th2=1:1:1 --t-end 2 --every 50 --summary "$work/o18.csv" --trajectories "$work/o18"
cmp -s "$work/o18/run_0.csv" "$work/t1/run_18.csv" && [ "$(sed -n 3p "$work/o18.csv" | cut -d, -f2-)" = "$(grep "^18," "$work/t1.csv" | cut -d, -f2-)" ] \
  && ok "lanes: run 18 alone (a sweep of one point) gives its row and trajectory bit for bit" || bad "lanes: run 18 alone differs"
# a parameter sweep: runs of their own parameters share the lanes — the same bytes on 1 and 3
# threads, a run alone (a sweep of its one point) the same row; with --no-lanes each row is one
# run's --param … --output, bit for bit
pg=(--grid g=4:16:5 --grid th1=1:3:5 --t-end 3)
"$sim" "${pg[@]}" --summary "$work/pg1.csv"
"$sim" "${pg[@]}" --summary "$work/pg3.csv" --threads 3
cmp -s "$work/pg1.csv" "$work/pg3.csv" && ok "parameter sweep: the same bytes on 1 and 3 threads" || bad "parameter sweep differs with threads"
"$sim" --grid g=10:10:1 --grid th1=2.5:2.5:1 --t-end 3 --summary "$work/pg12.csv"
[ "$(grep "^13," "$work/pg1.csv" | cut -d, -f2-)" = "$(sed -n 3p "$work/pg12.csv" | cut -d, -f2-)" ] \
  && ok "parameter sweep: run 13 (g = 10, th1 = 2.5) alone gives its row bit for bit" || bad "parameter sweep: run 13 alone differs"
"$sim" "${pg[@]}" --summary "$work/pgn.csv" --no-lanes
"$sim" --param g=10 --init th1=2.5 --t-end 3 -o "$work/pg12.out" 2> /dev/null
[ "$(grep "^13," "$work/pgn.csv" | cut -d, -f5-9)" = "$(tail -1 "$work/pg12.out" | cut -d, -f1-5)" ] \
  && [ "$(grep "^13," "$work/pg1.csv" | cut -d, -f5-9)" != "$(tail -1 "$work/pg12.out" | cut -d, -f1-5)" ] \
  && ok "parameter sweep: --no-lanes is one run's --param --output bit for bit, lanes not" || bad "parameter sweep vs --param --output"
[ "$(cut -d, -f1-4 "$work/pgn.csv" | tail -n +3)" = "$(cut -d, -f1-4 "$work/pg1.csv" | tail -n +3)" ] \
  && grep -q ",stopped," "$work/pg1.csv" && grep -q ",finished," "$work/pg1.csv" \
  && ok "parameter sweep: lanes' statuses are --no-lanes' (runs stopped and finished)" || bad "parameter sweep: statuses"
# the signature: --lanes (the default) spelt out is the same command; --no-lanes another one
head -1 "$work/t1.csv" | grep -q -- " --lanes$" && ! head -1 "$work/n1.csv" | grep -q -- "lanes" \
  && ok "signature: --lanes by default, nothing with --no-lanes" || bad "signature: $(head -1 "$work/t1.csv") / $(head -1 "$work/n1.csv")"
"$sim" "${tr[@]}" --lanes --summary "$work/l1.csv" --trajectories "$work/t1"
cmp -s "$work/l1.csv" "$work/t1.csv" && ok "--lanes spelt out: the same summary, signature line included" || bad "--lanes spelt out differs"
"$sim" "${tr[@]}" --summary "$work/n1.csv" --trajectories "$work/n1" 2> "$work/n1.err"; rc=$?
[ $rc -eq 2 ] && grep -q "written by another command" "$work/n1.err" && ok "a --no-lanes summary is not resumed in lanes" \
  || bad "--no-lanes summary resumed in lanes: rc $rc $(cat "$work/n1.err")"
awk -F, 'NR > 1 { if (abs($1 - 0.05 * (NR - 2)) > 1e-12) bad = 1 } END { exit bad || NR != 42 }
  function abs(v) { return v < 0 ? -v : v }' "$work/t1/run_18.csv" && ok "--every 50: 41 rows at t = 0.05 k" || bad "every"
# a sweep into tp killed after 30 runs: its summary's first 30 rows and their trajectories
# (the signature names the folder)
{ head -1 "$work/t1.csv" | sed "s|--trajectories [^ ]*|--trajectories $work/tp|"; sed -n 2,32p "$work/t1.csv"; } > "$work/tp.csv"
rm -rf "$work/tp"; mkdir "$work/tp"; cp "$work/t1"/run_[0-2]?.csv "$work/tp/"
"$sim" "${tr[@]}" --summary "$work/tp.csv" --trajectories "$work/tp" 2> "$work/tp.err"
grep -q "after its 30 of 49 runs" "$work/tp.err" && [ "$(tail -n +2 "$work/tp.csv" | md5sum)" = "$(tail -n +2 "$work/t1.csv" | md5sum)" ] \
  && diff -r "$work/t1" "$work/tp" > /dev/null && ok "resumed after 30 runs: the other 19 trajectories written" \
  || bad "resume with trajectories: $(cat "$work/tp.err")"
"$sim" --grid th1=0:1:2 --t-end 0.1 --summary "$work/tf.csv" --trajectories /proc/phynjo-no 2> "$work/tf.err"; rc=$?
[ $rc -eq 1 ] && grep -q "cannot make the folder /proc/phynjo-no" "$work/tf.err" && ok "an unwritable folder: exit 1, named" \
  || bad "unwritable folder: rc $rc $(cat "$work/tf.err")"

# Bad input: a clear error, exit 2.
expect_usage() {
  local what=$1; shift
  local err; err=$("$sim" "$@" 2>&1 >/dev/null); local rc=$?
  [ $rc -eq 2 ] && printf '%s' "$err" | grep -q -- "$what" && ok "usage error: $what" || bad "'$*': rc $rc, '$err'"
}
expect_usage "expected NAME=LO:HI:N" --grid th1=0:1 --summary "$work/x.csv"
expect_usage "'a' is not a finite number" --grid th1=a:1:3 --summary "$work/x.csv"
expect_usage "'0' is not a positive whole number of points" --grid th1=0:1:0 --summary "$work/x.csv"
expect_usage "'foo' is not a parameter" --grid foo=0:1:3 --summary "$work/x.csv"
expect_usage "LO must not exceed HI" --uniform th1=1:0 --summary "$work/x.csv"
expect_usage "needs --summary FILE" --grid th1=0:1:3
expect_usage "--samples needs --uniform" --grid th1=0:1:3 --samples 4 --summary "$work/x.csv"
expect_usage "swept twice" --grid th1=0:1:3 --uniform th1=0:1 --summary "$work/x.csv"
expect_usage "are for one run" --grid th1=0:1:3 --summary "$work/x.csv" -o "$work/y.csv"
expect_usage "--every goes with one run's --output or a sweep's --trajectories" --grid th1=0:1:3 --summary "$work/x.csv" --every 3
expect_usage "--trajectories needs a folder" --grid th1=0:1:3 --summary "$work/x.csv" --trajectories ""
expect_usage "sweeps run with --integrator rk4" --grid th1=0:1:3 --summary "$work/x.csv" --integrator cvode
[ ! -e "$work/x.csv" ] && ok "no summary written on a usage error" || bad "x.csv written"
finish
