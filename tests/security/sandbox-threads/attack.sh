# Threads are tasks of the machine, each with a pid: a sandboxed model must not be able to take
# the machine's pids (kernel.pid_max is 32768 on many machines; every fork() elsewhere then
# fails). --max-threads bounds them: its cgroup's pids.max, or RLIMIT_NPROC for a user that is not
# root. Tried at the default (512) and at --max-threads 100.
source "$(dirname "$0")/lib.sh"
need_sandbox
cp "$here/threads.l" .
for limit in default 100; do
  opt=(); [ $limit = default ] || opt=(--max-threads $limit)
  bound=$([ $limit = default ] && echo 512 || echo $limit)
  timeout 280 "$lcjit" --sandbox "${opt[@]}" -b -out o.str threads.l > out.txt 2> err.txt; status=$?
  [ $status = 0 ] || fail "--max-threads $limit: exit status $status"
  made=$(grep -o 'threads made: [0-9]*' out.txt | cut -d' ' -f3)
  [ -n "$made" ] || fail "--max-threads $limit: the model said nothing"
  # The bound counts lcjit's own threads too; as an ordinary user, the user's other tasks as well.
  [ "$made" -lt "$bound" ] || fail "--max-threads $limit: the model made $made threads"
  [ "$made" -ge 10 ] || fail "--max-threads $limit: only $made threads (a model may use some)"
done
pass "threads bounded: $made of 5000 under --max-threads 100"
