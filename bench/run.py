#!/usr/bin/env python3
"""Benchmark lcjit: per model, the cold (no PCH cache) and warm (PCH cached) whole-run time and
the --stats phases. Models: bench/models/*.l and tests/models/*.l (or the paths given).

Usage: bench/run.py [--lcjit build/lcjit] [--repeat 3] [--corpus] [model.l ...]
Targets (see README): warm whole run of a teaching model <= 100 ms; branching.l derivation
<= 0.2 s; signal.l derivation <= 0.5 s. Prints a table; nothing here is a pass/fail test."""
import argparse, glob, json, os, statistics, subprocess, sys, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(lcjit, model, files, cache, opt):
    env = dict(os.environ, LCJIT_CACHE_DIR=cache)
    with tempfile.TemporaryDirectory() as work:
        t0 = time.perf_counter()
        p = subprocess.run([lcjit, "-b", "-out", os.path.join(work, "out.str"), f"-O{opt}", "--stats", *files, model],
                           cwd=work, env=env, capture_output=True, text=True)
        wall = (time.perf_counter() - t0) * 1000
    if p.returncode != 0:
        return None, wall, p.stderr.strip().splitlines()[-1:] or ["?"]
    stats = json.loads(p.stderr.strip().splitlines()[-1])
    return stats, wall, None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lcjit", default=os.path.join(ROOT, "build", "lcjit"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--corpus", action="store_true", help="also run every tests/models model")
    ap.add_argument("-O", dest="opt", type=int, default=1)
    ap.add_argument("models", nargs="*")
    a = ap.parse_args()
    models = a.models or sorted(glob.glob(os.path.join(ROOT, "bench", "models", "*.l")))
    if a.corpus:
        models += sorted(glob.glob(os.path.join(ROOT, "tests", "models", "*.l")))
    print(f"{'model':28} {'cold ms':>9} {'warm ms':>9} {'pre':>6} {'rewrite':>7} {'compile':>8} {'derive':>8} "
          f"{'steps':>5} {'modules':>9}")
    warm_all = []
    with tempfile.TemporaryDirectory() as cache:
        for m in models:
            name = os.path.splitext(os.path.basename(m))[0]
            extra = []
            fl = os.path.splitext(m)[0] + ".files"
            if os.path.exists(fl):
                extra = [os.path.join(os.path.dirname(m), f) for f in open(fl).read().split()]
            cold_cache = tempfile.mkdtemp(dir=cache)
            stats, cold, err = run(a.lcjit, m, extra, cold_cache, a.opt)
            if err:
                print(f"{name:28} error: {err[0]}")
                continue
            runs = [run(a.lcjit, m, extra, cold_cache, a.opt) for _ in range(a.repeat)]
            warm = statistics.median(r[1] for r in runs)
            s = sorted(runs, key=lambda r: r[1])[len(runs) // 2][0]
            warm_all.append(warm)
            print(f"{name:28} {cold:9.1f} {warm:9.1f} {s['preprocess_ms']:6.1f} {s['rewrite_ms']:7.2f} "
                  f"{s['compile_ms']:8.1f} {s['derive_ms']:8.1f} {s['steps']:5d} {s['modules']:9d}"
                  + ("" if s["pch_cached"] else "  (PCH not cached!)"))
    if warm_all:
        print(f"median warm whole run over {len(warm_all)} models: {statistics.median(warm_all):.1f} ms")


if __name__ == "__main__":
    sys.exit(main())
