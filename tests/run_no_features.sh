#!/usr/bin/env bash
# A build without pictures (LCJIT_WITH_RENDERING=OFF) or without the window (LCJIT_WITH_WINDOW=OFF):
# asked for what it lacks, it says so by name and fails; everything else works as in a full build.
# Usage: run_no_features.sh LCJIT EXAMPLES_DIR pictures|window
set -u
lcjit=$(realpath "$1") examples=$(realpath "$2") what=$3
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
cp "$examples"/tree.l "$examples"/tree.v "$examples"/tree.mat "$here/models/quoted_include.l" .
export LCJIT_CACHE_DIR="$work/cache"
fail() { echo "FAIL: $*"; cat err.txt 2>/dev/null; exit 1; }

case "$what" in
pictures)
  # A picture: status 1, and the message names the file and the missing feature.
  "$lcjit" -b -out t.png tree.l tree.v tree.mat 2>err.txt && fail "-out t.png succeeded"
  grep -q "t.png: this lcjit was built without pictures (LCJIT_WITH_RENDERING=OFF)" err.txt || fail "no message naming the feature"
  [ ! -e t.png ] || fail "t.png written"
  # A video is made of pictures: the same, before anything is derived.
  "$lcjit" -b -out t.mp4 tree.l tree.v tree.mat 2>err.txt && fail "-out t.mp4 succeeded"
  grep -q "t.mp4: this lcjit was built without pictures (LCJIT_WITH_RENDERING=OFF), which a video is made of" err.txt ||
    fail "no message naming the feature for a video"
  [ ! -e t.mp4 ] || fail "t.mp4 written"
  # The exports and strings are there.
  "$lcjit" -b -out t.obj tree.l tree.v tree.mat 2>err.txt || fail "-out t.obj failed"
  grep -q '^f ' t.obj || fail "t.obj has no faces"
  "$lcjit" -b -out t.svg tree.l tree.v tree.mat 2>err.txt || fail "-out t.svg failed"
  grep -q '<svg' t.svg || fail "t.svg is not SVG"
  "$lcjit" -b -out q.str quoted_include.l 2>err.txt || fail "-out q.str failed"
  grep -q 'A(9)' q.str || fail "q.str lacks A(9)"
  # With no model, the built-in example is shown as its string.
  "$lcjit" 2>err.txt || fail "the built-in example failed"
  [ -s tree.str ] || fail "no tree.str from the built-in example"
  grep -q '^Internode(' tree.str || fail "tree.str holds no Internode module (examples/tree.l)"
  ;;
window)
  # No window even with a display: the model is written beside it, with a message saying why.
  DISPLAY=:0 "$lcjit" quoted_include.l 2>err.txt || fail "lcjit model.l failed"
  grep -q "this build has no window; writing quoted_include" err.txt || fail "no message naming the missing window"
  ls quoted_include.* | grep -qv '\.l$' || fail "nothing written beside the model"
  # The REPL's :view says the same and the REPL goes on.
  printf ':view\n:run\n:string\n' | "$lcjit" repl quoted_include.l >out.txt 2>err.txt
  cat out.txt >>err.txt
  grep -q "built without the window (LCJIT_WITH_WINDOW=OFF)" err.txt || fail ":view gave no message naming the feature"
  grep -q 'A(9)' err.txt || fail "the REPL did not go on after :view"
  ;;
*) echo "usage: $0 LCJIT EXAMPLES_DIR pictures|window"; exit 2 ;;
esac
echo ok
