#!/usr/bin/env bash
# `ratio ensemble_mpi2` (issue #17) = wall time of the flip map's sweep on 1 MPI rank / on 2
# ranks, the same work: the double pendulum's flip-time map (examples/models/flip_pendulum.lag,
# N × N over [-3, 3]², released from rest, 10 s cap, dt = 1 ms), each rank on one thread,
# `mpirun --oversubscribe -np K SIM --grid … --summary FILE`, mpirun's start included (what a
# user waits for), best of 3 runs, alternated. Target ≥ 1.7. Also checks the two summaries are
# the same bytes, and measures the schedule: the work of a run is its number of steps (t/dt
# from the summary), so the busiest rank's share over the mean share tells what a schedule
# loses — batches of 64 dealt round robin (phynjo's), against contiguous halves (static block).
#   usage: mpi_flipmap.sh SIM [N]     (N from PHYNJO_MPI_FLIPMAP_N, default 100)
set -euo pipefail
sim=$1; n=${2:-${PHYNJO_MPI_FLIPMAP_N:-100}}
command -v mpirun >/dev/null || { echo "mpirun not found (Debian openmpi-bin): skipped"; exit 0; }
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
grid=(--grid "th1=-3:3:$n" --grid "th2=-3:3:$n" --t-end 10 --threads 1)
run() { # ranks, summary -> wall seconds
  rm -f "$2"
  local s e; s=$(date +%s.%N)
  mpirun --allow-run-as-root --oversubscribe -np "$1" "$sim" "${grid[@]}" --summary "$2"
  e=$(date +%s.%N); awk -v a="$s" -v b="$e" 'BEGIN { printf "%.3f", b - a }'
}
best1=1e9; best2=1e9
for _ in 1 2 3; do
  t=$(run 1 "$work/one.csv"); best1=$(awk -v a="$best1" -v b="$t" 'BEGIN { print (b < a ? b : a) }')
  t=$(run 2 "$work/two.csv"); best2=$(awk -v a="$best2" -v b="$t" 'BEGIN { print (b < a ? b : a) }')
done
cmp -s "$work/one.csv" "$work/two.csv" || { echo "FAIL: the summaries of 1 and 2 ranks differ"; exit 1; }
runs=$((n * n))
echo "flip map $n x $n ($runs runs, 10 s cap), one thread per rank, best of 3:"
awk -v t="$best1" -v r="$runs" 'BEGIN { printf "  1 rank:  %7.2f s (%.0f trajectories/s)\n", t, r / t }'
awk -v t="$best2" -v r="$runs" 'BEGIN { printf "  2 ranks: %7.2f s (%.0f trajectories/s)\n", t, r / t }'
# the schedule: the busiest rank's steps over the mean, for K ranks, under batches of 64 runs
# dealt round robin and under K contiguous blocks (the map is symmetric under (th1, th2) ->
# (-th1, -th2): two halves balance by symmetry, more blocks do not)
awk -F, -v runs="$runs" 'NR > 2 {
    w = $5 / 0.001; total += w
    for (k = 2; k <= 16; k *= 2) { rr[k, int($1 / 64) % k] += w; block[k, int($1 * k / runs)] += w }
  }
  END {
    for (k = 2; k <= 16; k *= 2) {
      a = 0; b = 0
      for (r = 0; r < k; ++r) { if (rr[k, r] > a) a = rr[k, r]; if (block[k, r] > b) b = block[k, r] }
      printf "  %2d ranks: busiest / mean share: round robin of 64-run batches %.3f, contiguous blocks %.3f\n", k, a * k / total, b * k / total
    }
  }' "$work/one.csv"
awk -v a="$best1" -v b="$best2" 'BEGIN { printf "ratio ensemble_mpi2 = %.2f\n", a / b }'
