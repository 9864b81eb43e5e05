#!/usr/bin/env bash
# lcjit ended by a signal while its environmental program computes (it never answers) leaves
# nothing behind: no program, no semaphores, no shared memory, no .to_field/.from_field files.
# Usage: run_env_termination.sh LCJIT FIXTURE TRANSPORT SIGNAL...
# The signals are sent one after the other (INT INT: the second Ctrl-C ends lcjit).
set -u
lcjit=$1 fixture=$2 transport=$3
shift 3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
# A fresh cache: the compile builds its PCH, and LLVM installs its own signal handlers (which
# must hand the signal on to lcjit's).
export LCJIT_CACHE_DIR="$work/cache"
cat >m.l <<'L'
#include <lpfgall.h>
derivation length: 2;
axiom: E1(1) E2(2,3);
L
printf 'executable: %s hang\ncommunication type: %s\n' "$fixture" "$transport" >m.e
# Job control: a background job of a script otherwise starts with SIGINT ignored.
set -m
LCJIT_ENV_FIXTURE_LOG=$work/fixture.log "$lcjit" -b m.l m.e >out.txt 2>&1 &
pid=$!
for _ in $(seq 1 1200); do
  grep -q '^step' fixture.log 2>/dev/null && break
  kill -0 "$pid" 2>/dev/null || break
  sleep 0.1
done
if ! grep -q '^step' fixture.log 2>/dev/null; then
  echo "FAIL: the program never received a step"; cat out.txt; kill -9 "$pid"; exit 1
fi
read -r _ child key < <(grep '^pid' fixture.log)
for sig in "$@"; do
  kill -s "$sig" "$pid" 2>/dev/null
  sleep 0.2
done
wait "$pid"
rc=$?
echo "lcjit ended with status $rc after SIG$*"
cat out.txt
fail=0
if kill -0 "$child" 2>/dev/null; then
  echo "FAIL: the environmental program $child is still running"
  kill -9 "$child"
  fail=1
fi
semkey=$(printf '0x%08x' "$key")
shmkey=$(printf '0x%08x' $((key - 1)))
if ipcs -s | awk '{print $1}' | grep -qx "$semkey"; then
  echo "FAIL: semaphores $semkey left behind"; fail=1
fi
if ipcs -m | awk '{print $1}' | grep -qx "$shmkey"; then
  echo "FAIL: shared memory $shmkey left behind"; fail=1
fi
if ls -A | grep -q '_field'; then
  echo "FAIL: files left behind:"; ls -A | grep '_field'; fail=1
fi
[ "$fail" -eq 0 ] && echo "ok: nothing left after SIG$*"
exit "$fail"
