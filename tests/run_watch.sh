#!/usr/bin/env bash
# --watch in batch mode: one process; every save of the model rewrites -out and logs a
# "reload N" line; a broken save keeps the last good model and its output; -v reports the -O2
# tier swapped in; saving an earlier version again comes from the object cache; a surface the
# view file comes to name is watched from then on.
# Usage: run_watch.sh LCJIT DIR
set -u
lcjit=$1 dir=$2
work=$(mktemp -d)
trap 'kill $pid 2>/dev/null; rm -rf "$work"' EXIT
cp "$dir/grow.l" "$dir/grow.v" "$(dirname "$dir")/../examples/leaf.s" "$work/"
cd "$work"
export LCJIT_CACHE_DIR="$work/cache"
fail() { echo "FAIL: $*"; echo "--- stderr:"; cat err.txt; exit 1; }
wait_for() {  # wait_for PATTERN FILE: up to 60 s (the first run builds PCHs)
  for _ in $(seq 1 600); do grep -q "$1" "$2" 2>/dev/null && return 0; sleep 0.1; done
  fail "no '$1' in $2"
}
"$lcjit" --watch -b -v -out out.str grow.v grow.l 2> err.txt > /dev/null &
pid=$!
wait_for 'watching' err.txt
wait_for 'A(8)' out.str
wait_for 'swapped in' err.txt

sed -i 's/x \* 2/x * 3/' grow.l
wait_for 'reload 1 ' err.txt
grep -q 'reload 1 (grow.l): compiled -O0' err.txt || fail "reload 1 did not compile"
grep -q 'reload 1 (grow.l): .*frontend [0-9.]* set up ahead' err.txt || fail "reload 1's front end was not set up ahead"
grep -q 'A(27)' out.str || fail "reload 1 did not rewrite the output: $(cat out.str)"

echo 'this is not C++' >> grow.l
wait_for 'reload 2 (grow.l) failed; the last good model stays' err.txt
grep -q 'grow.l:16:1: error' err.txt || fail "no file:line:col diagnostic for the broken save"
grep -q 'A(27)' out.str || fail "the broken save changed the output"

sed -i '$d' grow.l                      # back to the x * 3 version: from the object cache
wait_for 'reload 3 ' err.txt
grep -q 'reload 3 (grow.l): -O0 code from the cache' err.txt || fail "reload 3 was compiled again"
grep -q 'A(27)' out.str || fail "reload 3 output: $(cat out.str)"
echo 'surface: leaf.s 1 4 4' >> grow.v  # the view file names a surface: watched after this reload
wait_for 'reload 4 (grow.v): re-read' err.txt
cp leaf.s leaf.tmp && mv leaf.tmp leaf.s
wait_for 'reload 5 (leaf.s): re-read' err.txt
# A save that loops forever in a production, then the fix: the fix's save stops the stuck run
# (no Ctrl-C) and its output is written.
cp grow.l good.l
sed -i 's/total += x;/total += x; std::fclose(std::fopen("looping", "w")); for (volatile int k = 0; k == 0;) {}/' grow.l
for _ in $(seq 1 600); do [ -e looping ] && break; sleep 0.1; done   # compiled, and in its loop
[ -e looping ] || fail "the looping save never reached its loop"
grep -q 'reload 6 ' err.txt && fail "reload 6 ended before the fix was saved"
sed -i 's/x \* 3/x * 5/' good.l && cp good.l grow.l
wait_for 'reload 7 ' err.txt
grep -q 'the run stopped for the change' err.txt || fail "the stuck run was not stopped"
grep -q 'reload 6 (grow.l): .*its run stopped for a newer change' err.txt || fail "reload 6 not reported as stopped"
grep -q 'interrupted' err.txt && fail "the stop was reported as an error"
wait_for 'A(125)' out.str
# A save nested too deep for the compiler's stack (once, it ended the session): an error
# at its line, and the session goes on with the last good model.
printf 'static int deep(int x) { return %sx; }\n' "$(printf '!%.0s' $(seq 1 2500))" >> grow.l
wait_for 'reload 8 (grow.l) failed; the last good model stays' err.txt
grep -q 'grow.l:[0-9]*:[0-9]*: error: this nests more than 1000' err.txt || fail "no error at the deep line"
grep -q 'A(125)' out.str || fail "the deep save changed the output"
# A save whose run crashes: the log says the run failed and that nothing was written (not
# "wrote out.str").
sed -i '$d' grow.l
wait_for 'reload 9 ' err.txt
sed -i 's/total += x;/total += x; { volatile int* p = nullptr; *p = 1; }/' grow.l
wait_for 'reload 10 ' err.txt
grep -q 'reload 10 (grow.l): .*; the run failed after [0-9]* steps, nothing written: out.str is the last good run' err.txt \
  || fail "reload 10's log does not say that the run failed and nothing was written"
grep -q 'reload 10 (grow.l): .*wrote out.str' err.txt && fail "reload 10 claims to have written out.str"
grep -q 'A(125)' out.str || fail "the failed run changed the output"
kill -0 $pid || fail "lcjit --watch exited"
echo ok
