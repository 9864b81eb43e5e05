#!/usr/bin/env bash
# A design exported as lcjit's other formats, and cfdg's output names: its drawn shapes as flat coloured triangles (a
# square two, a triangle one), each in its colour. Usage: run_exports.sh LCJIT
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
# cfdg's -o names: %v / %V the variation in lower / upper case; -t says where the time went.
"$lcjit" cfdg -t -s 50 -v ABC two.cfdg 'pic_%v_%V.png' 2> err.txt || { cat err.txt; fail "lcjit cfdg failed"; }
[ -s pic_abc_ABC.png ] || fail "-o pic_%v_%V.png: not written as pic_abc_ABC.png: $(ls)"
grep -q 'expand .* ms' err.txt || fail "-t printed no phases: $(cat err.txt)"
echo ok
