#!/usr/bin/env bash
# A sweep's Slurm job array end to end on a one-node cluster on this machine (cluster.sh): 40
# runs of examples/sweep/branching.l (2 angles x 20 seeds) written as a job array of 5 array
# tasks (--chunk 8), submitted with sbatch --wait, submitted again (nothing runs twice: each
# task resumes from its joblog), collected; results.csv must have 40 rows, all ok, each with a
# height. Not part of the tests (it installs and starts daemons as root). Prints what it saw.
# Usage: bench/slurm/run.sh [LCJIT]       (default: build/lcjit)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
lcjit=$(readlink -f "${1:-$root/build/lcjit}")
work=$(mktemp -d /tmp/lcjit-slurm-sweep.XXXXXX)
export LCJIT_SLURM=$work/cluster
trap '"$root/bench/slurm/cluster.sh" stop; rm -rf "$work"' EXIT
"$root/bench/slurm/cluster.sh" start
export SLURM_CONF=$LCJIT_SLURM/slurm.conf

cp "$root/examples/sweep/branching.l" "$work/"
cat > "$work/slurm.yaml" <<YAML
model: branching.l
parameters:
  ANGLE: [30, 60]
seeds: 20
outputs: [string]
YAML
"$lcjit" sweep slurm "$work/slurm.yaml" --chunk 8 --out "$work/runs"
start=$(date +%s.%N)
sbatch --wait "$work/runs/sweep.sbatch"
end=$(date +%s.%N)
records=$(ls "$work"/runs/runs/*/record.json | wc -l)
echo "first submission: $records records in $(echo "$end - $start" | bc) s"
before=$(cat "$work"/runs/joblog.* | wc -l)
sbatch --wait "$work/runs/sweep.sbatch"
after=$(cat "$work"/runs/joblog.* | wc -l)
[ "$before" = "$after" ] || { echo "FAIL: the second submission ran again ($before -> $after joblog lines)"; exit 1; }
echo "second submission: nothing ran again ($after joblog lines)"
"$lcjit" sweep collect "$work/runs"
python3 - "$work/runs/results.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 40, f"{len(rows)} rows"
assert all(r["status"] == "ok" for r in rows), [r["status"] for r in rows]
assert all(float(r["reported.height"]) > 0 for r in rows)
for angle in ("30", "60"):
    h = [float(r["reported.height"]) for r in rows if r["ANGLE"] == angle]
    print(f"ANGLE {angle}: {len(h)} runs, mean height {sum(h) / len(h):.3f}")
print("ok: 40 rows, all ok")
PY
