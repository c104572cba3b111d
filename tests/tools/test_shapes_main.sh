#!/usr/bin/env bash
# The simulator's --shapes FILE (a model's shapes at every output row): the header names
# each shape's coordinates, one row per output row at the same times, the bob's centre on
# the trajectory (x1 = l1 sin th1, y1 = -l1 cos th1 from the output CSV), the fixed obstacle
# still, the t-driven sphere at a sin(w t). Catches: a missing or misnamed column, shapes
# at another state or time than the row, a segment written with 3 entries, a box without its
# quaternion (lid's: q_z(th1) ⊗ q_y(th2) = (c1 c2, −s1 s2, c1 s2, s1 c2) of the half angles; the
# fixed crate's the identity), NaN columns when --param makes a box's axis zero.
#   usage: test_shapes_main.sh SHAPES_SIM
set -u
sim=$1
. "$(dirname "$0")/check.sh"

"$sim" --help | grep -q -- "--shapes FILE" && ok "--help lists --shapes" || bad "--help"
"$sim" --t-end 2 --dt 0.01 --every 10 --param h=0.25 -o "$work/out.csv" --shapes "$work/shapes.csv"; rc=$?
[ $rc -eq 0 ] && ok "exit 0" || bad "exit $rc"
want="t,bob1_x,bob1_y,bob1_z,rod1_x1,rod1_y1,rod1_z1,rod1_x2,rod1_y2,rod1_z2,bob2_x,bob2_y,bob2_z,rod2_x1,rod2_y1,rod2_z1,rod2_x2,rod2_y2,rod2_z2,post_x,post_y,post_z,float_x,float_y,float_z,arm_x1,arm_y1,arm_z1,arm_x2,arm_y2,arm_z2,lever_x1,lever_y1,lever_z1,lever_x2,lever_y2,lever_z2,lid_x,lid_y,lid_z,lid_qw,lid_qx,lid_qy,lid_qz,tilt_x,tilt_y,tilt_z,tilt_qw,tilt_qx,tilt_qy,tilt_qz,crate_x,crate_y,crate_z,crate_qw,crate_qx,crate_qy,crate_qz"
[ "$(head -1 "$work/shapes.csv")" = "$want" ] && ok "header" || bad "header: $(head -1 "$work/shapes.csv")"
[ "$(wc -l < "$work/shapes.csv")" = "$(wc -l < "$work/out.csv")" ] && [ "$(wc -l < "$work/out.csv")" -eq 22 ] \
  && ok "one row per output row (21 + header)" || bad "rows: $(wc -l < "$work/shapes.csv") vs $(wc -l < "$work/out.csv")"
# every row: the same t; bob1 and rod1's far end on the trajectory; post still; float at (h, sin(2t), 0)
paste -d, "$work/out.csv" "$work/shapes.csv" | awk -F, '
  NR > 1 {
    t = $1; th1 = $2; th2 = $3; n = 7  # out.csv: t, th1, th2, th1'"'"', th2'"'"', E  (6 columns), then shapes.csv from $7
    if ($n != t) bad = "time " t " vs " $n
    x1 = sin(th1); y1 = -cos(th1)
    if (abs($(n+1) - x1) > 1e-12 || abs($(n+2) - y1) > 1e-12 || $(n+3) != 0) bad = "bob1 at t = " t
    if (abs($(n+7) - x1) > 1e-12 || abs($(n+8) - y1) > 1e-12) bad = "rod1 end at t = " t
    if ($(n+25) != 0 || abs($(n+28) - x1) > 1e-12 || abs($(n+29) - y1) > 1e-12) bad = "arm (capsule) at t = " t
    if ($(n+19) != 1 || $(n+20) != -2 || $(n+21) != 0) bad = "post moved at t = " t
    if (abs($(n+22) - 0.25) > 1e-15 || abs($(n+23) - sin(2 * t)) > 1e-12) bad = "float at t = " t
    c1 = cos(th1 / 2); s1 = sin(th1 / 2); c2 = cos(th2 / 2); s2 = sin(th2 / 2)
    if (abs($(n+40) - c1 * c2) > 1e-12 || abs($(n+41) + s1 * s2) > 1e-12 || abs($(n+42) - c1 * s2) > 1e-12 ||
        abs($(n+43) - s1 * c2) > 1e-12) bad = "lid (box) turned wrongly at t = " t
    if ($(n+51) != -1 || $(n+52) != -2 || $(n+53) != 0 || $(n+54) != 1 || $(n+55) != 0 || $(n+56) != 0 || $(n+57) != 0)
      bad = "crate (fixed box) at t = " t
  }
  function abs(v) { return v < 0 ? -v : v }
  END { if (bad) { print bad; exit 1 } }' > "$work/why.txt" \
  && ok "bob, rod, post, float, arm, lid and crate where the model puts them" || bad "positions: $(cat "$work/why.txt")"
"$sim" --t-end 1 --shapes /nonexistent/dir/s.csv -o "$work/o.csv" 2> "$work/err.txt"; rc=$?
[ $rc -eq 1 ] && grep -q "cannot write /nonexistent/dir/s.csv" "$work/err.txt" && ok "unwritable --shapes: exit 1, named" \
  || bad "unwritable: exit $rc, $(cat "$work/err.txt")"
# tilt turns about (k, k, k): k = 0 leaves it no orientation — refused, not NaN columns
"$sim" --t-end 1 --param k=0 --shapes "$work/zero.csv" -o "$work/o.csv" 2> "$work/err.txt"; rc=$?
[ $rc -eq 1 ] && grep -q "the axis of turn 1 of box 'tilt' has length zero" "$work/err.txt" \
  && ! grep -qi nan "$work/zero.csv" && ok "an axis made zero by --param: exit 1, the box named, no NaN written" \
  || bad "zero axis: exit $rc, $(cat "$work/err.txt")"
finish
