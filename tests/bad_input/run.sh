#!/usr/bin/env bash
# The bad-input suite: every error class of docs/language.md and every documented limit, each
# checked against the exact first diagnostic line.
#   usage: run.sh PATH/TO/phynjo-lagc PATH/TO/phynjo-cas
set -u
lagc=$1; cas=$2
here=$(cd "$(dirname "$0")" && pwd)
pass=0; fail=0
check() { # NAME GOT WANT
    if [ "$2" == "$3" ]; then pass=$((pass+1)); else fail=$((fail+1)); printf 'FAIL %s\n  got:  %s\n  want: %s\n' "$1" "$2" "$3"; fi
}
cd "$here/lag"
while IFS=$'\t' read -r file want; do
    got=$("$lagc" "$file" --emit=eom 2>&1 >/dev/null | head -1)
    "$lagc" "$file" --emit=eom >/dev/null 2>&1; rc=$?
    check "$file" "$got" "$want"
    check "$file (exit status)" "$rc" "1"
done < "$here/lag_expected.tsv"
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
# a 100 MB file
head -c 104857600 /dev/zero | tr '\0' 'x' > "$work/huge.lag"
check "100 MB file" "$(cd "$work" && "$lagc" huge.lag --emit=eom 2>&1 | head -1)" \
      "huge.lag:1:1: error: file too large (104857600 bytes; the limit is 16777216)"
# the size of the derived equations and of the generated code
cp "$here/../../examples/models/double_pendulum.lag" "$work/dp.lag"
check "equation size limit" "$(cd "$work" && "$lagc" dp.lag -o dp.cpp --max-nodes=50 2>&1 | head -1)" \
      "dp.lag:9:1: error: the equations of motion are too large: 72 distinct subexpressions (the limit is 50)"
check "output size limit" "$(cd "$work" && "$lagc" dp.lag -o dp.cpp --max-output=1000 2>&1 | head -1 | sed 's/would be [0-9]* bytes/would be N bytes/')" \
      "dp.lag:9:1: error: the generated code would be N bytes (the limit is 1000)"
# expressions through phynjo-cas, one per line, each error on its line
got=$(cut -f1 "$here/expressions.tsv" | "$cas" simplify - 2>&1 >/dev/null | grep ': error: ')
want=$(cut -f2 "$here/expressions.tsv")
check "phynjo-cas bad expressions" "$got" "$want"
out_lines=$(cut -f1 "$here/expressions.tsv" | "$cas" simplify - 2>/dev/null | wc -l)
check "phynjo-cas: one output line per input line" "$out_lines" "$(wc -l < "$here/expressions.tsv")"
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
