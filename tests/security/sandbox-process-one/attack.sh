# A model reads the environment of every process the sandbox shows (the user's secrets live in
# variables: tokens, agents' sockets) and tries to take them over with ptrace; after attaching it
# ends as if nothing happened. The sandbox must show no process holding the user's environment,
# let the model attach to none, and the run must still end.
source "$(dirname "$0")/lib.sh"
need_sandbox
cp "$here/peek.l" .
secret=attack-secret-$RANDOM$RANDOM
# Without the sandbox the model does read its own environment: the check below means something.
ATTACK_SECRET=$secret "$lcjit" -b -out o.str peek.l > out.txt 2> err.txt || fail "the plain run failed"
grep -q "$secret" out.txt || fail "the model does not see the secret even without the sandbox"
rm -rf o.str .lcjit-cache
touch take-over
ATTACK_SECRET=$secret timeout 120 "$lcjit" --sandbox -b -out o.str peek.l > out.txt 2> err.txt; status=$?
[ $status = 124 ] && fail "the sandboxed run never ended"
[ $status = 0 ] || fail "exit status $status"
grep -q "processes seen: [1-9]" out.txt || fail "the model saw no process at all (is /proc there?)"
! grep -q "$secret" out.txt err.txt || fail "the secret reached the model"
! grep -q "^attached to" out.txt || fail "the model attached to another process: $(grep '^attached' out.txt)"
! grep -q "^opened .* for writing" out.txt || fail "the model may write another process's memory"
pass "the model saw $(grep -o 'processes seen: [0-9]*' out.txt), none with the user's environment, and took none over"
