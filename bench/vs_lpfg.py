#!/usr/bin/env python3
"""lcjit against the reference lpfg, row by row (docs/performance.md's table): paired runs with hyperfine,
alternating which program goes first from one round to the next, and the ratio of the medians
(lpfg time / lcjit time: above 1, lcjit is faster). Peak memory with /usr/bin/time. The machine's
load average is printed before and after: figures taken beside other work are not comparable.

Needs the reference lpfg (tests/compat/build_reference_lpfg.sh; default prefix /opt/lpfg-ref) and
hyperfine (Debian package). Nothing here is a test; docs/performance.md keeps a table it printed.

Usage: bench/vs_lpfg.py [--lcjit build/lcjit] [--lpfg-prefix /opt/lpfg-ref] [--runs 10] [--rounds 3]
                        [--research DIR] [--rows branching,signal,...] [--json FILE]
Rows: branching signal startup first_run compute_heavy out_str dtf memory compile_20k
  compute_heavy needs --research DIR, the folder of the LPFG-LIGNUM model (inuritdino/LPFG-LIGNUM,
  lpfg-dist); compile_20k is lcjit alone (a generated model of 20 000 productions; no lpfg figure).
Models: bench/models/ (branching.l, signal.l, turtle.l).
"""
import argparse, json, os, shutil, statistics, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = os.path.join(ROOT, "bench", "models")


def productions_20k():
    """A model of 20 000 productions, one per value of A's parameter: what a script generating a
    model writes, and the compile's worst case for functions per model."""
    lines = ["#include <lpfgall.h>", "module A(int);", "derivation length: 1;", "axiom: A(1);"]
    lines += [f"A(n) : {{ if (n == {k}) produce A(n+1); }}" for k in range(20000)]
    return "\n".join(lines) + "\n"


ONE_MODULE = "#include <lpfgall.h>\nderivation length: 1;\nmodule A();\nAxiom: A;\nproduction:\nA: { produce A; }\n"
ROWS = ["branching", "signal", "startup", "first_run", "compute_heavy", "out_str", "dtf", "memory", "compile_20k"]
TARGETS = {"branching": 4, "signal": 4, "startup": 1, "first_run": 8, "compute_heavy": 1, "out_str": 2, "dtf": 2,
           "memory": 1}


def lpfg_env(prefix, tmp):
    env = dict(os.environ, VLABROOT=prefix, VLABBIN=prefix + "/bin", VLABCONFIGDIR=prefix + "/config",
               LPFGPATH=prefix, LPFGRESOURCES=prefix, VLABTMPDIR=tmp, QT_QPA_PLATFORM="offscreen")
    env["PATH"] = prefix + "/bin:" + env["PATH"]
    return env


def load():
    return " ".join(open("/proc/loadavg").read().split()[:3])


