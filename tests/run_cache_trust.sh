#!/usr/bin/env bash
# The disk cache holds code lcjit loads and runs, so a cache folder is used only when it is the
# user's alone: made 0700 when missing; one that is writable by others, a symbolic
# link or (checked when run as root) another user's is refused with a warning naming it, and the
# run compiles into a private folder instead, which is gone when it ends.
# Usage: run_cache_trust.sh LCJIT MODEL.l (a model whose string holds A(9))
set -u
# The cache folder's own PCHs are what this tests: not the build's prebuilt ones.
export LCJIT_PREBUILT_DIR=
lcjit=$(realpath "$1") model=$(realpath "$2")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
mkdir tmp
export TMPDIR="$work/tmp"
fail() { echo "FAIL: $*"; cat err.txt 2>/dev/null; exit 1; }

run() {  # run CACHE: derive the model with LCJIT_CACHE_DIR=CACHE; the string must be right
  rm -f out.str
  LCJIT_CACHE_DIR="$1" "$lcjit" -b -out out.str "$model" 2>err.txt || fail "lcjit failed with cache $1"
  grep -q 'A(9)' out.str || fail "wrong string with cache $1"
}
refused() {  # refused CACHE WHY: warned, nothing written in CACHE, no private folder left behind
  grep -q "warning: the cache folder '$1' $2" err.txt || fail "no warning that '$1' $2"
  [ -z "$(ls -A "$1" 2>/dev/null)" ] || fail "wrote into the refused folder $1: $(ls -A "$1")"
  [ -z "$(ls -A "$TMPDIR")" ] || fail "left a private folder behind: $(ls -A "$TMPDIR")"
}

# A missing folder is made, private, and used.
run "$work/fresh/cache"
[ "$(stat -c %a "$work/fresh/cache")" = 700 ] || fail "the new cache folder is not 0700"
ls "$work/fresh/cache" | grep -q '\.pch$' || fail "the new cache folder was not used"
! grep -q warning err.txt || fail "a warning for a good folder"

# Writable by others.
mkdir shared && chmod 777 shared
run "$work/shared"
refused "$work/shared" "is writable by others"

# A symbolic link, even to a good folder.
mkdir good && ln -s good link
run "$work/link"
refused "$work/link" "is a symbolic link"
[ -z "$(ls -A good)" ] || fail "wrote through the symbolic link"

# Another user's folder (needs root to make one).
if [ "$(id -u)" = 0 ]; then
  mkdir theirs && chown 65534 theirs && chmod 755 theirs
  run "$work/theirs"
  refused "$work/theirs" "belongs to another user (uid 65534)"
fi
echo ok
