#!/usr/bin/env bash
# An installed lcjit: `cmake --install` into a scratch prefix puts bin/lcjit and
# share/lcjit/{include,examples,prebuilt} there; the installed program says its version, finds its
# runtime headers and its PCHs beside itself (a first run with an empty cache folder builds no
# PCH), and gives the build tree's string from another folder. With bubblewrap, it does so with
# the source and build trees hidden: it needs nothing from the checkout.
# Usage: run_install.sh LCJIT BUILD_DIR SOURCE_DIR
set -u
lcjit=$(realpath "$1") build=$(realpath "$2") source=$(realpath "$3")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; cat "$work/err.txt" 2>/dev/null; exit 1; }
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" > "$work/install.txt" 2>&1 || { cat "$work/install.txt"; fail "cmake --install failed"; }
for f in bin/lcjit share/lcjit/include/lpfgall.h share/lcjit/examples/koch.l; do
  [ -e "$prefix/$f" ] || fail "not installed: $f"
done
ls "$prefix"/share/lcjit/prebuilt/lpfgall-O1-*.pch >/dev/null 2>&1 || fail "no -O1 PCH in share/lcjit/prebuilt"
"$prefix/bin/lcjit" --version | grep -qE '^lcjit [0-9]+\.[0-9]+\.[0-9]+ \(LLVM and Clang 19\.' ||
  fail "--version: $("$prefix/bin/lcjit" --version)"

mkdir "$work/elsewhere" && cd "$work/elsewhere" || exit 1
cp "$source/examples/koch.l" .
"$lcjit" -b -out build.str koch.l 2>"$work/err.txt" || fail "the build tree's lcjit failed"
LCJIT_CACHE_DIR=$work/cache "$prefix/bin/lcjit" -b -v -out installed.str koch.l 2>"$work/err.txt" ||
  fail "the installed lcjit failed"
grep -q "(cached PCH)" "$work/err.txt" || fail "the installed lcjit built a PCH: its prebuilt ones were not used"
cmp -s build.str installed.str || fail "the installed lcjit's string differs from the build tree's"

if bwrap --bind / / --tmpfs "$source" --tmpfs "$build" true 2>/dev/null; then
  bwrap --bind / / --tmpfs "$source" --tmpfs "$build" --setenv LCJIT_CACHE_DIR "$work/cache2" \
    "$prefix/bin/lcjit" -b -out hidden.str koch.l 2>"$work/err.txt" || fail "with the checkout hidden, lcjit failed"
  cmp -s build.str hidden.str || fail "with the checkout hidden, the string differs"
  # The quick start's main job: the built-in example, from the installed examples, and where it went.
  bwrap --bind / / --tmpfs "$source" --tmpfs "$build" --setenv LCJIT_CACHE_DIR "$work/cache2" \
    "$prefix/bin/lcjit" 2>"$work/err.txt" || fail "with the checkout hidden, the built-in example failed"
  grep -q "built-in example $prefix/share/lcjit/examples/tree.l into $work/elsewhere/tree\.\(png\|str\)$" "$work/err.txt" ||
    fail "the built-in example's message does not name the installed model and the file written"
  ls tree.png tree.str 2>/dev/null | grep -q . || fail "the built-in example wrote nothing"
else
  echo "bubblewrap cannot hide folders here: the runs without the checkout are skipped"
fi
echo ok
