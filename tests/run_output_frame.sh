#!/usr/bin/env bash
# OutputFrame("file") from model code.
# 1. Batch mode does what lpfg's does: records the name, writes nothing, and the interpretation
#    rules run only where lpfg runs them (output_frame_order.l: seen=0, 1, 2, no frame.png; a
#    note on stderr says why nothing was written).
# 2. --output-frames writes each file a step named once the step is over, in the formats -out
#    writes: frame1.obj has one line segment (2 vertices), frame2.obj two (3 vertices after
#    chaining), frame2.png is a PNG; the order of the rules is unchanged (seen=0, 1, 2 again).
# Usage: run_output_frame.sh LCJIT FRAMES_DIR
set -eu
lcjit=$1 dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
expected=$(printf 'seen=0\nseen=1\nseen=2')

"$lcjit" -b -out out.str "$dir/output_frame_order.l" > seen.txt 2> err.txt || { echo "batch: lcjit failed"; cat err.txt; exit 1; }
[ "$(cat seen.txt)" = "$expected" ] || { echo "batch: printed $(tr '\n' ' ' < seen.txt), expected seen=0 1 2"; exit 1; }
[ ! -e frame.png ] || { echo "batch: OutputFrame wrote frame.png; lpfg's batch mode writes nothing"; exit 1; }
grep -q 'OutputFrame("frame.png") writes nothing in batch mode' err.txt || { echo "batch: no note on stderr"; cat err.txt; exit 1; }

"$lcjit" -b --output-frames -out out.str "$dir/output_frame_order.l" > seen.txt || { echo "--output-frames: lcjit failed"; exit 1; }
[ "$(cat seen.txt)" = "$expected" ] || { echo "--output-frames: printed $(tr '\n' ' ' < seen.txt), expected seen=0 1 2"; exit 1; }
[ -s frame.png ] || { echo "--output-frames: no frame.png"; exit 1; }

"$lcjit" -b --output-frames -out out.str "$dir/output_frame.l" || { echo "output_frame.l: lcjit failed"; exit 1; }
for f in frame1.obj frame2.obj frame2.png; do [ -s "$f" ] || { echo "missing $f"; exit 1; }; done
v1=$(grep -c '^v ' frame1.obj) v2=$(grep -c '^v ' frame2.obj)
[ "$v1" -eq 2 ] || { echo "frame1.obj: $v1 vertices, expected 2"; exit 1; }
[ "$v2" -eq 3 ] || { echo "frame2.obj: $v2 vertices, expected 3"; exit 1; }
head -c 8 frame2.png | od -An -c | grep -q 'P   N   G' || { echo "frame2.png is not a PNG"; exit 1; }
echo "ok: seen=0 1 2 with and without --output-frames; $v1 and $v2 vertices"
