#!/usr/bin/env bash
# A model's preprocessed text is kept in the cache folder and used while the files it was made
# from are unchanged (a run from the cache skips Clang's preprocessor). An edit of the
# model or of a header it includes is seen at once; the same file name in another folder is its
# own model.
# Usage: run_kept_preprocess.sh LCJIT
set -u
lcjit=$(realpath "$1")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export LCJIT_CACHE_DIR="$work/cache"
fail() { echo "FAIL: $*"; cat err.txt 2>/dev/null; exit 1; }
string() {  # string: derive m.l here; print the final string
  "$lcjit" -b -out out.str m.l 2>err.txt || fail "lcjit failed in $PWD"
  tr -d '\n' <out.str
}
mkdir -p "$work/a" "$work/b" && cd "$work/a"
printf '#define N 3\n' >part.h
printf '#include <lpfgall.h>\n#include "part.h"\nmodule A(int);\nderivation length: 0;\naxiom: A(N);\n' >m.l
# Files changed within a timestamp step (20 ms) before a run are not trusted to show their next
# change, so that run may keep nothing; files older than that are kept.
[ "$(string)" = 'A(3)' ] || fail "first run: $(cat out.str)"
sleep 0.1
[ "$(string)" = 'A(3)' ] || fail "second run: $(cat out.str)"
ls "$LCJIT_CACHE_DIR"/preprocessed/* >/dev/null 2>&1 || fail "no preprocessed text was kept"
[ "$(string)" = 'A(3)' ] || fail "third run (kept text): $(cat out.str)"
grep -q '^// F .*part\.h$' "$LCJIT_CACHE_DIR"/preprocessed/* || fail "the kept text does not list part.h"
# The included header changes to the same size, its modification time set back to what it was:
# the status-change time still moves.
printf '#define N 4\n' >part.h.new
touch -r part.h part.h.new
mv part.h.new part.h
[ "$(string)" = 'A(4)' ] || fail "the edited header was not seen: $(cat out.str)"
printf '#define N 42\n' >part.h
[ "$(string)" = 'A(42)' ] || fail "the edited header was not seen: $(cat out.str)"
# The model changes, the header not.
printf '#include <lpfgall.h>\n#include "part.h"\nmodule A(int);\nderivation length: 0;\naxiom: A(N) A(N + 1);\n' >m.l
[ "$(string)" = 'A(42)A(43)' ] || fail "the edited model was not seen: $(cat out.str)"
# A header found through CPLUS_INCLUDE_PATH: the text kept with one value is not used with another.
mkdir -p "$work/inc1" "$work/inc2"
printf '#define M 11\n' >"$work/inc1/extra.h"
printf '#define M 22\n' >"$work/inc2/extra.h"
printf '#include <lpfgall.h>\n#include <extra.h>\nmodule A(int);\nderivation length: 0;\naxiom: A(M);\n' >m.l
sleep 0.1
[ "$(CPLUS_INCLUDE_PATH="$work/inc1" string)" = 'A(11)' ] || fail "CPLUS_INCLUDE_PATH=inc1: $(cat out.str)"
[ "$(CPLUS_INCLUDE_PATH="$work/inc1" string)" = 'A(11)' ] || fail "CPLUS_INCLUDE_PATH=inc1 again: $(cat out.str)"
[ "$(CPLUS_INCLUDE_PATH="$work/inc2" string)" = 'A(22)' ] || fail "CPLUS_INCLUDE_PATH=inc2 got inc1's text: $(cat out.str)"
# Another folder, the same file names, other contents.
cd "$work/b"
printf '#define N 7\n' >part.h
printf '#include <lpfgall.h>\n#include "part.h"\nmodule A(int);\nderivation length: 0;\naxiom: A(N);\n' >m.l
[ "$(string)" = 'A(7)' ] || fail "another folder's m.l got the first one's text: $(cat out.str)"
echo "ok: kept preprocessed text"
