# A model passes --max-memory out of the guard's sight (memory it maps itself) and then sleeps in a
# system call, which the watchdog's signals only wake, and returns. The stop the watchdog asked for
# while End ran must fail End (exit 1, the limit's message), not be dropped when End returns, the
# run "succeeding" with lcjit over its limit.
source "$(dirname "$0")/lib.sh"
cp "$here/asleep.l" .
export LCJIT_CACHE_DIR=$PWD/cache
# The address space bound keeps a model that is never stopped from taking the machine's memory.
prlimit --as=4000000000 timeout 300 "$lcjit" -b --max-memory 300M -out o.str asleep.l > out.txt 2> err.txt
status=$?
[ $status = 124 ] && fail "End was never woken: the limit was not noticed"
[ $status = 1 ] || fail "exit $status, expected 1 (the stop was lost)"
grep -q "error: End was stopped after step 1: lcjit's memory reached .* (limit --max-memory 300\.00 MB)" err.txt ||
  fail "the error does not say that End was stopped by the memory limit"
pass "End, asleep when the limit was passed, failed with the limit's message"
