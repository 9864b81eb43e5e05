#!/usr/bin/env bash
# Makes docs/images/studio-*.png: examples/studio in lcjit's window under Xvfb with each panel
# open. Usage: docs/studio-shots.sh [LCJIT] (default build/lcjit). Needs xvfb-run, xdotool and
# ImageMagick's import.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
lcjit=$(realpath "${1:-$here/../build/lcjit}")
if [ -z "${LCJIT_IN_XVFB:-}" ]; then
  exec env LCJIT_IN_XVFB=1 xvfb-run -a -s "-screen 0 1280x900x24" "$0" "$lcjit"
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$here/../examples/studio/"* "$work/"
cd "$work"
export LCJIT_WINDOW_LAYOUT=$work/layout.txt
inputs=(plant.map plant.vset plant.func plant.tset plant.l)
# shot NAME PANEL [ACTION]: the window with PANEL open, after ACTION (a function) if given.
shot() {
  rm -f layout.txt
  "$lcjit" -w 960 640 --panel "$2" "${inputs[@]}" > /dev/null 2>&1 &
  local pid=$!
  for _ in $(seq 1 200); do grep -q "^$2/" layout.txt 2>/dev/null && break; sleep 0.1; done
  sleep 1
  if [ -n "${3:-}" ]; then "$3"; sleep 1.5; fi
  import -window "$(xdotool search --name 'lcjit: plant.l' | head -1)" "$here/images/studio-$1.png"
  kill $pid; wait $pid 2>/dev/null || true
}
centre() { awk -F'\t' -v l="$1" '$1 == l { split($2, r, " "); print int((r[1] + r[3]) / 2), int((r[2] + r[4]) / 2) }' layout.txt; }
pick() {  # Step back once, then a click on the main stem, low in the picture
  xdotool mousemove $(centre "String/Step back") click 1; sleep 1.5
  xdotool mousemove 563 560; sleep 0.5; xdotool click 1
}
shot parameters Parameters
shot profile Profile
shot string String pick
shot function "Function width"
shot timeline "Function LEAF"
shot colormap Colormap
echo "wrote $(ls "$here"/images/studio-*.png | wc -l) pictures into docs/images"
