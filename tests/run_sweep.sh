#!/usr/bin/env bash
# lcjit sweep (docs/sweeps.md), one case per ctest test (sweep.CASE):
#   plan     the runs of ranges, lists and seeds in tasks.tsv, worked out by hand; random draws
#            reproducible; a plan is found again, an edited sweep file refused
#   errors   bad sweep files: messages with file:line:column
#   slurm    the job array's script: its array, and one array task run by hand as Slurm would
#            (its chunk of ids, resumed when run again)
#   collect  results.csv from hand-written records: columns, quoting, missing runs
#   run      20 runs (2 STEPS × 10 seeds) through GNU parallel -j2; a rerun runs nothing; equal
#            seeds give equal strings, different ones different strings; a division by zero in
#            model code and a run killed outright are rows with status error and the reason
#   design   a Context Free design's runs: a -D value × 3 seeds (variations 1-3) through GNU
#            parallel, each row's shape count cfdg's for the same variation and definition (cfdg
#            run here); a string output refused
#   xl       an XL model's runs (docs/xl.md): two -D values, --steps 1 among the options, each
#            run's string in XL's names with its angle (by hand)
# Usage: run_sweep.sh LCJIT TESTS_SWEEP_DIR CASE
# No timings are checked: the suite runs on a busy 2-core machine.
set -u
lcjit=$1 src=$2 case=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
cp "$src/branch.l" "$src/killed.l" "$src/garden.cfdg" "$src/bush.rgg" .
fail() { echo "FAIL: $*"; exit 1; }

case $case in
plan)
  cat > grid.yaml <<'EOF'
model: branch.l
parameters:
  STEPS: [3, 6]
  LENGTH: {from: 1, to: 2, step: 0.5}
seeds: {from: 100, count: 2}
EOF
  "$lcjit" sweep plan grid.yaml > out.txt 2> err.txt || { cat err.txt; fail "plan failed"; }
  grep -q "grid-runs: 12 runs planned" out.txt || { cat out.txt; fail "the plan does not say 12 runs"; }
  d=$work/grid-runs
  # The first parameter varies slowest, the seed fastest.
  cat > expected.tsv <<EOF
000001	$d/runs/000001	STEPS=3	LENGTH=1	seed=100
000002	$d/runs/000002	STEPS=3	LENGTH=1	seed=101
000003	$d/runs/000003	STEPS=3	LENGTH=1.5	seed=100
000004	$d/runs/000004	STEPS=3	LENGTH=1.5	seed=101
000005	$d/runs/000005	STEPS=3	LENGTH=2	seed=100
000006	$d/runs/000006	STEPS=3	LENGTH=2	seed=101
000007	$d/runs/000007	STEPS=6	LENGTH=1	seed=100
000008	$d/runs/000008	STEPS=6	LENGTH=1	seed=101
000009	$d/runs/000009	STEPS=6	LENGTH=1.5	seed=100
000010	$d/runs/000010	STEPS=6	LENGTH=1.5	seed=101
000011	$d/runs/000011	STEPS=6	LENGTH=2	seed=100
000012	$d/runs/000012	STEPS=6	LENGTH=2	seed=101
EOF
  diff expected.tsv grid-runs/tasks.tsv || fail "tasks.tsv differs"
  cut -f1 expected.tsv | diff - grid-runs/ids || fail "ids differs"
  python3 - <<'PY' || fail "sweep.json does not record the sweep file"
