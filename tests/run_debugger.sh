#!/usr/bin/env bash
# lcjit --debugger under gdb (docs/faults.md): a breakpoint at a line of the .l file is hit in
# model code (on its third pass: step 3, tests/debugger/twice.l), the frame is named there, and
# the production's locals read as the rule made them (n = 3, twice = 6). Also: the same run
# without --debugger gives gdb no model code to stop in (the breakpoint stays pending).
# Usage: run_debugger.sh LCJIT DIR
set -u
lcjit=$1 dir=$2
command -v gdb >/dev/null || { echo "gdb is missing (setup.sh installs it)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$dir"/twice.l "$work/"
cd "$work"
debug() {  # debug LCJIT-ARGS…: gdb's output of a run stopped at twice.l:9 on its third pass
  timeout 300 gdb -nx -batch -ex "set breakpoint pending on" -ex "break twice.l:9" -ex "ignore 1 2" -ex run \
    -ex "print n" -ex "print twice" -ex kill --args "$lcjit" -b "$@" twice.l 2>&1
}
out=$(debug --debugger)
fail() { echo "FAIL: $*"; echo "--- gdb:"; echo "$out"; exit 1; }
grep -q "hit Breakpoint 1, .* at \./twice\.l:9" <<<"$out" || fail "the breakpoint at twice.l:9 was not hit in model code"
grep -q '^\$1 = 3$' <<<"$out" || fail "n is not 3"
grep -q '^\$2 = 6$' <<<"$out" || fail "twice is not 6"
out=$(debug)
grep -q "hit Breakpoint 1" <<<"$out" && fail "without --debugger gdb stopped in model code"
grep -q "exited normally" <<<"$out" || fail "without --debugger the run did not end normally"
echo ok
