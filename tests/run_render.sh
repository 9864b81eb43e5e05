#!/usr/bin/env bash
# Rendering test: tests/render/NAME.args holds the lcjit arguments (files relative to examples/);
# the picture (400×400) must match tests/render/NAME.png (tests/tools/image_diff.cpp).
# A line "# image_diff: OPTIONS" in the .args file gives the comparison stricter options (labels:
# Qt's glyph pixels are matched to the level, so their test allows no more than rounding).
# LCJIT_UPDATE_REFERENCES=1 rewrites the reference instead. Modes (6th argument):
#   expect-differ  mutants/NAME.args must NOT match (the comparison's own sensitivity check);
#   lpfg           the picture must match lpfg's own, tests/render/lpfg/NAME.png.
# Usage: run_render.sh LCJIT IMAGE_DIFF EXAMPLES_DIR RENDER_DIR NAME [expect-differ|lpfg]
set -u
lcjit=$1 diff=$2 examples=$3 dir=$4 name=$5 mode=${6:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# A mutant names the reference it must differ from in its first line: "# reference: NAME".
if [ "$mode" = expect-differ ]; then
  argsfile="$dir/mutants/$name.args"
  reference="$dir/$(sed -n 's/^# reference: *//p' "$argsfile").png"
elif [ "$mode" = lpfg ]; then
  argsfile="$dir/$name.args"
  reference="$dir/lpfg/$name.png"
else
  argsfile="$dir/$name.args"
  reference="$dir/$name.png"
fi
args=$(grep -v '^#' "$argsfile")
diffopts=$(sed -n 's/^# image_diff: *//p' "$argsfile")
out="$work/$name.png"
(cd "$examples" && "$lcjit" -q -w 400 400 -out "$out" $args) || { echo "lcjit failed"; exit 1; }
if [ -n "${LCJIT_UPDATE_REFERENCES:-}" ] && [ -z "$mode" ]; then
  cp "$out" "$reference" && echo "updated $reference" && exit 0
fi
"$diff" "$reference" "$out" $diffopts
status=$?
if [ "$mode" = expect-differ ]; then
  [ $status -eq 1 ] && { echo "differs, as it must"; exit 0; }
  echo "the mutated model still matches $reference: the comparison is not sensitive enough"
  exit 1
fi
exit $status
