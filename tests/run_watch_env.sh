#!/usr/bin/env bash
# --watch with an environmental program: a program that crashes is an error naming the
# .e file and the session goes on; saving a fixed .e restarts the program and the model runs with
# it; when lcjit ends, no program is left running.
# Usage: run_watch_env.sh LCJIT FIXTURE
set -u
lcjit=$1 fixture=$2
work=$(mktemp -d)
trap 'kill $pid 2>/dev/null; rm -rf "$work"' EXIT
cd "$work"
export LCJIT_CACHE_DIR="$work/cache" LCJIT_ENV_FIXTURE_LOG="$work/fixture.log"
fail() { echo "FAIL: $*"; echo "--- stderr:"; cat err.txt; exit 1; }
wait_for() {  # wait_for PATTERN FILE: up to 120 s (the first run builds PCHs)
  for _ in $(seq 1 1200); do grep -q "$1" "$2" 2>/dev/null && return 0; sleep 0.1; done
  fail "no '$1' in $2"
}
cat >m.l <<'L'
#include <lpfgall.h>
derivation length: 2;
axiom: E1(1);
L
# The test program adds one to each value it is sent: two exchanges (before steps 1 and 2).
printf 'executable: %s crash\ncommunication type: files\n' "$fixture" >m.e
"$lcjit" --watch -b -out out.str m.l m.e 2>err.txt >/dev/null &
pid=$!
wait_for 'watching' err.txt
wait_for 'm.e: error: the environmental program .* was killed by signal' err.txt
kill -0 $pid || fail "lcjit --watch ended after the program crashed"

printf 'executable: %s plus1\ncommunication type: files\n' "$fixture" >m.e.new && mv m.e.new m.e
wait_for 'reload 1 (m.e)' err.txt
wait_for 'E1(3)' out.str
kill -0 $pid || fail "lcjit --watch exited"

kill $pid
wait $pid
for child in $(awk '$1 == "pid" {print $2}' fixture.log); do
  kill -0 "$child" 2>/dev/null && fail "program $child outlived lcjit"
done
[ "$(awk '$1 == "pid"' fixture.log | wc -l)" -ge 2 ] || fail "the fixed .e did not start a new program"
ls -A | grep -q '_field' && fail "files left behind: $(ls -A | grep _field)"
echo ok