import json
p = json.load(open("grid-runs/sweep.json"))
assert p["text"] == open("grid.yaml").read(), p["text"]
assert len(p["hash"]) == 64 and p["runs"] == 12 and p["parameters"] == ["STEPS", "LENGTH"], p
PY
  # Planned again from the same file: nothing changes.
  cp grid-runs/tasks.tsv before.tsv
  "$lcjit" sweep plan grid.yaml > out.txt 2> err.txt || { cat err.txt; fail "a second plan failed"; }
  grep -q "12 runs (planned before)" out.txt || { cat out.txt; fail "the second plan did not find the first"; }
  diff before.tsv grid-runs/tasks.tsv || fail "a second plan changed tasks.tsv"
  # An edited sweep file with the same folder is refused.
  sed -i 's/\[3, 6\]/[3, 7]/' grid.yaml
  if "$lcjit" sweep plan grid.yaml > out.txt 2> err.txt; then fail "an edited sweep file was planned over the old plan"; fi
  grep -q "grid-runs was planned from another sweep file .*: use another --out or remove it" err.txt ||
    { cat err.txt; fail "no clear error for an edited sweep file"; }
  "$lcjit" sweep plan grid.yaml --out other > /dev/null 2> err.txt || { cat err.txt; fail "--out other failed"; }
  grep -q "STEPS=7" other/tasks.tsv || fail "--out other does not have the edit"
  # A folder that is not a plan is left alone.
  mkdir busy && touch busy/thesis.tex
  if "$lcjit" sweep plan grid.yaml --out busy 2> err.txt; then fail "planned into a folder of other files"; fi
  grep -q "busy: error: the folder exists and holds no sweep plan" err.txt || { cat err.txt; fail "no clear error for busy/"; }
  # Steps of 0.1 end at the end (0.30000000000000004 is 0.3); no seeds: no seed= word.
  printf 'model: branch.l\nparameters:\n  X: {from: 0, to: 0.3, step: 0.1}\n' > tenths.yaml
  "$lcjit" sweep plan tenths.yaml > /dev/null 2> err.txt || { cat err.txt; fail "tenths failed"; }
  [ "$(cut -f3- tenths-runs/tasks.tsv | tr '\n' ' ')" = "X=0 X=0.1 X=0.2 X=0.3 " ] ||
    { cat tenths-runs/tasks.tsv; fail "the range 0 to 0.3 by 0.1"; }
  n=0
  # Random draws: as many as asked, in the range, the same from the same seed, others from another.
  for seed in 7 7 8; do
    printf 'model: branch.l\nparameters:\n  S: {uniform: [0.5, 1.5], draws: 4, seed: %s}\n' $seed > draws.yaml
    rm -rf draws-runs
    "$lcjit" sweep plan draws.yaml > /dev/null 2> err.txt || { cat err.txt; fail "draws failed"; }
    n=$((n + 1))
    cut -f3 draws-runs/tasks.tsv | sed 's/^S=//' > drawn.$seed.$n
  done
  python3 - drawn.7.1 <<'PY' || fail "the draws are not 4 distinct values in [0.5, 1.5)"
import sys
v = [float(x) for x in open(sys.argv[1])]
assert len(v) == 4 and len(set(v)) == 4 and all(0.5 <= x < 1.5 for x in v), v
PY
  cmp -s drawn.7.1 drawn.7.2 || fail "the same seed drew other values"
  cmp -s drawn.7.1 drawn.8.3 && fail "another seed drew the same values"
  ;;

errors)
  # Each bad file: the message lcjit must give (the file, line:column, what is wrong).
  check() {
    printf '%b' "$2" > bad.yaml
    if "$lcjit" sweep plan bad.yaml > out.txt 2> err.txt; then fail "$1: a bad sweep file was planned"; fi
    grep -qF "$work/bad.yaml:$3" err.txt || { cat err.txt; fail "$1: expected '$3'"; }
    rm -rf bad-runs
  }
  check "yaml syntax" 'model: branch.l\nparameters:\n  A: [1, 2\n' "4:1: error: end of sequence flow not found"
  check "misspelt key" 'model: branch.l\nparamters:\n  A: [1]\n' "2:1: error: unknown key 'paramters' in the sweep file"
  check "no model" 'parameters:\n  A: [1]\n' " error: no model"
  check "missing model" 'model: nope.l\n' "1:8: error: nope.l: no such file"
  check "missing input" 'model: branch.l\nfiles: [branch.v]\n' "2:9: error: branch.v: no such file"
  # A file of no grammar language's (the model's view file, say, given as the model).
  printf 'view: on\n' > notmodel.v
  check "not a model" 'model: notmodel.v\n' "1:8: error: notmodel.v is not a model file (.l, .cfdg, .rgg or .xl)"
  check "range backwards" 'model: branch.l\nparameters:\n  A: {from: 2, to: 1, step: 0.5}\n' \
    "3:29: error: the values of A: the step does not lead from 2 to 1"
  check "not a number" 'model: branch.l\nparameters:\n  A: {from: x, to: 1}\n' "3:13: error: from must be a number, not 'x'"
  check "draws without seed" 'model: branch.l\nparameters:\n  A: {uniform: [0, 1], draws: 3}\n' \
    "3:6: error: the values of A: give the draws' seed"
  check "bad name" 'model: branch.l\nparameters:\n  2A: [1]\n' "3:3: error: '2A' is not a name a -D can define"
  check "empty list" 'model: branch.l\nparameters:\n  A: []\n' "3:6: error: the values of A: the list is empty"
  check "bad seeds" 'model: branch.l\nseeds: {from: 1}\n' "2:8: error: seeds: give from and count"
  check "bad output" 'model: branch.l\noutputs: [string, movie]\n' "2:19: error: unknown output 'movie'"
  check "a key twice" 'model: branch.l\nparameters:\n  A: [1]\n  A: [2]\n' "4:3: error: A is given twice"
  check "seeds past 2^64 - 1" 'model: branch.l\nseeds: {from: 18446744073709551615, count: 2}\n' \
    "2:8: error: seeds: from 18446744073709551615, count 2 passes the largest seed, 18446744073709551615"
  check "negative seed" 'model: branch.l\nseeds: [-1]\n' "2:9: error: each seed must be a whole number from 0 to"
  # (to - from) * step is -1e-400, which rounds to -0: the step's sign, not the product, says it.
  check "step away, tiny" 'model: branch.l\nparameters:\n  A: {from: 0, to: 1e-200, step: -1e-200}\n' \
    "3:34: error: the values of A: the step does not lead from 0 to 1e-200"
  check "draws' range too wide" 'model: branch.l\nparameters:\n  A: {uniform: [-1e308, 1e308], draws: 2, seed: 1}\n' \
    "3:16: error: uniform: the range from -1e+308 to 1e+308 is too wide"
  ;;

