#!/usr/bin/env bash
# --profile FILE.json (docs/studio.md): the counts of tests/models/profiled.l, worked out by hand in
# its header, per rule and per step; rules named by kind, predecessor and line; --profile alone, the
# same as a table on stdout; an input file after --profile is refused; an unwritable profile is an
# error.
# Usage: run_profile.sh LCJIT MODEL
set -u
lcjit=$1 model=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$lcjit" -b --profile p.json -out m.obj "$model" > out.txt 2> err.txt || { cat err.txt; echo "FAIL: lcjit failed"; exit 1; }
python3 - <<'PY' || { echo "FAIL: the profile is wrong"; cat p.json; exit 1; }
import json
p = json.load(open("p.json"))
assert p["steps"] == 2, p["steps"]
rules = {(r["kind"], r["line"]): r for r in p["rules"]}
want = {("production", 9): ("A(n)", 2), ("production", 10): ("B", 1),
        ("decomposition", 12): ("C", 2), ("interpretation", 14): ("B", 3)}
assert set(rules) == set(want), sorted(rules)
for key, (name, applied) in want.items():
    r = rules[key]
    assert r["rule"] == name and r["applied"] == applied and r["ran"] == applied, r
    assert r["file"].endswith("profiled.l") and r["ms"] >= 0, r
# hottest first
assert all(a["ms"] >= b["ms"] for a, b in zip(p["rules"], p["rules"][1:]))
def step(n):
    s = [s for s in p["per_step"] if s["step"] == n]
    assert len(s) == 1, p["per_step"]
    return {(p["rules"][r["rule"]]["kind"], p["rules"][r["rule"]]["line"]): r["applied"] for r in s[0]["rules"]}
assert step(1) == {("production", 9): 1, ("decomposition", 12): 1}, step(1)
assert step(2) == {("production", 9): 1, ("production", 10): 1, ("decomposition", 12): 1}, step(2)
PY
# --profile alone: the same counts as a table on stdout (rule, where, applied, ran, ms).
"$lcjit" -b -out m.obj "$model" --profile > table.txt 2> err.txt || { cat err.txt; echo "FAIL: --profile alone failed"; exit 1; }
for want in "production A(n) profiled.l:9 2 2" "production B profiled.l:10 1 1" "decomposition C profiled.l:12 2 2" \
            "interpretation B profiled.l:14 3 3"; do
  awk 'NF == 6 { print $1, $2, $3, $4, $5 }' table.txt | grep -qxF "$want" || { cat table.txt; echo "FAIL: no table line $want"; exit 1; }
done
# A file that follows --profile is its JSON file: never an input's (it would be written over).
cp "$model" m.l
if "$lcjit" -b -out m.obj --profile m.l > out.txt 2> err.txt; then echo "FAIL: --profile m.l was taken"; exit 1; fi
grep -q "\-\-profile m.l: that is an input file" err.txt || { cat err.txt; echo "FAIL: no clear error for --profile m.l"; exit 1; }
cmp -s "$model" m.l || { echo "FAIL: --profile m.l changed m.l"; exit 1; }
if "$lcjit" -b --profile /nonexistent/dir/p.json "$model" > out.txt 2> err.txt; then
  echo "FAIL: an unwritable profile did not fail the run"; exit 1
fi
grep -q "/nonexistent/dir/p.json: error: cannot write the profile" err.txt || { cat err.txt; echo "FAIL: no clear error"; exit 1; }
echo "ok: profile"
