# An lpfg.mak whose compile command asks for a C++ standard Clang does not know (-std=gnu++1x, a
# typo g++ rejects too), or defines a macro whose name no compiler takes (-D1X): one error line
# naming lpfg.mak and the line the flag is written on (or, when it is written nowhere whole, the
# line of the recipe that printed it), exit 1; not Clang's driver error and its notes, with no
# file named.
source "$(dirname "$0")/lib.sh"
command -v make >/dev/null || { echo "skipped: no make"; exit 77; }
cp "$here/model.l" .
export LCJIT_CACHE_DIR=$PWD/cache
# try WHAT EXPECTED LINES…: lpfg.mak made of LINES (a tab starts a recipe line) must give exactly
# one line of error, starting with EXPECTED (a grep pattern), and exit 1.
try() {
  local what=$1 expected=$2
  shift 2
  printf '%s\n' "$@" > lpfg.mak
  timeout 300 "$lcjit" -b -out o.str model.l > out.txt 2> err.txt; local status=$?
  [ $status = 1 ] || fail "$what: exit status $status, not 1"
  [ "$(wc -l < err.txt)" = 1 ] || fail "$what: $(wc -l < err.txt) lines of error, not one"
  grep -q "^$PWD/lpfg\.mak:$expected" err.txt || fail "$what: the error is not 'lpfg.mak:$expected…'"
}
t=$'\t'
try "-std on the recipe line" "4: error: -std=gnu++1x: Clang does not know this C++ standard (it knows .*c++17" \
  "lsys.so: lsys.o" "${t}g++ -shared -o lsys.so lsys.o" "lsys.o: lsys.ii" "${t}g++ -std=gnu++1x -c lsys.ii"
try "-std in a variable" "1: error: -std=gnu++1x: " \
  "FLAGS = -O2 -std=gnu++1x" "lsys.so: lsys.o" "${t}g++ -shared -o lsys.so lsys.o" "lsys.o: lsys.ii" "${t}g++ \$(FLAGS) -c lsys.ii"
try "-std made of variables" "5: error: -std=banana: " \
  "STD = banana" "lsys.so: lsys.o" "${t}g++ -shared -o lsys.so lsys.o" "lsys.o: lsys.ii" "${t}g++ -std=\$(STD) -c lsys.ii"
try "-D1X" "4: error: -D1X=2: a macro's name is an identifier" \
  "lsys.so: lsys.o" "${t}g++ -shared -o lsys.so lsys.o" "lsys.o: lsys.ii" "${t}g++ -D1X=2 -c lsys.ii"
try "-D with no name" "4: error: -D=2: no macro name" \
  "lsys.so: lsys.o" "${t}g++ -shared -o lsys.so lsys.o" "lsys.o: lsys.ii" "${t}g++ -D=2 -c lsys.ii"
pass "a standard Clang does not know and a bad macro name: one line naming lpfg.mak and its line"
