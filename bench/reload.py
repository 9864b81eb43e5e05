#!/usr/bin/env python3
"""Hot-swap latency: from saving an edit of the .l file to the new derived string being written.

Runs `lcjit --watch -b -out out.str MODEL.l` on a copy of each model, waits for the first run and
for the background -O2 build to settle, then makes N edits, each a save of the whole file
(write + close, like an editor), and times each from the save to lcjit's "reload K" line on
stderr (printed after the string is written). Two kinds of edit, each a new text so that every
one really compiles (no object-cache hit):
  body    a statement added to the first production body that produces (an edit confined to
          one production)
  global  a new global variable at the end of the file (an edit outside the productions)
Prints per model and kind: p50, p90, min, max (ms), lcjit's own compile time (p50) and its own
time from noticing the change to the string written (p50; the rest is the file system's event
and the pipe).

Usage: bench/reload.py [--lcjit build/lcjit] [--edits 20] [model.l ...]   (default: examples/*.l)
Targets (issue 5): p50 <= 50 ms for the teaching models; <= 20 ms for a one-production edit."""
import argparse, glob, os, re, select, shutil, statistics, subprocess, sys, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_line(proc, timeout):
    """The next stderr line of proc, or None after timeout seconds."""
    end = time.perf_counter() + timeout
    buf = b""
    while True:
        left = end - time.perf_counter()
        if left <= 0:
            return None
        r, _, _ = select.select([proc.stderr], [], [], left)
        if not r:
            return None
        c = os.read(proc.stderr.fileno(), 1)
        if not c:
            return None
        if c == b"\n":
            return buf.decode(errors="replace")
        buf += c


def edited(text, kind, n):
    if kind == "global":
        return text + f"\nstatic int lcjit_bench_edit_{n} = {n};\n"
    m = re.search(r"\bproduce\b", text)
    return text[: m.start()] + f"(void){n}; " + text[m.start():]


def bench_model(lcjit, model, edits):
    files = []
    fl = os.path.splitext(model)[0] + ".files"  # extra input files, as bench/run.py reads them
    if os.path.exists(fl):
        files = [os.path.join(os.path.dirname(model), f) for f in open(fl).read().split()]
    results = {}
    with tempfile.TemporaryDirectory() as work:
        src = os.path.join(work, os.path.basename(model))
        shutil.copy(model, src)
        text = open(src).read()
        if not re.search(r"\bproduce\b", text):
            return None
        proc = subprocess.Popen([lcjit, "--watch", "-b", "-v", "-out", "out.str", *files, src], cwd=work,
                                stderr=subprocess.PIPE, stdout=subprocess.DEVNULL)
        try:
            while True:  # the first run, then the -O2 tier in the background
                line = read_line(proc, 30)
                if line is None:
                    return None
                if "swapped in" in line:
                    break
            n = 0
            for kind in ("body", "global"):
                times, compiles, inside = [], [], []
                for _ in range(edits):
                    n += 1
                    new = edited(text, kind, 1000 + n)
                    t0 = time.perf_counter()
                    with open(src, "w") as f:
                        f.write(new)
                    while True:
                        line = read_line(proc, 30)
                        if line is None:
                            return None
                        if re.match(r"lcjit: reload \d+ ", line):
                            break
                    ms = (time.perf_counter() - t0) * 1000
                    if "failed" in line:
                        print(f"  {os.path.basename(model)}: reload failed: {line}", file=sys.stderr)
                        return None
                    times.append(ms)
                    m = re.search(r"compiled -O\d in ([\d.]+) ms", line)
                    if m:
                        compiles.append(float(m.group(1)))
                    m = re.search(r"([\d.]+) ms in all", line)
                    if m:
                        inside.append(float(m.group(1)))
                    # let the -O2 build of this version finish, as between a modeller's edits
                    deadline = time.perf_counter() + 10
                    while time.perf_counter() < deadline:
                        line = read_line(proc, 10)
                        if line is None or "swapped in" in line:
                            break
                results[kind] = (times, compiles, inside)
        finally:
            proc.kill()
            proc.wait()
    return results


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lcjit", default=os.path.join(ROOT, "build", "lcjit"))
    ap.add_argument("--edits", type=int, default=20)
    ap.add_argument("models", nargs="*")
    a = ap.parse_args()
    models = a.models or sorted(glob.glob(os.path.join(ROOT, "examples", "*.l")))
    print(f"{'model':16} {'edit':6} {'p50':>7} {'p90':>7} {'min':>7} {'max':>7} {'compile p50':>12} {'lcjit p50':>10}")
    p50s = {"body": [], "global": []}
    for m in models:
        r = bench_model(a.lcjit, m, a.edits)
        name = os.path.splitext(os.path.basename(m))[0]
        if not r:
            print(f"{name:16} (skipped: no produce statement, or lcjit did not reload)")
            continue
        for kind, (t, c, inside) in r.items():
            t.sort()
            p50 = statistics.median(t)
            p50s[kind].append(p50)
            print(f"{name:16} {kind:6} {p50:7.1f} {t[int(0.9 * (len(t) - 1))]:7.1f} {t[0]:7.1f} {t[-1]:7.1f} "
                  f"{statistics.median(c) if c else float('nan'):12.1f} {statistics.median(inside):10.1f}")
    for kind, v in p50s.items():
        if v:
            print(f"median of the models' p50, {kind} edits: {statistics.median(v):.1f} ms over {len(v)} models")


if __name__ == "__main__":
    main()