slurm)
  printf 'model: branch.l\nparameters:\n  STEPS: [3, 6]\nseeds: 10\noutputs: [string]\n' > s.yaml
  "$lcjit" sweep slurm s.yaml --chunk 3 > out.txt 2> err.txt || { cat err.txt; fail "sweep slurm failed"; }
  script=$work/s-runs/sweep.sbatch
  grep -qF "sbatch '$script'" out.txt || { cat out.txt; fail "no sbatch command printed"; }
  bash -n "$script" || fail "the script is not valid bash"
  # 20 runs in chunks of 3: array tasks 0 to 6, the last with ids 19 and 20.
  grep -qx "#SBATCH --array=0-6" "$script" || { cat "$script"; fail "the array is not 0-6"; }
  grep -qF "'$(readlink -f "$lcjit")' sweep task" "$script" || { cat "$script"; fail "not this lcjit's absolute path"; }
  # Array task 1 as Slurm would run it: ids 000004 to 000006, and no other (each gets a record,
  # whatever the run did).
  SLURM_ARRAY_TASK_ID=1 SLURM_CPUS_PER_TASK=2 bash "$script" > /dev/null 2>&1
  [ "$(cd s-runs/runs && ls */record.json | tr '\n' ' ')" = "000004/record.json 000005/record.json 000006/record.json " ] ||
    { ls -R s-runs/runs; fail "array task 1 did not run ids 4 to 6 alone"; }
  [ "$(tail -n +2 s-runs/joblog.1 | wc -l)" = 3 ] || { cat s-runs/joblog.1; fail "joblog.1 has not 3 runs"; }
  # Submitted again, it runs nothing.
  touch -d '1 minute ago' s-runs/runs/*/record.json
  SLURM_ARRAY_TASK_ID=1 SLURM_CPUS_PER_TASK=2 bash "$script" > /dev/null 2>&1
  [ "$(tail -n +2 s-runs/joblog.1 | wc -l)" = 3 ] || { cat s-runs/joblog.1; fail "the resumed array task ran again"; }
  [ -z "$(find s-runs/runs -name record.json -newermt '30 seconds ago')" ] || fail "the resumed array task rewrote a record"
  ;;

collect)
  printf 'model: branch.l\nparameters:\n  STEPS: [3, 6]\nseeds: 2\n' > c.yaml
  "$lcjit" sweep plan c.yaml > /dev/null 2> err.txt || { cat err.txt; fail "plan failed"; }
  r=c-runs/runs
  mkdir -p $r/000001 $r/000002 $r/000003
  cat > $r/000001/record.json <<'EOF'
{"lcjit": "x", "status": "ok", "steps": 3, "measures": {"modules": {"A": 1, "B": 3}, "segments": 0, "polygons": 0,
 "length": 0, "area": 0, "bbox": [0, 0, 0, 1, 2, 3.5], "reported": {}}, "times_ms": {"derive": 1.5}}
EOF
  cat > $r/000002/record.json <<'EOF'
{"lcjit": "x", "status": "error", "error": "branch.l:18:23: error: \"integer\" division, by zero", "steps": 0}
EOF
  cat > $r/000003/record.json <<'EOF'
{"lcjit": "x", "status": "ok", "steps": 6, "measures": {"modules": {"A": 1, "B": 6, "C": 2}, "segments": 4,
 "polygons": 0, "length": 2.5, "area": 0, "bbox": [-1, 0, -1, 1, 5, 1], "reported": {"height": 1.25}}}
EOF
  "$lcjit" sweep collect c-runs > out.txt 2> err.txt || { cat err.txt; fail "collect failed"; }
  grep -q "results.csv: 4 runs: 2 ok, 1 failed, 1 missing" out.txt || { cat out.txt; fail "collect's summary"; }
  # Columns: the plan's, then the measures in the records' order, a later run's module beside the
  # others; RFC 4180: quotes doubled, a field with a comma or a quote quoted, CRLF line ends.
  printf '%s\r\n' \
    'id,STEPS,seed,status,error,steps,modules.A,modules.B,modules.C,segments,polygons,length,area,bbox.xmin,bbox.ymin,bbox.zmin,bbox.xmax,bbox.ymax,bbox.zmax,reported.height' \
    '000001,3,1,ok,,3,1,3,,0,0,0,0,0,0,0,1,2,3.5,' \
    '000002,3,2,error,"branch.l:18:23: error: ""integer"" division, by zero",0,,,,,,,,,,,,,,' \
    '000003,6,1,ok,,6,1,6,2,4,0,2.5,0,-1,0,-1,1,5,1,1.25' \
    '000004,6,2,missing,,,,,,,,,,,,,,,,' > expected.csv
  diff expected.csv c-runs/results.csv || fail "results.csv differs"
  ;;

run)
  # STEPS B's after STEPS steps whatever the seed (branch.l): modules.B is STEPS, modules.A 1.
  printf 'model: branch.l\nparameters:\n  STEPS: [3, 6]\nseeds: 10\noutputs: [string, mesh]\n' > twenty.yaml
  "$lcjit" sweep run twenty.yaml -j2 > out.txt 2> err.txt || { cat out.txt err.txt; fail "sweep run failed"; }
  grep -q "results.csv: 20 runs: 20 ok, 0 failed, 0 missing" out.txt || { cat out.txt err.txt; fail "not 20 ok runs"; }
  python3 - <<'PY' || fail "results.csv is wrong"
import csv
rows = list(csv.DictReader(open("twenty-runs/results.csv", newline="")))
assert len(rows) == 20, len(rows)
for i, row in enumerate(rows):
    steps = "3" if i < 10 else "6"
    assert row["id"] == "%06d" % (i + 1) and row["STEPS"] == steps and row["seed"] == str(i % 10 + 1), row
    assert row["status"] == "ok" and row["error"] == "" and row["steps"] == steps, row
    assert row["modules.A"] == "1" and row["modules.B"] == steps, row
PY
  [ "$(tail -n +2 twenty-runs/joblog | wc -l)" = 20 ] || fail "the joblog has not 20 runs"
  for d in twenty-runs/runs/*; do [ -s $d/out.str ] && [ -s $d/out.obj ] || fail "$d lacks out.str or out.obj"; done
  # Run again: nothing runs, no record changes.
  touch -d '1 minute ago' twenty-runs/runs/*/record.json
  cp twenty-runs/joblog joblog.before
  "$lcjit" sweep run twenty.yaml -j2 > out.txt 2> err.txt || { cat out.txt err.txt; fail "the second sweep run failed"; }
  diff joblog.before twenty-runs/joblog || fail "the second sweep run ran something"
  [ -z "$(find twenty-runs/runs -name record.json -newermt '30 seconds ago')" ] || fail "the second run rewrote a record"
  # Seeds 1 and 2 of STEPS=6 (ids 11 and 12) differ; a run with seed 1 again (another sweep) gives
  # id 11's string.
  cmp -s twenty-runs/runs/000011/out.str twenty-runs/runs/000012/out.str && fail "seeds 1 and 2 gave the same string"
  # A division by zero (DIVISOR 0) and a run that kills itself are rows with status error.
  printf 'model: branch.l\nparameters:\n  STEPS: 6\n  DIVISOR: [1, 0]\nseeds: [1]\noutputs: [string]\n' > again.yaml
  "$lcjit" sweep run again.yaml -j2 > out.txt 2> err.txt || { cat out.txt err.txt; fail "sweep run again.yaml failed"; }
  cmp twenty-runs/runs/000011/out.str again-runs/runs/000001/out.str || fail "the same seed gave another string"
  printf 'model: killed.l\nseeds: 1\n' > killed.yaml
  "$lcjit" sweep run killed.yaml -j1 > out.txt 2> err.txt || { cat out.txt err.txt; fail "sweep run killed.yaml failed"; }
  python3 - <<'PY' || fail "the failed runs are not rows with their errors"
