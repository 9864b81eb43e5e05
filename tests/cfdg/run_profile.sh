#!/usr/bin/env bash
# --profile for a Context Free design (docs/cfdg.md): the rule counts of profile/profiled.cfdg,
# worked out by hand in its header, at three variations; each rule named by its shape, its weight
# among the shape's rules and its file:line (an imported file's own); the shapes finished by kind
# agree with the counts (and, where cfdg is installed, the SQUAREs with cfdg's own picture); the
# table on stdout (lcjit's options and `lcjit cfdg`), the JSON of --profile FILE.json; the picture
# is the same counted or not, and nothing is printed without --profile.
# Usage: run_profile.sh LCJIT DIR (DIR: tests/cfdg/profile)
set -u
lcjit=$1 dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$dir"/*.cfdg "$work/"
cd "$work"
fail() { echo "FAIL: $*"; cat err.txt 2>/dev/null; exit 1; }
for v in A BCD XYZZY; do
  "$lcjit" profiled.cfdg --variation $v -w 300 300 -out counted.png --profile p.json > out.txt 2> err.txt || fail "--profile p.json failed"
  [ -s out.txt ] && fail "--profile FILE.json printed on stdout: $(cat out.txt)"
  squares=""
  if command -v cfdg >/dev/null; then
    cfdg -q -V -s 300 -v $v profiled.cfdg ref.svg || fail "cfdg failed"
    squares=$(grep -c '<rect' ref.svg)
  fi
  python3 - "$squares" <<'PY' || { cat p.json; fail "variation $v: the profile is wrong"; }
import json, sys
p = json.load(open("p.json"))
rules = {(r["kind"], r["rule"]): r for r in p["rules"]}
want = {("rule", "Main"): ("profiled.cfdg", 13), ("rule", "Arm"): ("profiled.cfdg", 9),
        ("rule", "Leaf 1"): ("profiled_leaf.cfdg", 3), ("rule", "Leaf 3"): ("profiled_leaf.cfdg", 4),
        ("path", "Petal"): ("profiled.cfdg", 17)}
got = set(rules)
# a Leaf rule that never ran is left out (possible, if unlikely, for 20 draws)
assert got <= set(want) and {("rule", "Main"), ("rule", "Arm"), ("path", "Petal")} <= got, sorted(got)
for key, r in rules.items():
    assert (r["file"], r["line"]) == want[key], (key, r)
    assert r["applied"] == r["ran"] and r["ms"] >= 0, r
applied = lambda key: rules[key]["applied"] if key in rules else 0
assert applied(("rule", "Main")) == 1 and applied(("path", "Petal")) == 1
assert applied(("rule", "Arm")) == 20, rules[("rule", "Arm")]
leaf1, leaf3 = applied(("rule", "Leaf 1")), applied(("rule", "Leaf 3"))
assert leaf1 + leaf3 == 20, (leaf1, leaf3)
assert p["expanded"] == 41, p["expanded"]
finished = p["finished"]
assert finished.get("SQUARE", 0) == leaf1, (finished, leaf1)
assert finished.get("CIRCLE", 0) == leaf3 and finished.get("TRIANGLE", 0) == leaf3, (finished, leaf3)
assert finished.get("path Petal") == 1, finished
assert set(finished) <= {"SQUARE", "CIRCLE", "TRIANGLE", "path Petal"}, finished
if sys.argv[1]:
    assert int(sys.argv[1]) == leaf1, ("cfdg's SQUAREs", sys.argv[1], "Leaf 1 ran", leaf1)
# hottest first
assert all(a["ms"] >= b["ms"] for a, b in zip(p["rules"], p["rules"][1:]))
open("leaf1", "w").write(str(leaf1))
PY
  # The table: one line per rule (rule NAME, where, applied, ran, ms), the same counts.
  "$lcjit" profiled.cfdg --variation $v -w 300 300 -out plain.png > plain.txt 2> err.txt || fail "the run without --profile failed"
  [ -s plain.txt ] && fail "a run without --profile printed: $(cat plain.txt)"
  cmp -s counted.png plain.png || fail "variation $v: the picture counted is not the picture uncounted"
  for run in lcjit cfdg; do
    if [ $run = lcjit ]; then
      "$lcjit" profiled.cfdg --variation $v -w 300 300 -out t.png --profile > table.txt 2> err.txt || fail "--profile failed"
    else
      "$lcjit" cfdg --profile -s 300 -v $v profiled.cfdg t.png > table.txt 2> err.txt || fail "lcjit cfdg --profile failed"
    fi
    awk '$1 == "rule" && $2 == "Arm" { print $3, $4, $5 }' table.txt | grep -qx "profiled.cfdg:9 20 20" ||
      fail "$run: no 'rule Arm profiled.cfdg:9 20 20' line: $(cat table.txt)"
    awk '$1 == "rule" && $2 == "Leaf" && $3 == "1" { print $4, $5 }' table.txt | grep -qx "profiled_leaf.cfdg:3 $(cat leaf1)" ||
      fail "$run: Leaf 1's line is not profiled_leaf.cfdg:3 $(cat leaf1): $(cat table.txt)"
    grep -qx "41 rules expanded; finished: .*[:,] $(cat leaf1) SQUARE.*, 1 path Petal" table.txt ||
      fail "$run: no line of the rules expanded and the shapes finished: $(cat table.txt)"
  done
done
# An unwritable profile is an error.
if "$lcjit" profiled.cfdg --variation A -out x.png --profile /nonexistent/dir/p.json > out.txt 2> err.txt; then
  fail "an unwritable profile did not fail the run"
fi
grep -q "/nonexistent/dir/p.json: error: cannot write the profile" err.txt || fail "no clear error"
echo "ok: cfdg.profile"
