#!/usr/bin/env bash
# XL models (GroIMP's .rgg, docs/xl.md) run by lcjit, checked four ways:
#   cross NAME STEPS  NAME.rgg after --steps STEPS draws what NAME.l, the same L-system written by
#                     hand in L+C, draws: the same turtle commands (-dtf) and the same segments (OBJ)
#   string NAME STEPS the string after STEPS steps is NAME.expected (derived by hand); NAME.l
#                     when there is no NAME.rgg (--steps on an L+C model)
#   segments NAME     the segments drawn from the axiom are NAME.segments (derived by hand)
#   error NAME        lcjit fails with exit status 1 and each line of NAME.err is in its stderr
# Usage: run_xl.sh LCJIT XL_DIR KIND NAME [STEPS]
lcjit=$1 dir=$2 kind=$3 name=$4 steps=${5:-0}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$dir/$name".* "$work/"
cd "$work" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
case $kind in
  cross)
    "$lcjit" -b -dtf --steps "$steps" -out xl.obj "$name.rgg" || fail "lcjit $name.rgg exited with $?"
    mv "$name.str" xl.dtf
    "$lcjit" -b -dtf -out lc.obj "$name.l" || fail "lcjit $name.l exited with $?"
    mv "$name.str" lc.dtf
    [ "$(grep -c '^F(' lc.dtf)" -gt 1 ] || fail "the L+C reference draws nothing"
    diff -u lc.dtf xl.dtf || fail "the turtle commands differ from $name.l's"
    diff -u <(grep -v '^#\|^mtllib' lc.obj) <(grep -v '^#\|^mtllib' xl.obj) || fail "the segments differ from $name.l's"
    echo "ok: $name.rgg draws as $name.l ($(grep -c '^F(' xl.dtf) F)" ;;
  string)
    model=$name.rgg
    [ -f "$model" ] || model=$name.l
    "$lcjit" -b --steps "$steps" -out out.str "$model" || fail "lcjit exited with $?"
    diff -u "$name.expected" out.str || fail "the string differs from $name.expected"
    echo "ok: $name" ;;
  segments)
    "$lcjit" -b -out out.obj "$name.rgg" || fail "lcjit exited with $?"
    python3 "$dir/segments.py" out.obj "$name.segments" ;;
  error)
    "$lcjit" -b -out out.str "$name.rgg" >stdout 2>stderr
    rc=$?
    cat stderr
    [ "$rc" -eq 1 ] || fail "expected exit status 1, got $rc"
    while IFS= read -r want || [ -n "$want" ]; do
      [ -z "$want" ] || grep -qF -- "$want" stderr || fail "stderr lacks: $want"
    done <"$name.err"
    echo "ok: $name fails as expected" ;;
  *) fail "unknown kind $kind" ;;
esac
