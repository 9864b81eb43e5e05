#!/usr/bin/env bash
# Exports of whole example models (-out FILE), where a unit test's hand-made geometry cannot show
# that the model's own drawing reaches the file:
#   terrain_grid  examples/terrain.l: the terrain's grid lines are explicit colours (yellow or red
#                 times the texel): the .obj's line objects use materials named after those colours
#                 (rgb_RRGGBB) with that colour as Kd, not palette entry 255's.
#   multiview     examples/multiview.l (three windows: the top half and two quarters, a 10-pixel
#                 border): .svg, .eps and .pdf hold all three views, each in its rectangle as the
#                 picture lays them out (400 × 400: rows of 195 px with 10 between them, the bottom
#                 row's columns likewise), each drawing what its view group draws; a .obj holds
#                 view 0 and says so.
# Usage: run_export_models.sh LCJIT EXAMPLES_DIR CASE
set -u
lcjit=$(realpath "$1") examples=$(realpath "$2") case=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; cat "$work/err.txt" 2>/dev/null; exit 1; }
cd "$examples" || exit 1

case $case in
terrain_grid)
  "$lcjit" -q -out "$work/t.obj" terrain.v terrain.mat terrain.l 2>"$work/err.txt" || fail "lcjit failed"
  grep -q '^o lines_rgb_' "$work/t.obj" || fail "no grid lines in an explicit colour's object"
  ! grep '^o lines_' "$work/t.obj" | grep -qv '^o lines_rgb_' || fail "grid lines in a palette colour's object"
  # Each rgb_RRGGBB material's Kd is RR/255 GG/255 BB/255.
  awk 'function digit(h, i) { return index("0123456789ABCDEF", substr(h, i, 1)) - 1 }
       function byte(h) { return digit(h, 1) * 16 + digit(h, 2) }
       /^newmtl / { name = $2; next }
       /^Kd / && name ~ /^rgb_/ {
         for (i = 0; i < 3; ++i) { want = byte(substr(name, 5 + 2 * i, 2)) / 255; d = $(i + 2) - want
           if (d * d > 1e-12) { print name ": Kd " $2 " " $3 " " $4; bad = 1 } }
         ++seen }
       END { if (!seen) print "no rgb_ material"; exit bad || !seen }' "$work/t.mtl" || fail "rgb_ materials"
  ;;
multiview)
  for f in mv.svg mv.eps mv.pdf; do
    "$lcjit" -q -w 400 400 -out "$work/$f" multiview.l multiview.v multiview.map 2>"$work/err.txt" || fail "lcjit failed for $f"
  done
  svg="$work/mv.svg"
  [ "$(grep -o '<svg id="view[0-9]*" x="[0-9]*" y="[0-9]*" width="[0-9]*" height="[0-9]*"' "$svg" | tr '\n' '|')" = \
    '<svg id="view0" x="0" y="0" width="400" height="195"|<svg id="view1" x="0" y="205" width="195" height="195"|<svg id="view2" x="205" y="205" width="195" height="195"|' ] ||
    fail "the SVG's views: $(grep -o '<svg id=[^>]*>' "$svg")"
  grep -q '<rect id="border" x="0" y="0" width="400" height="400" fill="#3c3c3c"/>' "$svg" || fail "no border colour"
  # What each view draws: Whole and Buds spheres (triangles) and lines, Branches lines only.
  view() { awk -v v="$1" '/<svg id="view/ { on = index($0, "<svg id=\"view" v "\"") > 0 } on' "$svg"; }
  for v in 0 1 2; do view $v | grep -q '<g class="l ' || fail "view $v has no lines"; done
  view 0 | grep -q '<g class="t ' || fail "view 0 has no spheres"
  view 2 | grep -q '<g class="t ' || fail "view 2 has no spheres"
  ! view 1 | grep -q '<g class="t ' || fail "view 1 (branches only) has triangles"
  # EPS (1 pt per pixel, y up) and PDF: each view clipped to its rectangle, lines in each.
  eps="$work/mv.eps"
  [ "$(grep -c '^gsave newpath .* clip ' "$eps")" = 3 ] || fail "EPS: $(grep -c '^gsave' "$eps") views"
  grep -q '^gsave newpath 0 205 moveto 400 0 rlineto 0 195 rlineto -400 0 rlineto closepath clip' "$eps" || fail "EPS view 0"
  grep -q '^gsave newpath 205 0 moveto 195 0 rlineto 0 195 rlineto -195 0 rlineto closepath clip' "$eps" || fail "EPS view 2"
  [ "$(awk '/^gsave/ { ++v } / L$/ { lines[v] = 1 } END { print lines[1] lines[2] lines[3] }' "$eps")" = 111 ] ||
    fail "EPS: a view without lines"
  pdf="$work/mv.pdf"
  for r in '0 205 400 195' '0 0 195 195' '205 0 195 195'; do
    grep -q "^q $r re W n " "$pdf" || fail "PDF: no view at $r"
  done
  # A 3D format holds view 0, and says so.
  "$lcjit" -q -w 400 400 -out "$work/mv.obj" multiview.l multiview.v multiview.map 2>"$work/err.txt" || fail "lcjit failed for .obj"
  grep -q 'mv.obj holds view 0 (Whole) only' "$work/err.txt" || fail "no word of the views a .obj leaves out"
  ;;
*) echo "unknown case $case"; exit 2 ;;
esac
echo ok
