#!/usr/bin/env bash
# OutputFrame("file") from model code writes the same formats as -out: frame1.obj has one line
# segment (2 vertices), frame2.obj two (3 vertices after chaining), frame2.png is a PNG.
# Usage: run_output_frame.sh LCJIT MODEL
set -eu
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$1" -b -out out.str "$2"
for f in frame1.obj frame2.obj frame2.png; do [ -s "$f" ] || { echo "missing $f"; exit 1; }; done
v1=$(grep -c '^v ' frame1.obj) v2=$(grep -c '^v ' frame2.obj)
[ "$v1" -eq 2 ] || { echo "frame1.obj: $v1 vertices, expected 2"; exit 1; }
[ "$v2" -eq 3 ] || { echo "frame2.obj: $v2 vertices, expected 3"; exit 1; }
head -c 8 frame2.png | od -An -c | grep -q 'P   N   G' || { echo "frame2.png is not a PNG"; exit 1; }
echo "ok: $v1 and $v2 vertices"
