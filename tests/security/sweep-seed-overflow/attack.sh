# Seeds past the end: seeds {from: F, count: N} computed F + i in a signed 64-bit integer without
# a check (undefined behaviour in C++), so from 9223372036854775807 the runs got negative seeds;
# and --seed took -1 as 2^64 - 1, a number past 2^64 - 1 as 2^64 - 1, 010 as 8. A seed is a
# whole number from 0 to 2^64 - 1 in both: past that, or negative, is an error (in the sweep file,
# at its line and column), never a seed wrapped around.
source "$(dirname "$0")/lib.sh"
cp "$here/tree.l" "$here/seeds.yaml" .
largest=18446744073709551615
# refused TEXT EXPECTED: a sweep file with TEXT is refused with EXPECTED (after FILE:), unplanned.
refused() {
  printf '%b' "$1" > bad.yaml
  "$lcjit" sweep plan bad.yaml > out.txt 2> err.txt && fail "planned: $1 ($(cat bad-runs/tasks.tsv))"
  grep -qxF "$PWD/bad.yaml:$2" err.txt || fail "$1: the error is not 'bad.yaml:$2'"
  [ ! -e bad-runs ] || fail "$1: a plan folder was written"
}
"$lcjit" sweep plan seeds.yaml > out.txt 2> err.txt && fail "seeds past $largest were planned: $(cut -f3 seeds-runs/tasks.tsv)"
grep -qxF "$PWD/seeds.yaml:2:8: error: seeds: from $largest, count 2 passes the largest seed, $largest" err.txt ||
  fail "no error at the seeds' line and column"
refused 'model: tree.l\nseeds: {from: 9223372036854775807, count: 1000000}\n' "2:43: error: count must be 1 to 999999"
refused 'model: tree.l\nseeds: [1, -1]\n' \
  "2:12: error: each seed must be a whole number from 0 to $largest (as --seed takes it), not '-1'"
refused 'model: tree.l\nseeds: [18446744073709551616]\n' \
  "2:9: error: each seed must be a whole number from 0 to $largest (as --seed takes it), not '18446744073709551616'"
refused 'model: tree.l\nparameters:\n  A: {uniform: [0, 1], draws: 2, seed: -1}\n' \
  "3:40: error: seed must be a whole number from 0 to $largest (as --seed takes it), not '-1'"
# Up to the largest seed, every seed is what was asked.
printf 'model: tree.l\nseeds: {from: 18446744073709551614, count: 2}\n' > last.yaml
"$lcjit" sweep plan last.yaml > out.txt 2> err.txt || fail "the two largest seeds were refused"
[ "$(cut -f3 last-runs/tasks.tsv | tr '\n' ' ')" = "seed=18446744073709551614 seed=$largest " ] ||
  fail "the two largest seeds are planned as $(cut -f3 last-runs/tasks.tsv)"
# --seed takes what a sweep file's seeds are, and the run's record says the seed it ran.
for bad in -1 18446744073709551616 0x10 +5; do
  "$lcjit" -b --seed "$bad" --run-record r.json tree.l > out.txt 2> err.txt && fail "--seed $bad was taken"
  grep -qF -- "--seed: N must be a whole number from 0 to $largest, not '$bad'" err.txt || fail "--seed $bad: no clear error"
done
for seed in $largest:$largest 010:10; do
  "$lcjit" -b --seed "${seed%:*}" --run-record r.json tree.l > out.txt 2> err.txt || fail "--seed ${seed%:*} was refused"
  python3 -c 'import json, sys; assert json.load(open("r.json"))["seed"] == int(sys.argv[1])' "${seed#*:}" ||
    fail "--seed ${seed%:*} ran as seed $(grep -o '"seed": [^,]*' r.json), not ${seed#*:}"
done
pass "seeds past $largest and negative ones refused, in the sweep file and by --seed"
