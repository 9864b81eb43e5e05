#!/usr/bin/env bash
# A damaged cache entry is never loaded: it is deleted, the model compiled again and
# the right string written, with a note naming the file; the run after that is quiet. Damage as
# the finding measured it: code bytes flipped (lcjit died of SIGSEGV), a file cut in half, its
# second half zeroed, the ELF header changed; and, checksum made to match, an object that will not
# load (compiled again too). The -O0 PCH's support code likewise.
# Usage: run_cache_damage.sh LCJIT MODEL.l DAMAGE.py
set -u
# The cache folder's own PCHs are what this tests: not the build's prebuilt ones.
export LCJIT_PREBUILT_DIR=
lcjit=$(realpath "$1") model=$(realpath "$2") damage=$(realpath "$3")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
cp "$model" model.l
export LCJIT_CACHE_DIR="$work/cache"
fail() { echo "FAIL: $*"; cat err.txt 2>/dev/null; exit 1; }

derive() {  # derive LEVEL: the string must be the first run's, with no error
  rm -f out.str
  "$lcjit" -b -O "$1" -out out.str model.l 2>err.txt; s=$?
  [ $s -eq 0 ] || fail "exit status $s at -O$1"
  cmp -s out.str good.str || fail "a different string at -O$1"
}

"$lcjit" -b -O 1 -out good.str model.l 2>err.txt || fail "the first run failed"
for mode in flip_code trunc_half zero_tail elf_hdr "elf_hdr --keep-checksum" "trunc_half --keep-checksum"; do
  "$lcjit" -b -O 1 -out /dev/null model.l 2>/dev/null  # the object is in the cache
  python3 "$damage" cache obj $mode || fail "could not damage ($mode)"
  derive 1
  case "$mode" in
    *keep-checksum) why="it would not load" ;;
    *) why="it is damaged (its checksum does not match)" ;;
  esac
  grep -q "note: the cached compiled code $work/cache/objects/.*\.o was not used: $why.*; it was deleted and the model compiled again" err.txt \
    || fail "no note naming the object ($mode)"
  derive 1
  ! grep -q note err.txt || fail "a note on the run after the repair ($mode)"
done

# The support code of the -O0 PCH.
derive 0
for mode in flip_code trunc_half; do
  python3 "$damage" cache sup $mode || fail "could not damage the support code ($mode)"
  rm -rf cache/objects  # the model's object is not what is tested here
  derive 0
  grep -q "note: the cached compiled code $work/cache/.*\.pch\.o was not used: it is damaged" err.txt \
    || fail "no note naming the support code ($mode)"
  derive 0
  ! grep -q note err.txt || fail "a note on the run after the support code's repair ($mode)"
done
echo ok
