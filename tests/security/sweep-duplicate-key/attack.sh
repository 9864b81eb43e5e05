# A sweep file that gives a key twice (a copy-paste slip): YAML says a map's keys are unique, but
# yaml-cpp keeps both, so a parameter given twice made the cross product of both lists, each run
# with two -D for one name (the first wins: half the runs were the same run twice) and two columns
# of that name in results.csv. Every map of the file must refuse a key given twice, with its
# line and column, and nothing may be planned.
source "$(dirname "$0")/lib.sh"
cp "$here/tree.l" "$here/dup.yaml" .
# check WHAT TEXT EXPECTED: the file with TEXT is refused with EXPECTED (after FILE:), unplanned.
check() {
  [ -z "$2" ] || printf '%b' "$2" > dup.yaml
  "$lcjit" sweep plan dup.yaml > out.txt 2> err.txt && fail "$1: planned"
  grep -qxF "$PWD/dup.yaml:$3" err.txt || fail "$1: the error is not 'dup.yaml:$3'"
  [ ! -e dup-runs ] || fail "$1: a plan folder was written"
}
check "a parameter twice" "" "4:3: error: ANGLE is given twice"
check "the model twice" 'model: tree.l\nmodel: tree.l\n' "2:1: error: model is given twice"
check "a range's end twice" 'model: tree.l\nparameters:\n  A: {from: 1, to: 3, from: 2}\n' "3:23: error: from is given twice"
check "seeds' count twice" 'model: tree.l\nseeds:\n  from: 1\n  count: 2\n  count: 3\n' "5:3: error: count is given twice"
check "a key quoted the second time" 'model: tree.l\nparameters:\n  A: [1]\n  "A": [2]\n' "4:3: error: A is given twice"
check "a key the second time by an alias" 'model: tree.l\nparameters:\n  &name A: [1]\n  *name : [2]\n' \
  "4:3: error: A is given twice"
check "a list as a key" 'model: tree.l\nparameters:\n  [A, B]: [1]\n' "3:3: error: a key must be a single value (a name), not a list or a map"
# A second document would be read by nobody: its keys are as lost as a repeated one.
check "a second document" 'model: tree.l\n---\nmodel: tree.l\nseeds: 3\n' "2:1: error: a sweep file is one YAML document; this is a second one"
# The same names in different maps are not repeats.
printf 'model: tree.l\nparameters:\n  from: {from: 1, to: 2}\n  to: [1]\n' > ok.yaml
"$lcjit" sweep plan ok.yaml > out.txt 2> err.txt || fail "a file with no repeated key was refused"
pass "a key given twice refused in every map, with its line and column"
