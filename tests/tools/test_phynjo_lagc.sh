#!/usr/bin/env bash
# phynjo-lagc on the command line: outputs, determinism, exit codes, diagnostics on stderr.
#   usage: test_phynjo_lagc.sh PATH/TO/phynjo-lagc MODELS_DIR
set -u
lagc=$1; models=$2
. "$(dirname "$0")/check.sh"

"$lagc" "$models/double_pendulum.lag" -o "$work/a/../dp.cpp" 2>/dev/null; [ $? -ne 0 ] && ok "missing output directory is an error" || bad "missing output directory"
"$lagc" "$models/double_pendulum.lag" -o "$work/dp.cpp" && [ -s "$work/dp.cpp" ] && [ -s "$work/dp.hpp" ] \
  && grep -q '#include "dp.hpp"' "$work/dp.cpp" && grep -q 'namespace double_pendulum' "$work/dp.hpp" \
  && ok "writes OUT.cpp and OUT.hpp" || bad "writes OUT.cpp and OUT.hpp"
cp "$work/dp.cpp" "$work/first.cpp"; cp "$work/dp.hpp" "$work/first.hpp"
"$lagc" "$models/double_pendulum.lag" -o "$work/dp.cpp"
cmp -s "$work/dp.cpp" "$work/first.cpp" && cmp -s "$work/dp.hpp" "$work/first.hpp" && ok "deterministic: byte-identical output" || bad "deterministic"
"$lagc" "$models/nlink_cart_5.lag" -o "$work/n1.cpp" && "$lagc" "$models/nlink_cart_5.lag" -o "$work/n2.cpp" \
  && diff <(sed 's/n1\.hpp/X/' "$work/n1.cpp") <(sed 's/n2\.hpp/X/' "$work/n2.cpp") >/dev/null && ok "deterministic: nlink" || bad "deterministic: nlink"
"$lagc" "$models/pendulum.lag" --emit=eom | grep -qx 'M(1,1) = l^2\*m' && ok "--emit=eom" || bad "--emit=eom"
# readable f (catches the derivation's factored 900-character form printed as is)
hoop="$(dirname "$0")/../codegen/models/rotating_hoop.lag"
"$lagc" "$hoop" --emit=eom | grep -qx "f(1) = R^2\*m\*w^2\*cos(th)\*sin(th) - R\*g\*m\*sin(th)" && ok "--emit=eom: f simplified for the reader" \
  || bad "--emit=eom readable f: $("$lagc" "$hoop" --emit=eom | grep '^f')"
"$lagc" "$models/pendulum.lag" --emit=latex -o "$work/p.tex" && grep -q '\\documentclass' "$work/p.tex" && grep -q 'M_{11} = l^{2} m' "$work/p.tex" \
  && ok "--emit=latex" || bad "--emit=latex"
# --emit=linear: the upright pendulum, exact, with its unstable mode
lin=$("$lagc" "$models/pendulum.lag" --emit=linear --at theta=pi)
echo "$lin" | grep -qx '  \[g/l, 0\]' && echo "$lin" | grep -q '1 unstable mode' && ok "--emit=linear --at theta=pi" \
  || bad "--emit=linear: $lin"
"$lagc" "$models/pendulum.lag" --emit=linear --at "theta=pi" --format=latex | grep -q 'pmatrix' && ok "--emit=linear --format=latex" || bad "--emit=linear --format=latex"
"$lagc" "$models/pendulum.lag" --emit=linear --at "phi=0" >/dev/null 2>"$work/lin.err"; [ $? -eq 1 ] \
  && grep -q "'phi' is not a coordinate" "$work/lin.err" && ok "--emit=linear: unknown name, exit 1" || bad "--emit=linear unknown name"
"$lagc" "$models/pendulum.lag" --emit=eom --at theta=0 >/dev/null 2>&1; [ $? -eq 2 ] && ok "--at without --emit=linear: exit 2" || bad "--at without --emit=linear"
"$lagc" "$models/pendulum.lag" --emit=linear --at theta >/dev/null 2>&1; [ $? -eq 2 ] && ok "--at NAME without =: exit 2" || bad "--at NAME without ="
"$lagc" --help | grep -q 'usage: phynjo-lagc' && ok "--help" || bad "--help"
[ "$("$lagc" --version)" = "phynjo-lagc 0.1.0" ] && ok "--version" || bad "--version"
"$lagc" >/dev/null 2>&1; [ $? -eq 2 ] && ok "no arguments: exit 2" || bad "no arguments: exit 2"
"$lagc" "$models/pendulum.lag" --bogus >/dev/null 2>&1; [ $? -eq 2 ] && ok "unknown option: exit 2" || bad "unknown option"
"$lagc" "$models/pendulum.lag" >/dev/null 2>&1; [ $? -eq 2 ] && ok "no -o for C++: exit 2" || bad "no -o for C++"
"$lagc" "$models/pendulum.lag" --emit=eom --main >/dev/null 2>&1; [ $? -eq 2 ] && ok "--emit=eom --main: exit 2" || bad "--emit=eom --main"
"$lagc" "$models/pendulum.lag" --emit=latex --main -o "$work/x.tex" >/dev/null 2>&1; [ $? -eq 2 ] && ok "--emit=latex --main: exit 2" || bad "--emit=latex --main"
"$lagc" "$work/nonexistent.lag" -o "$work/x.cpp" >/dev/null 2>&1; [ $? -eq 1 ] && ok "unreadable model: exit 1" || bad "unreadable model"
printf 'coordinates q\nlagrangian 1/2*m*q'"'"'^2\n' > "$work/bad.lag"
err=$("$lagc" "$work/bad.lag" -o "$work/bad.cpp" 2>&1 >/dev/null); rc=$?
want="$work/bad.lag:2:16: error: unknown name 'm'
    lagrangian 1/2*m*q'^2
                   ^"
