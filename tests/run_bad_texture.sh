#!/usr/bin/env bash
# A texture that cannot be decoded (a corrupt JPEG Huffman table that stb_image
# wrote past) is left out with a warning naming it, and the run goes on: exit 0, the output
# written. lpfg, too, draws a model whose texture failed to load.
# Usage: run_bad_texture.sh LCJIT EXAMPLES_DIR CORRUPT_JPEG
set -u
lcjit=$(realpath "$1") examples=$(realpath "$2") jpeg=$(realpath "$3")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
export LCJIT_CACHE_DIR="$work/cache"
cp "$examples/birch.l" "$examples/birch.mat" .
cp "$jpeg" bad.jpg
sed 's/^texture: birch.png/texture: bad.jpg/' "$examples/birch.v" > birch.v
grep -q '^texture: bad.jpg' birch.v || { echo "FAIL: birch.v has no texture line to replace"; exit 1; }
"$lcjit" -b -out out.obj birch.v birch.mat birch.l 2> err.txt
rc=$?
cat err.txt
fail=0
[ "$rc" -eq 0 ] || { echo "FAIL: exit status $rc, expected 0"; fail=1; }
[ -s out.obj ] || { echo "FAIL: no out.obj"; fail=1; }
grep -qF "bad.jpg: warning: cannot decode JPEG image: Bogus Huffman table definition (lcjit goes on without it)" err.txt ||
  { echo "FAIL: no warning naming bad.jpg"; fail=1; }
if grep -q "error:" err.txt; then echo "FAIL: an 'error:' although the run succeeds"; fail=1; fi
[ "$fail" -eq 0 ] && echo "ok"
exit "$fail"