class Bench:
    def __init__(self, a, work):
        self.a, self.work = a, work
        self.env = lpfg_env(a.lpfg_prefix, os.path.join(work, "vlabtmp"))
        os.makedirs(self.env["VLABTMPDIR"], exist_ok=True)
        self.cache = os.path.join(work, "lcjit-cache")  # warm rows share it
        self.env["LCJIT_CACHE_DIR"] = self.cache

    def folder(self, name, files):
        """A folder of its own for a row: lpfg writes lsys.so and its outputs where it runs."""
        d = os.path.join(self.work, name)
        os.makedirs(d, exist_ok=True)
        for f in files:
            shutil.copy(f, d)
        return d

    def lpfg_library(self, folder, args):
        """lpfg -c: its compiled lsys.so, which -dll then loads (lpfg's run without its compile)."""
        p = subprocess.run(["lpfg", "-b", "-c", *args], cwd=folder, env=self.env, capture_output=True, text=True)
        so = os.path.join(folder, "lsys.so")
        if not os.path.exists(so):
            sys.exit(f"lpfg -c failed in {folder}:\n{p.stdout}{p.stderr}")
        return so

    def pair(self, folder, lpfg_cmd, lcjit_cmd, prepare=None, runs=None):
        """Median seconds of each command over the rounds, the order swapped each round."""
        times = {"lpfg": [], "lcjit": []}
        runs = runs or self.a.runs
        for r in range(self.a.rounds):
            order = [("lpfg", lpfg_cmd), ("lcjit", lcjit_cmd)]
            if r % 2:
                order.reverse()
            out = os.path.join(self.work, "hyperfine.json")
            cmd = ["hyperfine", "-N", "--warmup", "2", "--runs", str(runs), "--export-json", out, "--style", "none"]
            if prepare:
                cmd += ["--prepare", prepare]
            cmd += [" ".join(c) for _, c in order]
            subprocess.run(cmd, cwd=folder, env=self.env, check=True, stdout=subprocess.DEVNULL)
            for (name, _), res in zip(order, json.load(open(out))["results"]):
                times[name] += res["times"]
        return statistics.median(times["lpfg"]), statistics.median(times["lcjit"])

    def peak_kb(self, folder, cmd, n=3):
        kb = []
        for _ in range(n):
            p = subprocess.run(["/usr/bin/time", "-f", "%M", *cmd], cwd=folder, env=self.env, capture_output=True, text=True)
            kb.append(int(p.stderr.strip().splitlines()[-1]))
        return statistics.median(kb)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lcjit", default=os.path.join(ROOT, "build", "lcjit"))
    ap.add_argument("--lpfg-prefix", default="/opt/lpfg-ref")
    ap.add_argument("--runs", type=int, default=10, help="runs of each command per round")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--research", help="the LPFG-LIGNUM model's folder (compute_heavy)")
    ap.add_argument("--rows", default=",".join(ROWS))
    ap.add_argument("--json", help="also write the figures here")
    a = ap.parse_args()
    if not shutil.which("hyperfine"):
        sys.exit("hyperfine is needed (apt install hyperfine)")
    if not os.path.exists(os.path.join(a.lpfg_prefix, "bin", "lpfg")):
        sys.exit(f"no reference lpfg under {a.lpfg_prefix} (tests/compat/build_reference_lpfg.sh builds one)")
    with tempfile.TemporaryDirectory() as work:
        lcjit = os.path.join(work, "lcjit")
        shutil.copy(os.path.realpath(a.lcjit), lcjit)  # a rebuild meanwhile does not change what is measured
        b = Bench(a, work)
        bench = MODELS
        rows = []
        before = load()

        def add(name, what, lp, lc, unit="s", note=""):
            ratio = lp / lc if lc else float("nan")
            rows.append(dict(row=name, what=what, lpfg=lp, lcjit=lc, unit=unit, ratio=ratio,
                             target=TARGETS.get(name), note=note))
            fmt = (lambda v: f"{v * 1000:.1f} ms") if unit == "s" else (lambda v: f"{v / 1024:.0f} MiB")
            print(f"{name:14} lpfg {fmt(lp):>10}  lcjit {fmt(lc):>10}  ratio {ratio:5.2f}  {note}", flush=True)

        for row in a.rows.split(","):
            if row in ("branching", "signal"):
                d = b.folder(row, [os.path.join(bench, row + ".l")])
                so = b.lpfg_library(d, [row + ".l"])
                lp, lc = b.pair(d, ["lpfg", "-b", "-dll", so, row + ".l"], [lcjit, "-b", row + ".l"])
                add(row, f"derivation of {row}.l, whole process, no output", lp, lc)
            elif row == "startup":
                d = b.folder(row, [])
                open(os.path.join(d, "one.l"), "w").write(ONE_MODULE)
                so = b.lpfg_library(d, ["one.l"])
                lp, lc = b.pair(d, ["lpfg", "-b", "-dll", so, "one.l"], [lcjit, "-b", "one.l"])
                add(row, "a one-module model, lcjit's code from its cache, lpfg's from -dll", lp, lc)
            elif row == "first_run":
                d = b.folder(row, [os.path.join(ROOT, "examples", "koch.l")])
                fresh = os.path.join(work, "fresh-cache")
                lc_cmd = ["env", f"LCJIT_CACHE_DIR={fresh}", lcjit, "-b", "koch.l"]
                lp, lc = b.pair(d, ["lpfg", "-b", "koch.l"], lc_cmd, prepare=f"rm -rf {fresh}", runs=max(3, a.runs // 2))
                add(row, "examples/koch.l with an empty cache (lcjit) / with its compile (lpfg)", lp, lc)
            elif row == "compute_heavy":
                if not a.research:
                    print("compute_heavy: skipped (no --research folder)")
                    continue
                d = os.path.join(work, row)
                shutil.copytree(a.research, d)
                args = ["lignum.l", "view.v", "material.mat"]
                so = b.lpfg_library(d, args)
                # lcjit's default: -O1, then -O2 from the background build or the cache.
                lp, lc = b.pair(d, ["lpfg", "-b", "-dll", so, *args], [lcjit, "-b", *args], runs=3)
                _, lc2 = b.pair(d, ["lpfg", "-b", "-dll", so, *args], [lcjit, "-b", "-O2", *args], runs=3)
                add(row, "LPFG-LIGNUM, lcjit's default tiers after its first run", lp, lc,
                    note=f"lcjit -O2: {lc2 * 1000:.0f} ms (default / -O2 = {lc / lc2:.2f})")
            elif row == "out_str":
                d = b.folder(row, [os.path.join(bench, "branching.l")])
                so = b.lpfg_library(d, ["branching.l"])
                lp, lc = b.pair(d, ["lpfg", "-b", "-dll", so, "-out", "lpfg.str", "branching.l"],
                                [lcjit, "-b", "-out", "lcjit.str", "branching.l"], runs=5)
                sizes = f"lpfg writes names only ({os.path.getsize(os.path.join(d, 'lpfg.str')) >> 20} MiB), lcjit " \
                        f"modules with parameters ({os.path.getsize(os.path.join(d, 'lcjit.str')) >> 20} MiB)"
                add(row, "-out x.str of branching.l", lp, lc, note=sizes)
            elif row == "dtf":
                d = b.folder(row, [os.path.join(bench, "turtle.l")])
                so = b.lpfg_library(d, ["turtle.l"])
                lp, lc = b.pair(d, ["lpfg", "-b", "-dll", so, "-dtf", "turtle.l"], [lcjit, "-b", "-dtf", "turtle.l"])
                add(row, "-dtf turtle text of turtle.l", lp, lc)
            elif row == "memory":
                d = b.folder(row, [os.path.join(bench, "branching.l")])
                so = b.lpfg_library(d, ["branching.l"])
                subprocess.run([lcjit, "-b", "branching.l"], cwd=d, env=b.env, capture_output=True)
                lp = b.peak_kb(d, ["lpfg", "-b", "-dll", so, "branching.l"])
                lc = b.peak_kb(d, [lcjit, "-b", "branching.l"])
                add(row, "peak resident memory, branching.l", lp, lc, unit="KiB")
            elif row == "compile_20k":
                d = b.folder(row, [])
                with open(os.path.join(d, "prods_20k.l"), "w") as out:
                    out.write(productions_20k())
                secs, kb = [], []
                for _ in range(3):
                    fresh = os.path.join(work, "cache-20k")
                    shutil.rmtree(fresh, ignore_errors=True)
                    env = dict(b.env, LCJIT_CACHE_DIR=fresh)
                    p = subprocess.run(["/usr/bin/time", "-f", "%e %M", lcjit, "-b", "prods_20k.l"], cwd=d, env=env,
                                       capture_output=True, text=True)
                    s, m = p.stderr.strip().splitlines()[-1].split()
                    secs.append(float(s))
                    kb.append(int(m))
                s, m = statistics.median(secs), statistics.median(kb)
                rows.append(dict(row=row, what="compile of 20 000 one-line productions", lpfg=None, lcjit=s, unit="s",
                                 ratio=None, target=None, note=f"{m / 1024:.0f} MiB peak"))
                print(f"{row:14} lcjit {s:.2f} s, {m / 1024:.0f} MiB peak (target <= 5 s, <= 1 GB)", flush=True)
            else:
                sys.exit(f"unknown row {row}; rows: {', '.join(ROWS)}")
        after = load()
        print(f"\nload average before {before}, after {after}; {os.cpu_count()} cores\n")
        print("| work | lpfg | lcjit | lpfg/lcjit | target |\n|---|---:|---:|---:|---:|")
        for r in rows:
            fmt = (lambda v: "—" if v is None else f"{v * 1000:.1f} ms") if r["unit"] == "s" else (lambda v: f"{v / 1024:.0f} MiB")
            ratio = "—" if r["ratio"] is None else f"{r['ratio']:.2f}×"
            target = "≤ 5 s, ≤ 1 GB" if r["row"] == "compile_20k" else f"≥ {r['target']}×"
            what = r["what"] + (f" ({r['note']})" if r["note"] else "")
            print(f"| {what} | {fmt(r['lpfg'])} | {fmt(r['lcjit'])} | {ratio} | {target} |")
        if a.json:
            json.dump(dict(rows=rows, load_before=before, load_after=after), open(a.json, "w"), indent=1)


if __name__ == "__main__":
    main()
