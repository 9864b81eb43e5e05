#!/usr/bin/env bash
# Faults in model code end a batch run with a message and exit status 1, never with a signal
# (docs/faults.md). Usage: run_faults.sh LCJIT DIR CASE, with CASE one of
#   crash       a null dereference in step 3
#   time_limit  an endless loop stopped by --time-limit
#   ctrl_c      an endless loop interrupted by SIGINT (the first Ctrl-C)
#   max_modules runaway growth stopped by --max-modules
set -u
lcjit=$1 dir=$2 case=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
expect() {  # expect STATUS MESSAGE [REST]: the exit status and a line of stderr (with REST after MESSAGE)
  [ "$status" = "$1" ] || { echo "FAIL: exit status $status, expected $1"; cat err.txt; exit 1; }
  grep -qF -- "$2" err.txt || { echo "FAIL: no '$2' in stderr:"; cat err.txt; exit 1; }
  [ $# -lt 3 ] || grep -F -- "$2" err.txt | grep -qF -- "$3" || { echo "FAIL: no '$2…$3' in stderr:"; cat err.txt; exit 1; }
}
case $case in
  crash)
    "$lcjit" -b -out out.str "$dir/crash.l" 2> err.txt; status=$?
    # The statement that crashed (line 8), at its '=' (column 24); the caret under it.
    expect 1 "crash.l:8:24: error: production A(n) crashed in step 3: segmentation fault (null pointer dereference)"
    grep -qxF "    8 |   if (n == 2) *nowhere = 1;" err.txt || { echo "FAIL: no source line"; cat err.txt; exit 1; }
    grep -qxF "      |                        ^" err.txt || { echo "FAIL: no caret under column 24"; cat err.txt; exit 1; }
    [ ! -e out.str ] || { echo "FAIL: a string was written after the fault"; exit 1; } ;;
  time_limit)
    "$lcjit" -b --time-limit 0.2 -out out.str "$dir/loop.l" > out.txt 2> err.txt; status=$?
    # Stopped somewhere in the loop's line (9), the production's own line being 6.
    expect 1 "loop.l:9:" ": error: production A(n) was stopped in step 2: it ran longer than the time limit of 0.2 s (--time-limit)" ;;
  ctrl_c)
    # Line-buffered, so that "looping" shows while the model loops.
    stdbuf -oL "$lcjit" -b -out out.str "$dir/loop.l" > out.txt 2> err.txt &
    pid=$!
    for _ in $(seq 1 2400); do grep -q looping out.txt && break; sleep 0.05; done
    grep -q looping out.txt || { echo "FAIL: the model never reached its loop"; cat err.txt; kill $pid; exit 1; }
    sleep 0.2
    kill -INT $pid
    wait $pid; status=$?
    expect 1 "loop.l:9:" ": error: production A(n) was interrupted in step 2" ;;
  max_modules)
    "$lcjit" -b --max-modules 1000 -out out.str "$dir/grow.l" 2> err.txt; status=$?
    expect 1 "grow.l: error: the derivation was stopped in step 10: the string reached 1024 modules (limit --max-modules 1000)" ;;
  *) echo "unknown case $case"; exit 1 ;;
esac
echo "ok: $case"
