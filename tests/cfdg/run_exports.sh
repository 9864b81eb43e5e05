#!/usr/bin/env bash
# A design exported as lcjit's 3D formats, and cfdg's output names: its drawn shapes as flat
# coloured triangles (a square two, a triangle one), each in its colour; its PDF a page (drawn
# like the PNG: cfdg.pages). Usage: run_exports.sh LCJIT
set -u
lcjit=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
printf 'startshape A\nshape A {\n  SQUARE [ h 0 sat 1 b 1 ]\n  TRIANGLE [ x 2 h 120 sat 1 b 1 ]\n}\n' > two.cfdg
"$lcjit" two.cfdg --variation A -w 200 200 -out two.obj -out two.pdf 2> err.txt || { cat err.txt; fail "export failed"; }
[ "$(grep -c '^f ' two.obj)" -eq 3 ] || fail "two.obj: $(grep -c '^f ' two.obj) faces, expected 3"
grep -qi 'newmtl rgb_FF0000' two.mtl || fail "no red material: $(cat two.mtl)"
grep -qi 'newmtl rgb_00FF00' two.mtl || fail "no green material: $(cat two.mtl)"
head -c 5 two.pdf | grep -q '%PDF' || fail "two.pdf is not a PDF"
# cfdg's -o names: %v / %V the variation in lower / upper case, %f the frame (0 for one picture),
# another code spelt out as cfdg does; -t says where the time went.
"$lcjit" cfdg -t -s 50 -v ABC -o 'pic_%v_%V_%f_%q.png' two.cfdg 2> err.txt || { cat err.txt; fail "lcjit cfdg failed"; }
[ -s pic_abc_ABC_0__Unknown_format_code_q_.png ] || fail "-o pic_%v_%V_%f_%q.png: not written as cfdg names it: $(ls)"
grep -q 'expand .* ms' err.txt || fail "-t printed no phases: $(cat err.txt)"
# The output file argument is a name as it is (% is no code), with _%f before the extension in an
# animation: frames numbered from 1, as wide as the count; with -f K, the one frame's name as it is.
"$lcjit" cfdg -q -s 50 -v A two.cfdg 'a%v.png' || fail "lcjit cfdg a%v.png failed"
[ -s 'a%v.png' ] || fail "a%v.png: not written as it is: $(ls)"
"$lcjit" cfdg -q -s 50 -v A -a 10 two.cfdg 'anim.png' || fail "lcjit cfdg -a 10 failed"
[ -s anim_01.png ] && [ -s anim_10.png ] && [ ! -e anim_11.png ] || fail "-a 10 anim.png: frames not anim_01 … anim_10: $(ls)"
"$lcjit" cfdg -q -s 50 -v A -a 10 -f 3 -o 'one_%f.png' two.cfdg || fail "lcjit cfdg -a 10 -f 3 failed"
[ -s one_01.png ] || fail "-a 10 -f 3 -o one_%f.png: not written as one_01.png (cfdg counts the frames it writes): $(ls)"
# lcjit's own options: --frames N with a numbered -out writes the frames lcjit cfdg -a N writes.
"$lcjit" two.cfdg --variation A -w 50 50 --frames 10 -out 'own%02d.png' 2> err.txt || { cat err.txt; fail "--frames failed"; }
for k in 01 03 10; do
  cmp -s "own$k.png" "anim_$k.png" || fail "--frames 10 -out own%02d.png: own$k.png is not lcjit cfdg -a 10's anim_$k.png"
done
# What cfdg refuses in an animation, lcjit refuses with its words.
"$lcjit" cfdg -q -a 5 two.cfdg x.svg 2> err.txt && fail "-a with an SVG output was accepted"
grep -q 'Animation cannot output to SVG' err.txt || fail "-a with .svg: $(cat err.txt)"
"$lcjit" cfdg -q -f 2 two.cfdg x.png 2> err.txt && fail "-f without -a was accepted"
grep -q 'Animation frame can only be rendered when animating' err.txt || fail "-f without -a: $(cat err.txt)"
"$lcjit" cfdg -q -a 5 -f 6 two.cfdg x.png 2> err.txt && fail "-f after the last frame was accepted"
grep -q 'Animation frame is after the end of the animation' err.txt || fail "-f 6 of 5: $(cat err.txt)"
echo ok
