#!/usr/bin/env bash
# The build precompiles the runtime header for each level into build/prebuilt: a
# first run with an empty cache folder uses it and builds no PCH of its own; one that cannot use
# it (LCJIT_PREBUILT_DIR empty, or a folder others may write to) builds its own, and the string
# is the same. Usage: run_prebuilt.sh LCJIT PREBUILT_DIR MODEL.l (a model whose string holds A(9))
set -u
lcjit=$(realpath "$1") prebuilt=$(realpath "$2") model=$(realpath "$3")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail() { echo "FAIL: $*"; cat err.txt 2>/dev/null; exit 1; }
ls "$prebuilt"/*-O0-*.pch "$prebuilt"/*-O0-*.pch.o "$prebuilt"/*-O1-*.pch "$prebuilt"/*-O2-*.pch >/dev/null ||
  fail "the build made no PCH for some level in $prebuilt"
run() {  # run CACHE LEVEL [ENV...]: derive the model; the string must be right
  local cache=$1 level=$2
  shift 2
  rm -f out.str
  env LCJIT_CACHE_DIR="$cache" "$@" "$lcjit" -b -O"$level" --stats -out out.str "$model" 2>err.txt ||
    fail "lcjit -O$level failed with cache $cache"
  grep -q 'A(9)' out.str || fail "wrong string (-O$level, cache $cache)"
}

# Every level, from an empty cache folder: the prebuilt PCHs, none built.
for level in 0 1 2; do
  run "$work/fresh$level" $level
  grep -q '"pch_cached":true' err.txt || fail "-O$level built a PCH"
  ! ls "$work/fresh$level"/*.pch >/dev/null 2>&1 || fail "-O$level wrote a PCH into the cache folder"
done

# Without the prebuilt folder: the cache folder gets its own.
run "$work/own" 1 LCJIT_PREBUILT_DIR=
grep -q '"pch_cached":false' err.txt || fail "no PCH was built without the prebuilt folder"
ls "$work/own"/*-O1-*.pch >/dev/null 2>&1 || fail "the PCH built is not in the cache folder"

# A prebuilt folder others may write to is not trusted: its code would run.
cp -r "$prebuilt" "$work/open" && chmod 777 "$work/open"
run "$work/open-cache" 0 LCJIT_PREBUILT_DIR="$work/open"
ls "$work/open-cache"/*-O0-*.pch >/dev/null 2>&1 || fail "a PCH from a folder writable by others was used"
echo "ok: prebuilt PCHs"
