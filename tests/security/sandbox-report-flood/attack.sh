# A model floods the pipe the sandboxed lcjit reports on (a gigabyte) to grow the parent lcjit,
# which is outside the sandbox and its limits. The parent must keep only what it understands —
# its peak resident size stays far below what was written — and stop the run.
source "$(dirname "$0")/lib.sh"
need_sandbox
[ -x /usr/bin/time ] || { echo "skipped: no /usr/bin/time"; exit 77; }
cp "$here/flood.l" .
# %M: the largest resident size of lcjit and of each process it waited for (the parent, bubblewrap,
# the sandboxed lcjit: a compile's 200-some MB at most).
timeout 280 /usr/bin/time -f "peak %M" -o peak.txt "$lcjit" --sandbox -b -out o.str flood.l > out.txt 2> err.txt; status=$?
peak_mb=$(( $(grep -o 'peak [0-9]*' peak.txt | cut -d' ' -f2) / 1024 ))
[ $status = 1 ] || fail "exit status $status (peak $peak_mb MB)"
grep -q "flood.l: error: the sandboxed run was stopped before the first step: it wrote more than 64.00 MB to lcjit's report pipe" err.txt ||
  fail "the run was not stopped for its flood"
[ $peak_mb -le 512 ] || fail "the peak resident size was $peak_mb MB"
[ ! -e o.str ] || fail "a string was written"
pass "the flood stopped the run; peak resident size $peak_mb MB"