[ $rc -eq 1 ] && [ "$err" == "$want" ] && [ ! -e "$work/bad.cpp" ] && ok "model error: exit 1, diagnostic, no output" || { bad "model error [$err] rc=$rc"; }
head -c 110000000 /dev/zero | tr '\0' ' ' > "$work/huge.lag"
err=$("$lagc" "$work/huge.lag" -o "$work/huge.cpp" 2>&1); rc=$?
[ $rc -eq 1 ] && echo "$err" | grep -q "file too large (110000000 bytes" && ok "a 110 MB file: diagnosed" || bad "huge file [$err]"
printf '\x89PNG\r\n' > "$work/bin.lag"
"$lagc" "$work/bin.lag" -o "$work/bin.cpp" 2>&1 | grep -q "not UTF-8 text" && ok "binary file: diagnosed" || bad "binary file"
# --parts, --pieces-above, --split-above: counts within bounds, C++ only; the part files written
for bad_opt in "--parts 0" "--parts 17" "--parts" "--pieces-above=0" "--split-above x"; do
  err=$("$lagc" "$models/double_pendulum.lag" -o "$work/p.cpp" $bad_opt 2>&1); rc=$?
  [ $rc -eq 2 ] && echo "$err" | grep -q -- "${bad_opt%%[ =]*}" && ok "$bad_opt: usage error" || bad "$bad_opt (exit $rc): $err"
done
"$lagc" "$models/double_pendulum.lag" --emit=eom --parts 2 >/dev/null 2>&1; [ $? -eq 2 ] && ok "--parts with --emit=eom: usage error" || bad "--parts with --emit=eom"
"$lagc" "$models/double_pendulum.lag" -o "$work/p.cpp" --parts=3 && [ -s "$work/p.part2.cpp" ] && [ -s "$work/p.part3.cpp" ] \
  && [ ! -e "$work/p.part4.cpp" ] && ok "--parts=3: p.part2.cpp and p.part3.cpp beside p.cpp" || bad "--parts=3 files"
# units cost nothing at run time: a model with units generates the same code as without them
# (the file's name kept: the first line of each output names it)
for m in bouncing_ball impact_oscillator; do
  mkdir -p "$work/units" "$work/plain"
  cp "$models/$m.lag" "$work/units/$m.lag"
  sed 's/ \[[^]]*\]//g' "$models/$m.lag" > "$work/plain/$m.lag"
  grep -q '\[' "$work/units/$m.lag" && ! grep -q '\[' "$work/plain/$m.lag" \
    && (cd "$work/units" && "$lagc" $m.lag -o $m.cpp) && (cd "$work/plain" && "$lagc" $m.lag -o $m.cpp) \
    && cmp -s "$work/units/$m.cpp" "$work/plain/$m.cpp" && cmp -s "$work/units/$m.hpp" "$work/plain/$m.hpp" \
    && ok "units change no generated code ($m)" || bad "units change the generated code ($m)"
done
# units as written (N/m, not kg/s^2); a parameter computed from others in base units
"$lagc" "$models/impact_oscillator.lag" --emit=latex > "$work/io.tex"
grep -q 'k = 1\\;\\mathrm{N/m}' "$work/io.tex" && grep -q 'c = \\frac{1}{10}\\;\\mathrm{kg/s}' "$work/io.tex" \
  && ok "--emit=latex: the units of parameters as written" || bad "--emit=latex units: $(grep -E '^\\\[ (k|c) =' "$work/io.tex")"
printf 'coordinates x [m]\nparameters m = 2 [kg], k = 8 [N/m], w = sqrt(k/m)\nlagrangian 1/2*m*x'"'"'^2 - 1/2*k*x^2\n' > "$work/u.lag"
"$lagc" "$work/u.lag" --emit=latex | grep -q 'w = .*\\;\\mathrm{1/s}\|w = .*\\;\\mathrm{s^{-1}}' \
  && ok "--emit=latex: a derived parameter's unit from its dimension" || bad "--emit=latex derived unit: $("$lagc" "$work/u.lag" --emit=latex | grep 'w =')"
# a constraint's phi named like its multiplier: a coordinate ph1 prints phi_1 too
printf 'coordinates ph1, y\nparameters l = 1\nlagrangian 1/2*(ph1'"'"'^2 + y'"'"'^2)\nconstraint rod: ph1^2 + y^2 = l^2\n' > "$work/ph.lag"
"$lagc" "$work/ph.lag" --emit=latex > "$work/ph.tex"
grep -q '\\phi_{\\mathrm{rod}} = ' "$work/ph.tex" && ! grep -q '\\phi_{1} = ' "$work/ph.tex" \
  && ok "--emit=latex: the constraint is phi_rod, not phi_1 beside a coordinate ph1" || bad "--emit=latex constraint symbol"
finish
