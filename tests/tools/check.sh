# Sourced by the command-line test scripts: a scratch folder removed at exit, and ok/bad
# counters; `finish` prints the closing line "N passed, N failed" and sets the exit status.
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
pass=0; fail=0
ok() { echo "ok   $1"; pass=$((pass+1)); }
bad() { echo "FAIL $1"; fail=$((fail+1)); }
finish() { echo "$pass passed, $fail failed"; [ "$fail" -eq 0 ]; }
