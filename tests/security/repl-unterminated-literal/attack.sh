# C++ typed at `lcjit repl` with a string or character literal that its line ends inside: the
# error must be about the literal, at the user's line and column (<repl>:LINE:COL), as Clang and
# g++ say it — never about a bracket of the code the REPL puts the input in, on a line the input
# does not have. And the literals must not make the REPL wait for lines that close a bracket in
# them: the lines after them, :quit too, are read as what they are.
source "$(dirname "$0")/lib.sh"
cp "$here/model.l" .
export LCJIT_CACHE_DIR=$PWD/cache
lines=(
  '"unterminated'
  "'x"
  'int twice(int x) {'
  '  return "oops;'
  '}'
  '"{ in a string"'
  "'{'"
  'bonus + 1 // the end of the line is a comment'
  ':quit'
  'bonus + 2'
)
printf '%s\n' "${lines[@]}" | timeout 300 "$lcjit" repl model.l > out.txt 2> err.txt
status=$?
[ $status = 124 ] && fail "the REPL never ended"
[ $status -lt 128 ] || fail "lcjit was ended by signal $((status - 128))"
for want in \
  "<repl>:1:1: error: missing terminating '\"' character" \
  "<repl>:1:1: error: missing terminating ' character" \
  "<repl>:2:10: error: missing terminating '\"' character"; do
  grep -qxF -- "$want" err.txt || fail "no '$want'"
done
! grep -q "never closed\|:89:\|ended inside C++\|__lc_" err.txt || fail "an error names what the user did not type"
[ "$(grep -c "error" err.txt)" = 3 ] || fail "$(grep -c error err.txt) errors, not the 3 literals'"
# bonus is 1 in model.l; what follows :quit is not read.
grep -qx 2 out.txt || fail "the line after the literals with brackets got no answer"
! grep -qx 3 out.txt || fail "a line after :quit was run"
pass "each unterminated literal is said to be one at its line and column, and the REPL read on"
