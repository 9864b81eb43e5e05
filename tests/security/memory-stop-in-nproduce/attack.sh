# A production grows the string without end (nproduce in a loop) until --max-memory stops it. The
# stop must be named at the statement that was running, the call of B in `nproduce B(1);` (line 9,
# column 14: docs/faults.md names a call at its start), at every optimisation level: not at the
# module's declaration (line 5), where lcjit's generated code for emitting a B is placed, with a
# column of that generated text past the end of the line.
source "$(dirname "$0")/lib.sh"
cp "$here/nproduce.l" .
export LCJIT_CACHE_DIR=$PWD/cache
for level in 0 1 2; do
  # The address space bound keeps a run that is never stopped from taking the machine's memory.
  prlimit --as=4000000000 timeout 300 "$lcjit" -O $level -b --max-memory 300M -out o.str nproduce.l > out.txt 2> err.txt
  status=$?
  [ $status = 1 ] || fail "-O$level: exit $status, expected 1"
  head -1 err.txt | grep -q "^nproduce\.l:9:14: error: production A was stopped in step 1: .*--max-memory 300\.00 MB" ||
    fail "-O$level: the stop is not named at the nproduce (nproduce.l:9:14)"
done
pass "the stop is named at nproduce.l:9:14 at -O0, -O1 and -O2"