import csv
rows = list(csv.DictReader(open("again-runs/results.csv", newline="")))
assert [r["DIVISOR"] for r in rows] == ["1", "0"], rows
assert rows[0]["status"] == "ok", rows[0]
assert rows[1]["status"] == "error" and "crashed in step 1: integer division by zero" in rows[1]["error"], rows[1]
rows = list(csv.DictReader(open("killed-runs/results.csv", newline="")))
assert len(rows) == 1 and rows[0]["status"] == "error", rows
assert "lcjit was killed by signal 9 (Killed) and wrote no record" in rows[0]["error"], rows[0]
PY
  ;;

design)
  command -v cfdg >/dev/null || { echo "cfdg (contextfree) is not installed: skipped"; exit 77; }
  printf 'model: garden.cfdg\nparameters:\n  turn: [10, 25]\nseeds: 3\noutputs: [picture]\n' > garden.yaml
  "$lcjit" sweep run garden.yaml -j2 > out.txt 2> err.txt || { cat out.txt err.txt; fail "sweep run failed"; }
  grep -q "results.csv: 6 runs: 6 ok, 0 failed, 0 missing" out.txt || { cat out.txt err.txt; fail "not 6 ok runs"; }
  for turn in 10 25; do for v in 1 2 3; do
    cfdg -q -V -s 500 -v $v -D turn=$turn garden.cfdg ref.svg || fail "cfdg failed"
    echo "$turn $v $(grep -c '<rect\|<circle' ref.svg)"
  done; done > expected.txt
  python3 - <<'PY' || fail "results.csv is not cfdg's shapes"
