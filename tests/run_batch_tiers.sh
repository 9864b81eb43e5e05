#!/usr/bin/env bash
# Batch tiers: a batch run without -O starts with -O1 code; once the derivation has run
# --tier-after milliseconds, -O2 compiles in the background, is swapped in between steps and goes
# into the cache; the next run starts with it. The string is the same whichever code made which
# step: lpfg's -O3 string, worked out by hand (one A, so `count` goes up once a step). A model of
# thousands of productions starts at -O0 instead of -O1.
# Usage: run_batch_tiers.sh LCJIT MODEL.l
set -u
lcjit=$(realpath "$1") model=$(realpath "$2")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
export LCJIT_CACHE_DIR="$work/cache"
fail() { echo "FAIL: $*"; cat err.txt 2>/dev/null; exit 1; }
expected='B(1)B(2)B(3)B(4)B(5)B(6)A(6)'
check() {  # check WHAT: the string is right
  [ "$(tr -d ' \n' <out.str)" = "$expected" ] || fail "$1: the string is $(cat out.str), not $expected"
}

# -O given: that level only, no second tier.
"$lcjit" -b -v -O1 --tier-after 0 -out out.str "$model" 2>err.txt || fail "the -O1 run failed"
check "-O1"
! grep -q -- '-O2' err.txt || fail "-O1 was asked for, yet -O2 came in"

# No -O, a derivation past --tier-after: -O2 compiles in the background, for this run or the cache.
"$lcjit" -b -v --tier-after 0 -out out.str "$model" 2>err.txt || fail "the first tiered run failed"
check "first tiered run"
grep -q 'compiling -O2 in the background' err.txt || fail "no -O2 build started"
ls "$LCJIT_CACHE_DIR"/objects/*-O2.o >/dev/null 2>&1 || fail "the -O2 build is not in the cache"

# The next run starts with the cached -O2 code and compiles nothing in the background.
"$lcjit" -b -v --tier-after 0 -out out.str "$model" 2>err.txt || fail "the second tiered run failed"
check "second tiered run"
grep -q -- '-O2 code of an earlier run from the cache' err.txt || fail "the cached -O2 code was not taken"
! grep -q 'compiling -O2 in the background' err.txt || fail "compiled -O2 again"
# A model of more than 1000 productions (Session::kLargeModelProductions) starts at -O0 unless -O
# says otherwise: -O1's passes would cost more than they save. lpfg tries A's productions in
# order; the one for n == 1 applies.
big() {  # big N: N one-line productions
  printf '#include <lpfgall.h>\nmodule A(int);\nderivation length: 1;\naxiom: A(1);\n'
  for ((k = 0; k < $1; ++k)); do echo "A(n) : { if (n == $k) produce A(n+1); }"; done
}
big 1001 >big.l
big 1000 >edge.l
"$lcjit" -b -v -out out.str big.l 2>err.txt || fail "the 1001-production model failed"
[ "$(tr -d ' \n' <out.str)" = 'A(2)' ] || fail "1001 productions: the string is $(cat out.str), not A(2)"
grep -q 'compiled -O0' err.txt || fail "1001 productions were not compiled at -O0 first"
"$lcjit" -b -v -out out.str edge.l 2>err.txt || fail "the 1000-production model failed"
grep -q 'compiled -O1' err.txt || fail "1000 productions were not compiled at -O1"
"$lcjit" -b -v -O1 -out out.str big.l 2>err.txt || fail "the 1001-production model failed at -O1"
grep -q 'compiled -O1' err.txt || fail "-O1 was asked for, and not given"
echo "ok: batch tiers"
