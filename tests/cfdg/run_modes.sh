#!/usr/bin/env bash
# What the modes do with a Context Free design where they run L-systems only: each says so (exit
# 1, a message naming the design), and nothing reads it as an L-system. Also what a batch run
# refuses of --seed for a design, and the run record of a design that fails. The modes that run
# designs are tested beside it (cfdg.*, interactive.design, sweep.design, sandbox.design).
# Usage: run_modes.sh LCJIT DESIGN
set -u
lcjit=$1 design=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
cp "$design" d.cfdg
fail() { echo "FAIL: $*"; echo "--- stderr"; cat err.txt; exit 1; }
expect() {  # expect MESSAGE: exit status 1 and MESSAGE in stderr
  [ "$status" = 1 ] || fail "exit status $status, expected 1"
  grep -qF -- "$1" err.txt || fail "no '$1' in stderr"
  ! grep -q "axiom\|preprocess" err.txt || fail "the design was read as an L-system"
}
# The REPL (its C++ runs in an L-system), given the design on its command line and with :load.
printf ':quit\n' | "$lcjit" repl d.cfdg > out.txt 2> err.txt
grep -qF "d.cfdg: error: a Context Free design is not an L-system, and this mode runs L-systems" err.txt out.txt ||
  fail "the REPL does not refuse the design: $(cat out.txt)"
printf ':load d.cfdg\n:quit\n' | "$lcjit" repl > out.txt 2> err.txt
grep -qF "d.cfdg: error: a Context Free design is not an L-system" err.txt out.txt || fail ":load does not refuse the design: $(cat out.txt)"
# --lab (a window and the REPL).
"$lcjit" --lab -b -out x.png d.cfdg > out.txt 2> err.txt; status=$?
expect "lcjit: --lab runs L-systems; a design runs with --watch (and --sandbox)"
# A string output.
"$lcjit" -b -out x.str d.cfdg > out.txt 2> err.txt; status=$?
expect "lcjit: x.str: not a picture or export lcjit writes"
# --seed N is variation N (a sweep's runs): there is no variation 0, and a run takes one or the other.
"$lcjit" -b --seed 0 -out x.png d.cfdg > out.txt 2> err.txt; status=$?
expect "lcjit: --seed 0: a design's variations are numbered from 1"
"$lcjit" -b --seed 2 --variation A -out x.png d.cfdg > out.txt 2> err.txt; status=$?
expect "lcjit: give --variation or --seed, not both"
# A design that fails has a run record all the same: status error, the error at its place.
printf 'startshape A\nshape A { SQUARE [x oops] }\n' > bad.cfdg
"$lcjit" -b --seed 1 --run-record r.json -out x.png bad.cfdg > out.txt 2> err.txt; status=$?
expect "bad.cfdg:2:"
python3 - <<'PY' || fail "the failed run's record: $(cat r.json)"
import json
r = json.load(open("r.json"))
assert r["status"] == "error" and "bad.cfdg:2:" in r["error"] and r["seed"] == 1 and "measures" not in r, r
PY
echo "ok"
