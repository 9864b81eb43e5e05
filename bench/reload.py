#!/usr/bin/env python3
"""Hot-swap latency: from saving an edit of the .l file to the new derived string being written.

Runs `lcjit --watch -b -out out.str [FILES] MODEL.l` in a copy of each model's folder (FILES: its
NAME.files, else its command in the folder's README.md, else its NAME.v/.map/.mat…), waits for the first run and
for the background -O2 build to settle, then makes N edits, each a save of the whole file
(write + close, like an editor), and times each from the save to lcjit's "reload K" line on
stderr (printed after the string is written). Two kinds of edit, each a new text so that every
one really compiles (no object-cache hit):
  body    a statement added at the start of the block around the first `produce` (an edit
          confined to one production)
  global  a new global variable at the end of the file (an edit outside the productions)
Prints per model and kind: p50, p90, min, max (ms), lcjit's own compile time (p50) and its own
time from noticing the change to the string written (p50; the rest is the file system's event
and the pipe).

Usage: bench/reload.py [--lcjit build/lcjit] [--edits 20] [model.l ...]   (default: examples/*.l)
Targets: p50 <= 50 ms for the teaching models; <= 20 ms for a one-production edit."""
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


def body_start(text):
    """Just after the '{' of the block around the first `produce` that has one (the innermost
    block still open there; `A : produce B;` has none), or None. A statement there is always
    valid, where one put before the `produce` itself is not (`if (c) produce A; else …`)."""
    code = re.sub(r"//[^\n]*|/\*.*?\*/|\"(\\.|[^\"\\])*\"|'(\\.|[^'\\])*'",
                  lambda c: " " * len(c.group(0)), text, flags=re.S)  # same offsets
    for m in re.finditer(r"\bproduce\b", code):
        depth = 0
        for i in range(m.start() - 1, -1, -1):
            if code[i] == "}":
                depth += 1
            elif code[i] == "{":
                if depth == 0:
                    return i + 1
                depth -= 1
    return None


def edited(text, kind, n):
    if kind == "global":
        return text + f"\nstatic int lcjit_bench_edit_{n} = {n};\n"
    at = body_start(text)
    return text[:at] + f" (void){n};" + text[at:]


INPUT_EXTENSIONS = (".v", ".map", ".mat", ".a", ".e", ".func", ".fset", ".tset", ".vset", ".con", ".cset")


def input_files(model):
    """The model's other input files, as names in its folder: its NAME.files if there is one, else
    the command its folder's README.md gives for it (examples/), else the files of its own name
    with an input extension."""
    folder, base = os.path.split(model)
    stem = os.path.splitext(base)[0]
    fl = os.path.join(folder, stem + ".files")
    if os.path.exists(fl):
        return open(fl).read().split()
    readme = os.path.join(folder, "README.md")
    if os.path.exists(readme):
        m = re.search(r"`lcjit(?: -\S+ \S+)* ((?:\S+ )*)" + re.escape(base) + "`", open(readme).read())
        if m:
            return m.group(1).split()
    return sorted(f for f in os.listdir(folder) if os.path.splitext(f)[0] == stem and f.endswith(INPUT_EXTENSIONS))


def bench_model(lcjit, model, edits):
    """{kind: (times, compiles, inside)}, or a string saying why the model was skipped."""
    files = input_files(model)
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        # The model's whole folder, so that its includes, surfaces and meshes are where it says.
        work = os.path.join(tmp, "model")
        shutil.copytree(os.path.dirname(os.path.abspath(model)), work,
                        ignore=shutil.ignore_patterns(".lcjit-cache", "*.png", "*.str"))
        src = os.path.join(work, os.path.basename(model))
        text = open(src).read()
        if body_start(text) is None:
            return "no produce statement inside a block"
        proc = subprocess.Popen([lcjit, "--watch", "-b", "-v", "-out", "out.str", *files, os.path.basename(src)],
                                cwd=work, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL)
        said = []  # lcjit's last lines, to say why a model is skipped
        try:
            while True:  # the first run, then the -O2 tier in the background
                line = read_line(proc, 30)
                if line is None:
                    return "lcjit did not run it: " + " / ".join(said[-3:])
                said.append(line)
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
                            return f"no reload after a {kind} edit: " + " / ".join(said[-3:])
                        said.append(line)
                        if re.match(r"lcjit: reload \d+ ", line):
                            break
                    ms = (time.perf_counter() - t0) * 1000
                    if "failed" in line:
                        return f"a {kind} edit failed: " + " / ".join(said[-3:])
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
        if isinstance(r, str):
            print(f"{name:16} skipped: {r}")
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
