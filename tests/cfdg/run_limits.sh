#!/usr/bin/env bash
# A design that never finishes: --max-memory stops it with a message naming the limit, the shapes
# made so far are drawn and the run fails (status 1); -m (cfdg's shape limit) ends it as cfdg does,
# the same shapes as cfdg's (status 0). Usage: run_limits.sh LCJIT IMAGE_DIFF DESIGNS_DIR
set -u
lcjit=$1 diff=$2 designs=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; cat "$work/err.txt"; exit 1; }
"$lcjit" "$designs/runaway.cfdg" --max-memory 120M -w 40 40 --variation A -out "$work/r.png" 2> "$work/err.txt"
rc=$?
[ "$rc" -eq 1 ] || fail "--max-memory: exit status $rc, expected 1"
grep -q "stopped: lcjit's memory reached .*--max-memory" "$work/err.txt" || fail "no message naming the memory limit"
grep -q "drawing the [0-9]* shapes made so far" "$work/err.txt" || fail "the shapes made were not drawn"
[ -s "$work/r.png" ] || fail "no picture written"
"$lcjit" cfdg -q -m 700 -s 100 -v A "$designs/runaway.cfdg" "$work/m.png" 2> "$work/err.txt" || fail "-m: exit status $?"
if command -v cfdg >/dev/null; then
  cfdg -q -m 700 -s 100 -v A "$designs/runaway.cfdg" "$work/c.png"
  "$diff" "$work/c.png" "$work/m.png" --exact || fail "-m 700: not cfdg's picture"
fi
echo ok
