#!/usr/bin/env bash
# XL models (GroIMP's .rgg, docs/xl.md) run by lcjit, checked eight ways:
#   cross NAME STEPS  NAME.rgg after --steps STEPS draws what NAME.l, the same L-system written by
#                     hand in L+C, draws: the same turtle commands (-dtf) and the same segments (OBJ)
#   string NAME STEPS the string after STEPS steps is NAME.expected (derived by hand); NAME.l
#                     when there is no NAME.rgg (--steps on an L+C model); what the model printed
#                     is NAME.stdout, when there is one; NAME.options holds more options for lcjit;
#                     NAME.DATASET.csv is the dataset DATASET's table it wrote (DATASET.csv)
#   profile NAME STEPS --profile's table has each line of NAME.profile (the rules in XL's words and
#                     names, as the user wrote their patterns) and no L+C production nor a name
#                     of the translation's
#   segments NAME [STEPS] the segments drawn after STEPS steps (0: the axiom) are NAME.segments
#                     (derived by hand)
#   colours NAME      the segments drawn from the axiom have the colours NAME.colours names
#                     (the quick reference's colour table)
#   error NAME        lcjit fails with exit status 1 and each line of NAME.err is in its stderr
#                     (NAME.options: more options for lcjit)
#   repl NAME STEPS   `lcjit repl --steps STEPS NAME.rgg`: :step 2 derives the tutorial's tree two
#                     steps (25 modules, by hand: tree_string.expected), :string shows them in XL's
#                     names, and C++ typed at the prompt runs in the model (k * 2 is 6)
#   watch NAME STEPS  --watch: a saved edit of NAME.rgg (RU(30) made RU(20)) is drawn again (as OBJ:
#                     no pictures needed); a broken one (its first `==>` made `==`, line 5 column 9
#                     in tree.rgg) is an error there, and the last good model stays
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
    extra=()
    [ ! -f "$name.options" ] || read -r -a extra <"$name.options"
    "$lcjit" -b --steps "$steps" "${extra[@]}" -out out.str "$model" >printed || fail "lcjit exited with $?"
    diff -u "$name.expected" out.str || fail "the string differs from $name.expected"
    [ ! -f "$name.stdout" ] || diff -u "$name.stdout" printed || fail "what it printed differs from $name.stdout"
    for want in "$name".*.csv; do  # NAME.DATASET.csv: the table the model wrote to DATASET.csv
      [ -e "$want" ] || continue
      diff -u "$want" "${want#"$name".}" || fail "${want#"$name".} differs from $want"
    done
    echo "ok: $name" ;;
  profile)
    "$lcjit" -b --steps "$steps" --profile - "$name.rgg" >profile.txt || fail "lcjit exited with $?"
    cat profile.txt
    while IFS= read -r want || [ -n "$want" ]; do
      [ -z "$want" ] || grep -qF -- "$want" profile.txt || fail "the profile lacks: $want"
    done <"$name.profile"
    ! grep -q "production\|__" profile.txt || fail "the profile names L+C's productions or the translation's names"
    echo "ok: $name's profile in XL's words" ;;
  segments)
    "$lcjit" -b --steps "$steps" -out out.obj "$name.rgg" || fail "lcjit exited with $?"
    python3 "$dir/segments.py" out.obj "$name.segments" ;;
  colours)
    "$lcjit" -b -out out.obj "$name.rgg" || fail "lcjit exited with $?"
    python3 "$dir/colours.py" out.obj "$name.colours" ;;
  repl)
    printf ':step 2\n:string --count 3\nint k = 3;\nk * 2\n' | "$lcjit" repl --steps "$steps" "$name.rgg" >out.txt 2>&1 ||
      fail "lcjit repl exited with $?: $(cat out.txt)"
    cat out.txt
    grep -qx "step 2 of $steps: 25 modules" out.txt || fail "no step 2 with 25 modules"
    grep -qx " 1  \[" out.txt || fail "module 1 is not XL's ["
    grep -qx "6" out.txt || fail "the C++ k * 2 did not give 6"
    echo "ok: $name.rgg in the REPL" ;;
  error)
    extra=()
    [ ! -f "$name.options" ] || read -r -a extra <"$name.options"
    "$lcjit" -b "${extra[@]}" -out out.str "$name.rgg" >stdout 2>stderr
    rc=$?
    cat stderr
    [ "$rc" -eq 1 ] || fail "expected exit status 1, got $rc"
    while IFS= read -r want || [ -n "$want" ]; do
      [ -z "$want" ] || grep -qF -- "$want" stderr || fail "stderr lacks: $want"
    done <"$name.err"
    echo "ok: $name fails as expected" ;;
  watch)
    "$lcjit" --watch --steps "$steps" -out w.obj "$name.rgg" >out.txt 2>err.txt &
    pid=$!
    trap 'kill $pid 2>/dev/null; rm -rf "$work"' EXIT
    for _ in $(seq 1 2400); do [ -s w.obj ] && break; sleep 0.05; done
    [ -s w.obj ] || fail "no first drawing: $(cat err.txt)"
    cp w.obj first.obj
    sed 's/RU(30)/RU(20)/' "$name.rgg" >edited && mv edited "$name.rgg"
    for _ in $(seq 1 2400); do grep -q "reload 1 " err.txt && break; sleep 0.05; done
    grep -qF "reload 1 ($name.rgg): " err.txt || fail "no reload after the save: $(cat err.txt)"
    ! cmp -s first.obj w.obj || fail "the drawing after the edit is the first one (OBJ)"
    sed 's/==>/==/' "$name.rgg" >broken && mv broken "$name.rgg"
    for _ in $(seq 1 2400); do grep -q "reload 2 " err.txt && break; sleep 0.05; done
    grep -qF "$name.rgg:5:9: error: expected '==>' after the rule's left side" err.txt ||
      fail "no error at the broken rule: $(cat err.txt)"
    grep -qF "reload 2 ($name.rgg) failed; the last good model stays" err.txt || fail "the broken edit: $(cat err.txt)"
    kill -0 $pid 2>/dev/null || fail "lcjit --watch ended after the broken edit"
    echo "ok: $name.rgg under --watch" ;;
  *) fail "unknown kind $kind" ;;
esac
