#!/usr/bin/env bash
# A cache folder that cannot be written (a full disk; here a file-size limit
# of 2 MB, which fails the ~9 MB PCH's write as ENOSPC would) costs only the cache: the run gives
# the right string with one warning, and leaves no temporary file; in --watch, the -O2 tier's
# failed PCH write does not end the session, and an edit is still compiled and written.
# Usage: run_cache_full.sh LCJIT
set -u
# The cache folder's own PCHs are what this tests: not the build's prebuilt ones.
export LCJIT_PREBUILT_DIR=
lcjit=$(realpath "$1")
work=$(mktemp -d)
trap 'kill $pid 2>/dev/null; rm -rf "$work"' EXIT
pid=
cd "$work"
printf '#include <lpfgall.h>\nmodule A(int);\nderivation length: 2;\naxiom: A(1);\nA(n): { produce A(n * 3); }\n' > model.l
fail() { echo "FAIL: $*"; echo "--- stderr:"; cat err.txt 2>/dev/null; exit 1; }
wait_for() {  # wait_for PATTERN FILE: up to 60 s
  for _ in $(seq 1 600); do grep -q "$1" "$2" 2>/dev/null && return 0; sleep 0.1; done
  fail "no '$1' in $2"
}
LCJIT_CACHE_DIR="$work/roomy" "$lcjit" -b -out good.str model.l 2>err.txt || fail "the run with room failed"

trap '' XFSZ  # a write past the limit fails (EFBIG) instead of ending the process
ulimit -f 2048
export LCJIT_CACHE_DIR="$work/full"
"$lcjit" -b -out out.str model.l 2>err.txt || fail "exit status $? with a full cache"
cmp -s out.str good.str || fail "a different string with a full cache"
[ "$(grep -c 'warning: the precompiled runtime header cannot be written to the cache folder' err.txt)" = 1 ] \
  || fail "not exactly one warning"
! ls -a full | grep -q 'tmp' || fail "temporary files left: $(ls -a full)"

# --watch: the -O0 model, then the -O2 tier in the background (its PCH cannot be written either).
"$lcjit" --watch -b -v -out w.str model.l 2>err.txt >/dev/null &
pid=$!
wait_for 'watching' err.txt
wait_for 'A(9)' w.str
wait_for 'swapped in' err.txt
sed -i 's/n \* 3/n * 5/' model.l
wait_for 'reload 1 ' err.txt
wait_for 'A(25)' w.str
kill -0 $pid || fail "lcjit --watch ended"
echo ok
