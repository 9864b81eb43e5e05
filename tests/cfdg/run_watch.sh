#!/usr/bin/env bash
# lcjit design.cfdg --watch: one process; a saved edit of the design, or of a file it imports,
# draws again; a broken save is reported at its line and column and the last good picture stays.
# Usage: run_watch.sh LCJIT
set -u
lcjit=$1
work=$(mktemp -d)
trap 'kill $pid 2>/dev/null; rm -rf "$work"' EXIT
cd "$work"
export LCJIT_CACHE_DIR="$work/cache"
fail() { echo "FAIL: $*"; echo "--- stderr:"; cat err.txt; exit 1; }
wait_for() {  # wait_for PATTERN FILE: up to 60 s
  for _ in $(seq 1 600); do grep -q "$1" "$2" 2>/dev/null && return 0; sleep 0.1; done
  fail "no '$1' in $2"
}
printf 'startshape A\nimport part.cfdg\nshape A { SQUARE [ ] B [ x 2 ] }\n' > design.cfdg
printf 'shape B { TRIANGLE [ ] }\n' > part.cfdg
"$lcjit" design.cfdg --watch --variation A -out out.svg 2> err.txt > /dev/null &
pid=$!
wait_for 'watching' err.txt
wait_for '<rect' out.svg
grep -q '#TRIANGLE"' out.svg || fail "the imported shape was not drawn"

sed -i 's/SQUARE/CIRCLE/' design.cfdg
wait_for 'reload 1: drawn again' err.txt
grep -q '<circle' out.svg || fail "reload 1 did not draw the edit: $(cat out.svg)"

echo 'shape C { SQUARE [ x ) }' >> design.cfdg
wait_for 'reload 2 failed; the last good picture stays' err.txt
grep -q 'design.cfdg:4:22: error' err.txt || fail "no file:line:col for the broken save"
grep -q '<circle' out.svg || fail "the broken save changed the picture"

sed -i '$d' design.cfdg
wait_for 'reload 3: drawn again' err.txt
sed -i 's/TRIANGLE/SQUARE/' part.cfdg   # the imported file is watched too
wait_for 'reload 4: drawn again' err.txt
grep -q '#TRIANGLE"' out.svg && fail "reload 4 did not draw the imported file's edit"
grep -q '<rect' out.svg || fail "reload 4: no square from the imported file"
echo "ok"
