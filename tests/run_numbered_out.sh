#!/usr/bin/env bash
# -out with a numbered name (Context Free's style): `-out f%02d.obj` writes the axiom
# and every step, f00.obj … f03.obj for 3 steps, each what `-out` alone writes for that many
# steps; a name with no conversion, or two, is one file as before.
# Usage: run_numbered_out.sh LCJIT MODEL.l (tests/models/numbered.l: step K draws K segments)
set -u
lcjit=$(realpath "$1") model=$(realpath "$2")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
fail() { echo "FAIL: $*"; cat err.txt 2>/dev/null; exit 1; }
cp "$model" numbered.l
"$lcjit" -b -out 'f%02d.obj' numbered.l 2>err.txt || fail "lcjit failed"
[ "$(ls f*.obj | tr '\n' ' ')" = "f00.obj f01.obj f02.obj f03.obj " ] || fail "files: $(ls)"
for k in 0 1 2 3; do  # each frame is the whole output of a run of k steps (written under its name)
  mkdir "k$k" && sed "s/derivation length: 3;/derivation length: $k;/" numbered.l > "k$k/numbered.l"
  (cd "k$k" && "$lcjit" -b -out "f0$k.obj" numbered.l 2>../err.txt) || fail "lcjit failed for $k steps"
  cmp -s "k$k/f0$k.obj" "f0$k.obj" || fail "f0$k.obj differs from the output of a $k-step run"
  cmp -s "k$k/f0$k.mtl" "f0$k.mtl" || fail "f0$k.mtl differs from the output of a $k-step run"
done
[ "$(grep -c '^v ' f03.obj)" -gt "$(grep -c '^v ' f01.obj)" ] || fail "the frames do not grow"
"$lcjit" -b -out 'two%d%d.obj' numbered.l 2>err.txt || fail "lcjit failed on two conversions"
[ -f 'two%d%d.obj' ] || fail "a name with two conversions is not one file: $(ls)"
echo ok
