# A run that printed a lot before it died: `lcjit sweep task` writes the run's record itself and
# quotes the run's last words from its stderr.txt. It must read only the end of that file: its
# memory must not grow with what the run printed (512 MB here; `sweep run -j N` has N tasks).
source "$(dirname "$0")/lib.sh"
cp "$here/loud.l" "$here/loud.yaml" .
"$lcjit" sweep plan loud.yaml > out.txt 2> err.txt || fail "the plan failed"
/usr/bin/time -f %M -o rss.txt "$lcjit" sweep task loud-runs 000001 > out.txt 2> err.txt; status=$?
[ $status = 1 ] || fail "sweep task's status is $status, not 1 (a failed run)"
size=$(stat -c %s loud-runs/runs/000001/stderr.txt)
[ "$size" -ge $((512 << 20)) ] || fail "the run's stderr.txt is $size bytes, not 512 MB: the attack did not happen"
# Max RSS of the task and of the run it waited for (the larger): a task holding stderr.txt would
# be past its size; half of it leaves the run's compile and lcjit itself room enough.
rss_kb=$(tail -1 rss.txt)
[ "$rss_kb" -lt $((256 << 10)) ] || fail "sweep task's max RSS was $((rss_kb >> 10)) MB for a $((size >> 20)) MB stderr.txt"
python3 - <<'PY' || fail "the record does not quote the last words: $(cat loud-runs/runs/000001/record.json)"
import json
r = json.load(open("loud-runs/runs/000001/record.json"))
assert r["status"] == "error", r
assert r["error"] == "lcjit was killed by signal 9 (Killed) and wrote no record; it said: last words: the model gave up", r
PY
pass "max RSS $((rss_kb >> 10)) MB for a $((size >> 20)) MB stderr.txt; the record quotes its last line"
