#!/usr/bin/env bash
# --lab without a display (teaching labs): run from another folder, lcjit works in the
# model's folder only (picture, caches), sandboxed where it can be, prints a broken
# model's errors in plain language before the compiler's text, and keeps watching: saving the
# fix draws the picture.
# Usage: run_lab.sh LCJIT MODEL.l
set -u
lcjit=$1 model=$2
work=$(mktemp -d)
trap 'kill $pid 2>/dev/null; rm -rf "$work"' EXIT
mkdir "$work/model" "$work/elsewhere"
cp "$model" "$work/model/plant.l"
sed -i 's/produce/produce Oops(1)/' "$work/model/plant.l"  # an undeclared module
cd "$work/elsewhere"
fail() { echo "FAIL: $*"; cat err.txt; exit 1; }
env -u DISPLAY -u WAYLAND_DISPLAY HOME="$work/home" XDG_CACHE_HOME="$work/home/cache" \
  "$lcjit" --lab ../model/plant.l 2> err.txt > /dev/null &
pid=$!
for _ in $(seq 1 1200); do grep -q "what the compiler said" err.txt && break; sleep 0.1; done
grep -q "^plant.l, line 21: 'Oops' is not a declared module" err.txt || fail "no plain-language error first"
grep -q "/model/plant.l:21:11: error: undeclared module 'Oops'" err.txt || fail "no compiler text after it"
sed -i 's/produce Oops(1)/produce/' "$work/model/plant.l"
for _ in $(seq 1 1200); do [ -f "$work/model/plant.png" ] && break; sleep 0.1; done
[ -f "$work/model/plant.png" ] || fail "no plant.png after the fix"
[ -d "$work/model/.lcjit-cache" ] || fail "no cache in the model's folder"
[ -z "$(ls -A "$work/elsewhere" | grep -v err.txt)" ] || fail "wrote in the working folder: $(ls -A)"
[ ! -e "$work/home" ] || fail "wrote in the home folder: $(find "$work/home")"
# Where bubblewrap works, every run is sandboxed (docs/security.md); elsewhere a warning says not.
if bwrap --unshare-all --ro-bind / / true 2>/dev/null; then
  grep -q "every run is sandboxed" err.txt || fail "--lab did not sandbox the runs"
else
  grep -q "warning: --lab runs without a sandbox" err.txt || fail "no warning that --lab runs without a sandbox"
fi
echo ok
