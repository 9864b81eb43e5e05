# Shared folders (/tmp and the like: every user writes there, and agents keep their sockets
# there) must never be shown to a sandboxed model: not as its folder, not read-only as an -I
# folder (a read-only bind does not stop connect()), and a socket or a FIFO is no input file.
source "$(dirname "$0")/lib.sh"
need_sandbox
command -v python3 >/dev/null || { echo "skipped: no python3 for the listening socket"; exit 77; }
mkdir -m 1777 shared            # a folder like /tmp: world-writable, sticky
mkdir shared/agent
sock=$PWD/shared/agent/agent.sock
python3 -c 'import socket, sys
s = socket.socket(socket.AF_UNIX); s.bind(sys.argv[1]); s.listen(8)
while True:
    c, _ = s.accept(); c.sendall(b"AGENT-SECRET-4711"); c.close()' "$sock" &
listener=$!
keep $listener
wait_for 60 test -S "$sock" || fail "the socket never appeared"
sed "s|AGENT_SOCKET|$sock|" "$here/agent.l" > agent.l
# Without the sandbox the model does reach the agent: the checks below mean something.
"$lcjit" -b -out o.str agent.l > out.txt 2> err.txt
grep -q "agent said: AGENT-SECRET-4711" out.txt || fail "the model does not reach the socket even without the sandbox"

# The model's folder is the shared folder.
cp agent.l shared/
"$lcjit" --sandbox -b -out o.str shared/agent.l > out.txt 2> err.txt; status=$?
[ $status = 1 ] || fail "a model in a shared folder: exit status $status"
grep -q "the model's folder '$PWD/shared' is a folder every user may write to" err.txt || fail "a model in a shared folder was not refused"

# The real /tmp, if that is where the suite runs: refused as well (by name, whatever its mode).
tmp=$(cd /tmp && pwd -P)
cp agent.l "$tmp/lcjit-security-$$.l"
"$lcjit" --sandbox -b -out "$tmp/lcjit-security-$$.str" "$tmp/lcjit-security-$$.l" > out.txt 2> err.txt; status=$?
rm -f "$tmp/lcjit-security-$$.l" "$tmp/lcjit-security-$$.str"
[ $status = 1 ] || fail "a model in /tmp: exit status $status"
grep -q "the model's folder '$tmp' .*; give the model a folder of its own" err.txt || fail "a model in /tmp was not refused"

# The shared folder as an include folder, read-only.
mkdir m && cp agent.l m/
"$lcjit" --sandbox -b -I "$PWD/shared" -out o.str m/agent.l > out.txt 2> err.txt; status=$?
[ $status = 1 ] || fail "-I a shared folder: exit status $status"
grep -q "the include folder '$PWD/shared' is a folder every user may write to" err.txt || fail "-I a shared folder was not refused"

# The socket, and a FIFO, named as input files.
mkfifo m/plant.map
for input in "$sock" m/plant.map; do
  timeout 120 "$lcjit" --sandbox -b -out o.str "$input" m/agent.l > out.txt 2> err.txt; status=$?
  [ $status = 1 ] || fail "$input as an input: exit status $status"
  grep -q "$input: error: not a regular file" err.txt || fail "$input as an input was not refused"
done
! grep -q "AGENT-SECRET" out.txt || fail "the model reached the agent"
pass "shared folders refused as the model's and as -I, a socket and a FIFO refused as inputs"