import csv
rows = list(csv.DictReader(open("garden-runs/results.csv", newline="")))
expected = [line.split() for line in open("expected.txt")]
assert len(rows) == 6 == len(expected), (rows, expected)
for row, (turn, v, shapes) in zip(rows, expected):
    assert row["turn"] == turn and row["seed"] == v and row["status"] == "ok", row
    assert row["variation"] == "ABC"[int(v) - 1] and row["shapes"] == shapes, (row, shapes)
assert len({r["shapes"] for r in rows}) > 1, "every run drew as many shapes"
PY
  for d in garden-runs/runs/*; do [ -s $d/out.png ] || fail "$d lacks out.png"; done
  printf 'model: garden.cfdg\noutputs: [string]\n' > strings.yaml
  "$lcjit" sweep plan strings.yaml > out.txt 2> err.txt && fail "a design's string output was planned"
  grep -q "strings.yaml:2:11: error: a Context Free design has no string" err.txt || { cat err.txt; fail "no error for a design's string"; }
  ;;
xl)
  printf 'model: bush.rgg\nparameters:\n  ANGLE: [20, 45]\noutputs: [string]\noptions: ["--steps", "1"]\n' > bush.yaml
  "$lcjit" sweep run bush.yaml -j2 > out.txt 2> err.txt || { cat out.txt err.txt; fail "sweep run failed"; }
  grep -q "results.csv: 2 runs: 2 ok, 0 failed, 0 missing" out.txt || { cat out.txt err.txt; fail "not 2 ok runs"; }
  for run in 1:20 2:45; do
    id=00000${run%%:*} a=${run#*:}
    [ "$(tr '\n' ' ' < bush-runs/runs/$id/out.str)" = "F(1) [ RU($a) X ] [ RU(-$a) X ] " ] ||
      fail "run $id: $(tr '\n' ' ' < bush-runs/runs/$id/out.str)"
  done
  ;;
*) fail "unknown case $case" ;;
esac
echo "ok: sweep $case"
