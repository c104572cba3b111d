#!/usr/bin/env bash
# The archive of the runtime's worlds (ArchivedRun, docs/archive.md) through
# examples/archive/archived_world, in one run:
# - `ratio archive_overhead_pile` = the 1,000-sphere pile's run time (3 s, dt = 1/240 s, warm-
#   started contacts) without the archive / with it at the default spacing (a snapshot a second
#   of wall time, synced); target ≥ 0.95;
# - `ratio archive_vs_full_output_nbody` = bytes of the full state (every body's position and
#   velocity, %.17g) written every step / bytes of the archive at the default spacing, from
#   which any step is reconstructed (--at); N = 512, 10⁴ steps; target ≥ 100;
# - `ratio archive_seek_nbody` = time of the run from t = 0 to a late T / time of `--at T`.
# Best of 5, alternated.
#   usage: archive_worlds.sh ARCHIVED_WORLD
set -euo pipefail
aw=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
. "$(dirname "$0")/archive_util.sh"

# ---- the pile: overhead at the default spacing -------------------------------------------------
plain=1e9; archived=1e9
for _ in 1 2 3 4 5; do
  plain=$(min "$plain" "$(secs "$aw" pile --n 10 -o "$work/plain.csv")")
  rm -f "$work/pile.par"
  archived=$(min "$archived" "$(secs "$aw" pile --n 10 -o "$work/arch.csv" --archive "$work/pile.par")")
done
cmp -s "$work/plain.csv" "$work/arch.csv" || { echo "FAIL: the pile with --archive wrote other rows"; exit 1; }
pile_bytes=$(stat -c %s "$work/pile.par")
echo "1,000-sphere pile, 3 s of dt = 1/240 s (720 steps), best of 5:"
echo "  without the archive: $plain s; with it (a snapshot per second of wall time, synced): $archived s, $pile_bytes bytes"

# ---- N-body: size against the full output, and seeking -----------------------------------------
nb=(nbody --n 512 --t-end 10 --every 100)
rm -f "$work/nb.par"
"$aw" "${nb[@]}" -o "$work/nb.csv" --archive "$work/nb.par" 2>/dev/null
archive_bytes=$(stat -c %s "$work/nb.par")
full_bytes=$("$aw" nbody --n 512 --t-end 10 --every 1 --full | wc -c)
T=9.8765
full=1e9; at=1e9
for _ in 1 2 3 4 5; do
  full=$(min "$full" "$(secs "$aw" "${nb[@]}" --t-end "$T" -o "$work/to.csv")")
  at=$(min "$at" "$(secs "$aw" "${nb[@]}" --archive "$work/nb.par" --at "$T" -o "$work/at.csv")")
done
[ "$(tail -1 "$work/to.csv")" = "$(tail -1 "$work/at.csv")" ] || { echo "FAIL: --at T differs from the run to T"; exit 1; }
echo "N-body, 512 bodies, 10^4 steps of 1 ms:"
echo "  the full state every step: $full_bytes bytes; the archive (a snapshot per second of wall time): $archive_bytes bytes"
echo "  run from 0 to T = $T s: $full s; --at $T from the archive: $at s"
ratios archive_overhead_pile archive_vs_full_output_nbody archive_seek_nbody
