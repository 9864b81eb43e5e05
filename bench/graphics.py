#!/usr/bin/env python3
"""Graphics benchmarks: interpretation of bench/models/turtle.l (2 M turtle
commands) into geometry data, and rendering bench/segments.l (1 M segments) to a PNG with Mesa's
software rasteriser. Reports lcjit's --stats phases (median of --repeat runs); targets:
interpretation <= 150 ms, render <= 1 s. Not a pass/fail test.

Usage: bench/graphics.py [--lcjit build/lcjit] [--repeat 3]"""
import argparse, json, os, statistics, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = [("turtle.l -> geometry", os.path.join(ROOT, "bench", "models", "turtle.l"), "out.obj", "interpret_ms", 150),
         ("segments.l -> png", os.path.join(ROOT, "bench", "segments.l"), "out.png", "render_ms", 1000)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lcjit", default=os.path.join(ROOT, "build", "lcjit"))
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    print(f"{'case':24} {'derive':>8} {'interpret':>10} {'render/export':>14} {'target':>18}")
    for name, model, out, key, target in CASES:
        runs = []
        with tempfile.TemporaryDirectory() as work:
            for _ in range(a.repeat):
                p = subprocess.run([a.lcjit, "--stats", "-out", os.path.join(work, out), model], cwd=work,
                                   capture_output=True, text=True)
                if p.returncode != 0:
                    print(f"{name:24} error: {p.stderr.strip()[-200:]}")
                    break
                runs.append(json.loads(p.stderr.strip().splitlines()[-1]))
        if not runs:
            continue
        med = {k: statistics.median(r[k] for r in runs) for k in ("derive_ms", "interpret_ms", "render_ms")}
        ok = "met" if med[key] <= target else "MISSED"
        print(f"{name:24} {med['derive_ms']:8.1f} {med['interpret_ms']:10.1f} {med['render_ms']:14.1f} "
              f"{key[:-3]} <= {target} ms {ok}")


if __name__ == "__main__":
    main()
