# Memory a sandboxed model holds outside its address space (RLIMIT_AS) and its resident size (the
# guard's --max-memory) must be refused or bounded: files in memory, System V shared memory, the
# sandbox's tmpfs folders, a user namespace of its own to mount another. The machine's shared
# memory is looked at while the model holds what it got.
source "$(dirname "$0")/lib.sh"
need_sandbox
cp "$here/hoard.l" .
shmem_kb() { awk '/^Shmem:/{print $2}' /proc/meminfo; }
before=$(shmem_kb)
timeout 300 "$lcjit" --sandbox --max-memory 300M -b -out o.str hoard.l > out.txt 2> err.txt &
run=$!
keep $run
wait_for 240 grep -q holding out.txt || { kill $run; fail "the model never said what it holds"; }
grown=$(( ($(shmem_kb) - before) / 1024 ))
touch release
wait $run; status=$?
[ $status = 0 ] || fail "exit status $status"
grep -q "^memfd: 0 MB, refused" out.txt || fail "memfd: $(grep memfd out.txt)"
grep -q "^shm: 0 MB, refused" out.txt || fail "System V shared memory: $(grep shm out.txt)"
for f in /dev/shm /tmp; do
  mb=$(grep "^$f/hold:" out.txt | grep -o '[0-9]* MB' | cut -d' ' -f1)
  [ "${mb:-9999}" -le 64 ] || fail "$f: the model held $mb MB (its tmpfs is 64 MB)"
done
grep -q "^unshare(CLONE_NEWUSER): Operation not permitted" out.txt || fail "unshare: $(grep unshare out.txt)"
# The sandbox's two 64 MB tmpfs folders are all it may hold beside its own address space (the
# rest of the machine may move too: a bound, not an equality).
[ $grown -le 300 ] || fail "the machine's shared memory grew by $grown MB while the model held its memory"
pass "memfd and System V memory refused, tmpfs bounded, no user namespace; shared memory grew by $grown MB"
