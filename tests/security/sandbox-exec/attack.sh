# A sandboxed model that replaces lcjit by another program (execve) would leave the guard behind:
# the sleep it starts never ends, --time-limit or not. The sandbox refuses execve once lcjit runs.
source "$(dirname "$0")/lib.sh"
need_sandbox
cp "$here/replace.l" .
timeout 120 "$lcjit" --sandbox --time-limit 5 -b -out o.str replace.l > out.txt 2> err.txt; status=$?
[ $status = 124 ] && fail "the run never ended: the model replaced lcjit"
grep -q "^execv: Operation not permitted" out.txt || fail "execv was not refused"
[ $status = 0 ] || fail "exit status $status"
pass "execve refused; the run ended"
