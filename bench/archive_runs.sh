#!/usr/bin/env bash
# The simulation archive (docs/archive.md) on a generated model's simulator, in one run:
# - `ratio archive_overhead_double_pendulum` = the run's time without the archive / with it at
#   the default spacing (a snapshot a second of wall time and one at the end, each synced:
#   fdatasync of the output and the archive); target ≥ 0.95 (bench_archive_worlds has the pile);
# - `ratio archive_vs_full_output_double_pendulum` = bytes of the CSV of every step / bytes of
#   an archive with a snapshot every 20,000 steps (100 in the run), which reconstructs any step
#   (--at) in at most 20,000 steps; target ≥ 100;
# - `ratio archive_seek_double_pendulum` = time of a run from t = 0 to a late T / time of
#   `--at T` from that archive (printed with the size and time of each).
# Best of 5, alternated. The double pendulum (examples/models/double_pendulum.lag), rk4,
# dt = 1 ms, 2000 s (2·10⁶ steps).
#   usage: archive_runs.sh SIM
set -euo pipefail
sim=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
run=(--t-end 2000 --dt 1e-3 --every 1000)
. "$(dirname "$0")/archive_util.sh"
plain=1e9; archived=1e9; full=1e9; at=1e9
for _ in 1 2 3 4 5; do
  plain=$(min "$plain" "$(secs "$sim" "${run[@]}" -o "$work/plain.csv")")
  rm -f "$work/a.par"
  archived=$(min "$archived" "$(secs "$sim" "${run[@]}" -o "$work/arch.csv" --archive "$work/a.par")")
done
cmp -s "$work/plain.csv" "$work/arch.csv" || { echo "FAIL: the run with --archive wrote other bytes"; exit 1; }
# the full output: every step
"$sim" --t-end 2000 --dt 1e-3 --every 1 -o "$work/full.csv"
full_bytes=$(stat -c %s "$work/full.csv"); rm -f "$work/full.csv"
# the archive for seeking: 100 snapshots
rm -f "$work/a.par"
"$sim" "${run[@]}" -o "$work/arch.csv" --archive "$work/a.par" --archive-every 20000
archive_bytes=$(stat -c %s "$work/a.par")
T=1987.654
for _ in 1 2 3 4 5; do
  full=$(min "$full" "$(secs "$sim" "${run[@]}" --t-end "$T" -o "$work/to.csv")")
  at=$(min "$at" "$(secs "$sim" "${run[@]}" --archive "$work/a.par" --at "$T" -o "$work/at.csv")")
done
[ "$(tail -1 "$work/to.csv")" = "$(tail -1 "$work/at.csv")" ] || { echo "FAIL: --at T differs from the run to T"; exit 1; }
echo "double pendulum, rk4, 2e6 steps of 1 ms, best of 5:"
echo "  without the archive: $plain s; with it (the default: a snapshot a second of wall time, synced): $archived s"
echo "  CSV of every step: $full_bytes bytes; an archive of 100 snapshots (every 20,000 steps): $archive_bytes bytes"
echo "  run from 0 to T = $T s: $full s; --at $T from the archive: $at s"
ratios archive_overhead_double_pendulum archive_vs_full_output_double_pendulum archive_seek_double_pendulum
