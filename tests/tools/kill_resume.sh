# Sourced by the archive's test scripts (after check.sh): runs killed at random moments and
# resumed from their archive, compared byte for byte with the run never stopped.
#   reference NAME COMMAND...   the run without a stop in $work/NAME, its time in $work/NAME/ms
#   killed DIR LABEL N FILES -- COMMAND...   (below)

# milliseconds since the epoch
now_ms() { date +%s%3N; }

# killed DIR LABEL N FILES -- COMMAND...: N times, runs COMMAND --archive A, kills it with SIGKILL
# when its first FILE has reached a random part (under 90%) of its length in the uninterrupted
# run (a part of 0: at start-up) and up to a tenth of the run's time later, and continues it
# with --resume A (or runs it again when no archive was made); each time the FILES
# (space-separated, in $work/DIR) must then be those of the run without a stop (FILE.ref). The moment follows the run's progress, not the clock: a machine
# slower or busier than when the reference was timed still has its kills inside the run.
killed() {
  local dir="$work/$1" name=$2 n=$3 files=$4; shift 5
  local ms=$(cat "$dir/ms") kills=0 from_snapshots=0 wrong="" f watch
  watch=${files%% *}
  local full=$(stat -c %s "$dir/$watch.ref")
  for ((i = 0; i < n; ++i)); do
    rm -f "$dir/a.par"; for f in $files; do rm -f "$dir/$f"; done
    "$@" --archive "$dir/a.par" >/dev/null 2>/dev/null &
    local pid=$! part=$((RANDOM % 900)) size st=R extra=$((RANDOM % (ms / 10 + 1)))
    local at=$((full * part / 1000))
    # until the output has grown that far, or the run has ended (a zombie: state Z)
    while [ "$st" != Z ] && [ -e "/proc/$pid" ]; do
      size=$(stat -c %s "$dir/$watch" 2>/dev/null) || size=0
      [ "$size" -ge "$at" ] && break
      sleep 0.002
      read -r _ _ st _ 2>/dev/null < "/proc/$pid/stat" || st=Z
    done
    # then up to a tenth of the run's time more: a file that grows in bursts (stdio's buffer,
    # the rows flushed at each snapshot) still has its kills anywhere between the bursts
    [ "$st" != Z ] && sleep "$((extra / 1000)).$(printf '%03d' $((extra % 1000)))"
    local delay="$part/1000 of $watch + $extra ms"
    kill -9 "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    [ $? -eq 137 ] && kills=$((kills + 1))
    if [ -e "$dir/a.par" ]; then "$@" --resume "$dir/a.par" >/dev/null 2>"$dir/kill.err"
    else "$@" --archive "$dir/a.par" >/dev/null 2>"$dir/kill.err"; fi
    grep -q "continuing from the snapshot at step" "$dir/kill.err" && from_snapshots=$((from_snapshots + 1))
    for f in $files; do
      cmp -s "$dir/$f" "$dir/$f.ref" || wrong="$wrong killed at $delay: $f differs [$(cmp "$dir/$f" "$dir/$f.ref" 2>&1 | head -1); $(tail -c 200 "$dir/kill.err")];"
    done
  done
  # the kills must land in the run, and after snapshots: else they test nothing
  if [ -n "$wrong" ]; then bad "$name:$wrong"
  elif [ $kills -lt $((n / 2)) ] || [ $from_snapshots -lt $((n / 4)) ]; then
    bad "$name: only $kills of $n kills in the run, $from_snapshots resumes from a snapshot (the run takes $ms ms)"
  else ok "$name: killed at $n random moments ($kills in the run, $from_snapshots resumed from a snapshot; the run takes $ms ms), each resumed to the same bytes"; fi
}

# reference NAME COMMAND...: the run without a stop, timed (ms)
reference() {
  local name=$1; shift
  mkdir -p "$work/$name"
  local t0=$(now_ms)
  "$@" 2>"$work/$name/ref.err" >/dev/null || bad "$name: the reference run failed [$(head -c 300 "$work/$name/ref.err")]"
  echo $(( $(now_ms) - t0 )) > "$work/$name/ms"
}

