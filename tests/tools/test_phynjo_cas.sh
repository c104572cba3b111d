#!/usr/bin/env bash
# The phynjo-cas command line: results, batch mode (one line out per line in), errors and
# exit codes.   usage: test_phynjo_cas.sh PATH/TO/phynjo-cas
set -u
cas=$1
fails=0
expect() { # expect NAME EXPECTED-STDOUT EXPECTED-STATUS -- ARGS…
    local name=$1 want=$2 want_rc=$3; shift 4
    local got rc
    got=$("$cas" "$@" 2>/dev/null); rc=$?
    if [ "$got" != "$want" ] || [ "$rc" != "$want_rc" ]; then
        echo "FAIL $name: got [$got] (exit $rc), want [$want] (exit $want_rc)"; fails=$((fails+1))
    else echo "ok   $name"; fi
}
expect simplify "1" 0 -- simplify "sin(x)^2 + cos(x)^2"
expect simplify-exact "1/2" 0 -- simplify "1/3 + 1/6"
expect diff "2*x*cos(x^2)" 0 -- diff x "sin(x^2)"
expect diff-velocity "l^2*m*theta'" 0 -- diff "theta'" "1/2*m*l^2*theta'^2 + m*g*l*cos(theta)"
expect latex '\frac{l^{2} m \dot{\theta}^{2}}{2}' 0 -- latex "1/2*m*l^2*theta'^2"
expect cpp "9.81*std::sin(x) + x*x" 0 -- cpp "9.81*sin(x) + x^2"
expect eval "0.5" 0 -- eval "sin(x)^2 + y" x=pi/6 y=1/4
expect eval-velocity "6.0" 0 -- eval "x'*y" "x'=2" y=3
expect eval-missing "" 1 -- eval "x + y" x=1
expect eval-nan "" 1 -- eval "log(x)" x=-1
expect parse-error "" 1 -- simplify "x +"
expect usage "" 2 -- frobnicate
expect usage-args "" 2 -- diff x
expect bad-variable "" 2 -- diff "x^2" "x"
expect version "phynjo-cas 0.1.0" 0 -- --version

# batch mode: exactly one output line per input line, errors on stderr with line numbers
out=$(printf 'x^2 + 2*x\nx +\nsin(x)^2+cos(x)^2\n\n(a+b)^2 - a^2\r\n' | "$cas" simplify - 2>/tmp/phynjo_cas_err.$$); rc=$?
want=$'2*x + x^2\n\n1\n\n2*a*b + b^2'
if [ "$out" == "$want" ] && [ $rc -eq 1 ] && [ "$(printf '%s\n' "$out" | wc -l)" -eq 5 ] \
   && grep -q '^<stdin>:2:4: error: expected an expression' /tmp/phynjo_cas_err.$$ \
   && grep -q '^<stdin>:4:1: error: expected an expression' /tmp/phynjo_cas_err.$$; then echo "ok   batch"
else echo "FAIL batch: [$out] rc=$rc"; cat /tmp/phynjo_cas_err.$$; fails=$((fails+1)); fi
out=$(printf 'x^3\ny\n' | "$cas" diff x -); [ "$out" == $'3*x^2\n0' ] && echo "ok   batch-diff" || { echo "FAIL batch-diff [$out]"; fails=$((fails+1)); }
out=$(printf 'x\n1/0\nx/2\n' | "$cas" eval - x=4 2>/dev/null); [ "$out" == $'4.0\n\n2.0' ] && echo "ok   batch-eval" || { echo "FAIL batch-eval [$out]"; fails=$((fails+1)); }
# a 10,000-line batch: still one line per line
n=$(seq 1 10000 | sed 's/.*/x^&/' | "$cas" diff x - | wc -l); [ "$n" -eq 10000 ] && echo "ok   batch-10000" || { echo "FAIL batch-10000 ($n lines)"; fails=$((fails+1)); }
# stderr text of an argument error
err=$("$cas" simplify "x @ y" 2>&1 >/dev/null)
[ "$err" == $'<argument>:1:3: error: unexpected character \'@\'\n    x @ y\n      ^' ] && echo "ok   stderr" || { echo "FAIL stderr [$err]"; fails=$((fails+1)); }
rm -f /tmp/phynjo_cas_err.$$
echo "$((25 - fails)) passed, $fails failed"
[ $fails -eq 0 ]
