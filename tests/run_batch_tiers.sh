#!/usr/bin/env bash
# Batch tiers (issue 16): a batch run without -O starts with -O1 code; once the derivation has run
# --tier-after milliseconds, -O2 compiles in the background, is swapped in between steps and goes
# into the cache; the next run starts with it. The string is the same whichever code made which
# step: lpfg's -O3 string, worked out by hand (one A, so `count` goes up once a step).
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
echo "ok: batch tiers"
