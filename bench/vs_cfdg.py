#!/usr/bin/env python3
"""lcjit against Context Free's cfdg (3.4, Debian's contextfree), design by design: paired runs with
hyperfine, the order swapped from one round to the next, and the ratio of the medians (cfdg time /
lcjit time: above 1, lcjit is faster); peak memory with /usr/bin/time; lcjit's own account of
where its time went (`lcjit cfdg -t`: parse, compile, expand, draw and write). Both write the same
PNG (tests/cfdg checks they are equal). The machine's load average is printed before and after:
figures taken beside other work are not comparable.

Rows: the shipped designs with the most shapes that lcjit draws exactly, at 400 px, and
sierpinski and point at 2000 px (docs/cfdg.md keeps a table this printed).
Usage: bench/vs_cfdg.py [--lcjit build/lcjit] [--runs 3] [--rounds 2] [--rows NAME,...]
Nothing here is a test.
"""
import argparse, json, os, shutil, statistics, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = "/usr/share/doc/contextfree/examples"
ROWS = {  # name: (design under EXAMPLES, size in pixels)
    "perftest": ("tests/perftest.cfdg", 400),
    "ciliasun_v2": ("ciliasun_v2.cfdg", 400),
    "cilia": ("cilia.cfdg", 400),
    "sierpinski": ("sierpinski.cfdg", 2000),
    "point": ("point.cfdg", 2000),
}
TARGET = 3.0  # lcjit at least three times as fast, whole process, warm cache


def load():
    return os.getloadavg()[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lcjit", default=os.path.join(ROOT, "build", "lcjit"))
    ap.add_argument("--runs", type=int, default=3, help="runs of each command per round")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--rows", default=",".join(ROWS))
    ap.add_argument("--variation", default="A")
    ap.add_argument("--json", help="also write the figures here")
    a = ap.parse_args()
    for tool in ("hyperfine", "cfdg"):
        if not shutil.which(tool):
            sys.exit(f"{tool} is needed (apt install {'hyperfine' if tool == 'hyperfine' else 'contextfree'})")
    rows = []
    print(f"load average before: {load():.2f}")
    with tempfile.TemporaryDirectory() as work:
        lcjit = os.path.join(work, "lcjit")
        shutil.copy(os.path.realpath(a.lcjit), lcjit)  # a rebuild meanwhile does not change what is measured
        env = dict(os.environ, LCJIT_CACHE_DIR=os.path.join(work, "cache"))
        for name in a.rows.split(","):
            design, size = ROWS[name]
            path = os.path.join(EXAMPLES, design)
            ours = [lcjit, "cfdg", "-q", "-s", str(size), "-v", a.variation, path, os.path.join(work, "l.png")]
            theirs = ["cfdg", "-q", "-s", str(size), "-v", a.variation, path, os.path.join(work, "c.png")]
            subprocess.run(ours, env=env, check=True)  # the object cache is warm from here on
            times = {"cfdg": [], "lcjit": []}
            for r in range(a.rounds):
                order = [("cfdg", theirs), ("lcjit", ours)]
                if r % 2:
                    order.reverse()
                out = os.path.join(work, "hyperfine.json")
                subprocess.run(["hyperfine", "-N", "--warmup", "1", "--runs", str(a.runs), "--export-json", out,
                                "--style", "none"] + [" ".join(c) for _, c in order],
                               env=env, check=True, stdout=subprocess.DEVNULL)
                for (who, _), res in zip(order, json.load(open(out))["results"]):
                    times[who] += res["times"]
            peak = {}
            for who, cmd in (("cfdg", theirs), ("lcjit", ours)):
                p = subprocess.run(["/usr/bin/time", "-f", "%M", *cmd], env=env, capture_output=True, text=True)
                peak[who] = int(p.stderr.strip().splitlines()[-1])
            phases = subprocess.run(ours[:2] + ["-t"] + ours[2:], env=env, capture_output=True, text=True).stderr.strip()
            cf, lc = statistics.median(times["cfdg"]), statistics.median(times["lcjit"])
            row = dict(row=name, design=design, size=size, cfdg_s=cf, lcjit_s=lc, ratio=cf / lc,
                       cfdg_peak_mib=peak["cfdg"] / 1024, lcjit_peak_mib=peak["lcjit"] / 1024, phases=phases)
            rows.append(row)
            print(f"{name:12} {size:5} px  cfdg {cf:7.3f} s  lcjit {lc:7.3f} s  ratio {cf / lc:5.2f} (target {TARGET})  "
                  f"peak cfdg {peak['cfdg'] / 1024:6.0f} MiB  lcjit {peak['lcjit'] / 1024:6.0f} MiB", flush=True)
            print(f"{'':12} {phases.splitlines()[-1] if phases else ''}", flush=True)
    print(f"load average after: {load():.2f}")
    if a.json:
        json.dump(rows, open(a.json, "w"), indent=1)


if __name__ == "__main__":
    main()
