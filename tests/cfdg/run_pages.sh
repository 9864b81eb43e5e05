#!/usr/bin/env bash
# A design's PDF and PostScript pages (runtime/cfdg/VectorPage), rendered by Ghostscript at one
# point a pixel, against cfdg's PNG of the same design and variation (cfdg run here): the same
# size, and at most 2% of the pixels apart by more than 40 of 255 in a channel (the two
# rasterisers' antialiasing of edges; a shape out of place, a wrong colour or framing moves far
# more). Designs: paths with strokes, caps and joins (welcome, roundcaptest), triangles, a tiled
# picture (demo1); the PDF's alpha (clonepathtest: PostScript has none). Skipped (77) without cfdg
# or gs. Usage: run_pages.sh LCJIT IMAGE_DIFF
set -u
lcjit=$1 diff=$2
examples=/usr/share/doc/contextfree/examples
command -v cfdg >/dev/null && command -v gs >/dev/null || { echo "cfdg or gs is missing: skipped"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail=0
check() {  # check DESIGN FORMAT…
  local design=$1 name; name=$(basename "$1" .cfdg); shift
  cfdg -q -s 400 -v A "$examples/$design" ref.png || { echo "FAIL $name: cfdg failed"; fail=1; return; }
  for format in "$@"; do
    "$lcjit" cfdg -q -s 400 -v A "$examples/$design" "page.$format" || { echo "FAIL $name.$format: lcjit failed"; fail=1; continue; }
    gs -q -dNOPAUSE -dBATCH -dSAFER -dEPSCrop -dGraphicsAlphaBits=4 -sDEVICE=png16m -r72 -sOutputFile=page.png "page.$format" ||
      { echo "FAIL $name.$format: gs cannot read it"; fail=1; continue; }
    if "$diff" ref.png page.png --max-fraction 0.02 > out.txt 2>&1; then echo "ok $name.$format"
    else echo "FAIL $name.$format: $(cat out.txt)"; fail=1; fi
  done
}
check welcome.cfdg pdf ps
check tests/roundcaptest.cfdg pdf ps
check tests/trisvgtest.cfdg pdf ps
check tests/demo1.cfdg pdf eps
check tests/clonepathtest.cfdg pdf
exit $fail
