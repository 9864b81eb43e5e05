#!/usr/bin/env bash
# -D NAME=VALUE, --seed N and --run-record FILE (docs/sweeps.md) on tests/overrides/m.l, whose
# comment says what it does. Usage: run_overrides.sh LCJIT DIR CASE. Records are read with
# python3's json; every expected value is worked out from the model by hand.
set -u
lcjit=$1 dir=$2 case=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$dir"/m.l "$dir"/m.vset "$work"/
cd "$work"
fail() { echo "FAIL: $*"; cat err.txt 2>/dev/null; exit 1; }
field() { python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); print(eval(sys.argv[2], {"r": r}))' "$@"; }
# lpfg's ran(1) after sran(5): X = (0x5DEECE66D * 5 + 0xB) mod 2^48, divided by 2^48.
lpfg_draw=$(python3 -c 'print(((0x5DEECE66D * 5 + 0xB) % 2**48) / 2**48)')
case $case in
  record)  # a plain run: what it was run with, and what it made
    "$lcjit" -b --run-record r.json m.vset m.l 2> err.txt || fail "the run failed"
    [ "$(field r.json 'r["status"], r["steps"], r["overrides"], r["seed"]')" = "('ok', 3, {}, None)" ] || fail "$(cat r.json)"
    [ "$(field r.json 'r["measures"]["modules"]')" = "{'A': 1, 'F': 3}" ] || fail "modules: $(cat r.json)"
    # Three F(1) up the y axis: three segments, length 3, the box from the origin to (0,3,0).
    [ "$(field r.json 'r["measures"]["segments"], r["measures"]["length"], r["measures"]["bbox"]')" = \
      "(3, 3.0, [0.0, 0.0, 0.0, 0.0, 3.0, 0.0])" ] || fail "geometry: $(cat r.json)"
    [ "$(field r.json 'r["measures"]["reported"]')" = "{'angle': 30.0, 'draw': $lpfg_draw, 'width': 2.0}" ] ||
      fail "reported: $(cat r.json)"
    [ "$(field r.json 'sorted(r["inputs"])')" = "['m.l', 'm.vset']" ] || fail "inputs: $(cat r.json)"
    # Each input's BLAKE3 (64 hex digits): another when the file changes.
    [ "$(field r.json 'all(len(h) == 64 and int(h, 16) >= 0 for h in r["inputs"].values())')" = True ] || fail "hashes"
    echo "// changed" >> m.l
    "$lcjit" -b --run-record r2.json m.vset m.l 2> err.txt || fail "the second run failed"
    [ "$(field r2.json 'r["inputs"]["m.l"]')" != "$(field r.json 'r["inputs"]["m.l"]')" ] || fail "the same hash"
    [ "$(field r2.json 'r["inputs"]["m.vset"]')" = "$(field r.json 'r["inputs"]["m.vset"]')" ] || fail "the .vset's hash" ;;
  define)  # the model's #defines (one over two lines) and a .vset value
    "$lcjit" -b -D STEPS=5 -D ANGLE=45 -D WIDTH=7 --run-record r.json m.vset m.l 2> err.txt || fail "the run failed"
    [ "$(field r.json 'r["steps"], r["measures"]["modules"]["F"], r["measures"]["reported"]["angle"], r["measures"]["reported"]["width"]')" = \
      "(5, 5, 45.0, 7.0)" ] || fail "$(cat r.json)"
    [ "$(field r.json 'r["overrides"]')" = "{'STEPS': '5', 'ANGLE': '45', 'WIDTH': '7'}" ] || fail "$(cat r.json)"
    # Lines keep their numbers: an overridden value that does not compile is reported where it is used.
    "$lcjit" -b -D ANGLE=oops m.vset m.l 2> err.txt && fail "ANGLE=oops compiled"
    grep -q "^m.l:15:[0-9]*: error: use of undeclared identifier 'oops'" err.txt || fail "not at line 15" ;;
  unknown)  # names that are not the model's, a macro with arguments, a .vset value that is no number
    "$lcjit" -b -D NOPE=1 --run-record r.json m.vset m.l 2> err.txt; [ $? = 1 ] || fail "exit status"
    grep -qxF "error: -D NOPE: the model has no #define NOPE and no .vset or .tset value NOPE; it has #define ANGLE, STEPS; .vset and .tset values WIDTH" err.txt ||
      fail "the message"
    [ "$(field r.json 'r["status"]')" = error ] && field r.json 'r["error"]' | grep -q "no #define NOPE" || fail "the record: $(cat r.json)"
    "$lcjit" -b -D TWICE=3 m.vset m.l 2> err.txt && fail "TWICE=3 ran"
    grep -qxF "error: -D TWICE: the model's TWICE is a macro with arguments; -D sets a value" err.txt || fail "TWICE"
    "$lcjit" -b -D WIDTH=wide m.vset m.l 2> err.txt && fail "WIDTH=wide ran"
    grep -qxF "error: -D WIDTH=wide: the .vset value WIDTH is a number" err.txt || fail "WIDTH"
    "$lcjit" -b -D STEPS m.l 2> err.txt && fail "-D STEPS ran"
    grep -qF -- "-D STEPS: give NAME=VALUE" err.txt || fail "no NAME=VALUE" ;;
  timeline)  # a .tset timeline's range: GROW's linear function at 2.5 is 0.5 over 0..5, 0.25 over 0..10
    cp "$dir"/m.tset .
    "$lcjit" -b --run-record r.json m.vset m.tset m.l 2> err.txt || fail "the run failed"
    # (within the sampling of the curve: lpfg tabulates it, 20 samples)
    [ "$(field r.json 'abs(r["measures"]["reported"]["grow"] - 0.5) < 1e-3')" = True ] || fail "$(cat r.json)"
    "$lcjit" -b -D GROW=0:10 --run-record r.json m.vset m.tset m.l 2> err.txt || fail "the run with -D failed"
    [ "$(field r.json 'abs(r["measures"]["reported"]["grow"] - 0.25) < 1e-3')" = True ] || fail "$(cat r.json)"
    "$lcjit" -b -D GROW=10 m.vset m.tset m.l 2> err.txt && fail "GROW=10 ran"
    grep -qxF "error: -D GROW=10: the .tset timeline GROW takes START:END" err.txt || fail "GROW=10" ;;
  crash)  # a run that faults is a record with its error
    "$lcjit" -b -D ANGLE=0 --run-record r.json m.vset m.l 2> err.txt; [ $? = 1 ] || fail "exit status"
    [ "$(field r.json 'r["status"], r["steps"], "measures" in r')" = "('error', 3, False)" ] || fail "$(cat r.json)"
    field r.json 'r["error"]' | grep -qF "m.l:16:" || fail "the error: $(cat r.json)"
    field r.json 'r["error"]' | grep -qF "error: End crashed after step 3: segmentation fault" || fail "the error: $(cat r.json)" ;;
  seed)  # --seed N: the same N the same numbers, another N others; none: lpfg's
    for s in 1 2 1; do "$lcjit" -b --seed $s --run-record r$s.json m.vset m.l 2> err.txt || fail "seed $s"; cp r$s.json again$s.json; done
    "$lcjit" -b --seed 1 --run-record again.json m.vset m.l 2> err.txt || fail "seed 1 again"
    one=$(field r1.json 'r["measures"]["reported"]["draw"]') two=$(field r2.json 'r["measures"]["reported"]["draw"]')
    [ "$one" = "$(field again.json 'r["measures"]["reported"]["draw"]')" ] || fail "seed 1 twice: $one"
    [ "$one" != "$two" ] || fail "seeds 1 and 2 drew the same $one"
    [ "$one" != "$lpfg_draw" ] && [ "$two" != "$lpfg_draw" ] || fail "a seed drew lpfg's number"
    [ "$(field r1.json 'r["seed"]')" = 1 ] || fail "the record's seed" ;;
  concurrent)  # a sweep's runs at once share one cache: 12 processes, 3 values, an empty cache
    export LCJIT_CACHE_DIR="$work/cache"
    pids=()
    for i in $(seq 1 12); do
      steps=$((2 + i % 3))
      "$lcjit" -b -D STEPS=$steps -out s$i.str m.vset m.l 2> err$i.txt &
      pids+=($!)
    done
    for i in $(seq 1 12); do wait ${pids[$((i - 1))]} || { cat err$i.txt; fail "run $i failed"; }; done
    for i in $(seq 1 12); do
      steps=$((2 + i % 3))
      [ "$(grep -c '^F(1)$' s$i.str)" = $steps ] && grep -qx "A($steps)" s$i.str || fail "run $i's string: $(cat s$i.str)"
    done
    ! ls -a cache/objects | grep -q '\.lcjit-new-' || fail "a temporary file was left in the cache"
    # What they left is whole: runs from it give the same strings.
    for steps in 2 3 4; do
      "$lcjit" -b -D STEPS=$steps -out again.str m.vset m.l 2> err.txt || fail "from the cache, STEPS=$steps"
      [ "$(grep -c '^F(1)$' again.str)" = $steps ] || fail "from the cache, STEPS=$steps: $(cat again.str)"
    done
    grep -q "damaged\|would not load" err*.txt && fail "a damaged cache entry" ;;
  *) echo "unknown case $case"; exit 1 ;;
esac
echo "ok: $case"
