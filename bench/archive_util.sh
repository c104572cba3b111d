# Sourced by bench/archive_runs.sh and bench/archive_worlds.sh.
# secs COMMAND...: its wall time (s); min A B; ratios OVERHEAD SIZE SEEK: the three `ratio`
# lines from $plain/$archived (s), $full_bytes/$archive_bytes, $full/$at (s).
secs() { local s e; s=$(date +%s.%N); "$@" >/dev/null 2>&1; e=$(date +%s.%N); awk -v a="$s" -v b="$e" 'BEGIN { printf "%.4f", b - a }'; }
min() { awk -v a="$1" -v b="$2" 'BEGIN { print (b < a ? b : a) }'; }
ratios() {
  awk -v a="$plain" -v b="$archived" -v n="$1" 'BEGIN { printf "ratio %s = %.3f\n", n, a / b }'
  awk -v a="$full_bytes" -v b="$archive_bytes" -v n="$2" 'BEGIN { printf "ratio %s = %.1f\n", n, a / b }'
  awk -v a="$full" -v b="$at" -v n="$3" 'BEGIN { printf "ratio %s = %.1f\n", n, a / b }'
}
