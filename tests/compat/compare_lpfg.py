#!/usr/bin/env python3
"""Side-by-side comparison of lcjit with the reference lpfg on real models (strings and pictures).

Not part of the test suite: it needs the reference lpfg (tests/compat/build_reference_lpfg.sh) and the
models, neither of which is in this repository. docs/compatibility.md says how to run it and
what it found.

    compare_lpfg.py [options] MANIFEST            # MANIFEST: name<TAB>folder<TAB>lpfg command line
    compare_lpfg.py --vlab GITDIR --write-manifest FILE --export DIR
                                                  # a manifest of a vlab snapshot's lpfg objects

For each model, in copies of its folder:
  - lpfg -b -out ref.strb ARGS (lpfg compiles with g++ -O3; its strings are the reference);
  - lcjit -b -out out.str ARGS, and lcjit decodes ref.strb with the same model (REPL LoadString),
    so the two strings are compared as text, one module per line, every parameter printed exactly
    (%.9g floats, %.17g doubles): "equal" means every module and every bit of every parameter;
  - pictures (unless --no-pictures): lpfg's window under Xvfb at 96 dpi (-out ref.png, 400x400) and
    lcjit -b -out out.png at the same size, compared with tests/tools/image_diff.
Models with a .e file (environment programs) are run only with --env.
"""
import argparse
import os
import shlex
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def run(cmd, cwd, timeout, env=None):
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           timeout=timeout, env=env, text=True, errors="replace")
        return p.returncode, p.stdout, time.monotonic() - t0
    except subprocess.TimeoutExpired as e:
        out = e.stdout if isinstance(e.stdout, str) else (e.stdout or b"").decode(errors="replace")
        return -999, out + "\n[timeout]", time.monotonic() - t0


def lpfg_env(prefix):
    env = dict(os.environ)
    env.update(VLABROOT=prefix, VLABBIN=prefix + "/bin", VLABCONFIGDIR=prefix + "/config",
               LPFGPATH=prefix, LPFGRESOURCES=prefix, VLABTMPDIR="/tmp", QT_QPA_PLATFORM="offscreen")
    env["PATH"] = prefix + "/bin:" + env["PATH"]
    return env


# lpfg options with their argument counts; the comparison sets its own output and window options.
OPTION_ARGS = {"-a": 0, "-b": 0, "-q": 0, "-v": 0, "-d": 0, "-c": 0, "-cn": 0, "-ds": 0, "-dtf": 0, "-dtfes": 0,
               "-wnb": 0, "-wnm": 0, "-cleanEA20": 0, "-tablet": 0, "-timer": 0, "-timed": 0, "-out": 1,
               "-rmode": 1, "-lp": 1, "-dll": 1, "-o": 1, "-w": 2, "-wp": 2, "-wr": 2, "-wpr": 2}
DROPPED = {"-a", "-b", "-out", "-w", "-wp", "-wr", "-wpr", "-wnb", "-wnm", "-rmode", "-ds", "-dtf", "-dtfes", "-q", "-v",
           "-d", "-timer", "-timed", "-tablet"}


def model_args(cmdline):
    """The lpfg command line without the program name and the options the comparison replaces."""
    words = shlex.split(cmdline)
    if words and os.path.basename(words[0]) == "lpfg":
        words = words[1:]
    out, i = [], 0
    while i < len(words):
        w = words[i]
        n = OPTION_ARGS.get(w, 0)
        if w not in DROPPED:
            out.extend(words[i:i + 1 + n])
        i += 1 + n
    return out


def lsystem_of(args):
    return next((a for a in args if a.endswith(".l")), None)


def fresh_copy(src, dst):
    if os.path.exists(dst):
        shutil.rmtree(dst)
    shutil.copytree(src, dst, symlinks=True)


def decode_ref(lcjit, folder, args, strb):
    script = 'LoadString("%s");\n:save ref.str\n' % strb
    p = subprocess.run([lcjit, "repl", *args], cwd=folder, input=script, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, timeout=300, errors="replace")
    path = os.path.join(folder, "ref.str")
    return (open(path, errors="replace").read() if os.path.exists(path) else None), p.stdout


def numbers_close(a, b):
    """Largest relative difference between two module lines with the same names, or None."""
    import re
    na = re.findall(r"-?[\d.]+(?:e[-+]?\d+)?|nan|inf", a)
    nb = re.findall(r"-?[\d.]+(?:e[-+]?\d+)?|nan|inf", b)
    if len(na) != len(nb) or re.sub(r"[-\d.e+]+", "", a) != re.sub(r"[-\d.e+]+", "", b):
        return None
    worst = 0.0
    for x, y in zip(na, nb):
        try:
            fx, fy = float(x), float(y)
        except ValueError:
            continue
        d = abs(fx - fy) / max(abs(fx), abs(fy), 1e-30)
        worst = max(worst, d)
    return worst


def compare_strings(ref, out):
    r, o = ref.splitlines(), out.splitlines()
    if r == o:
        return "equal", "%d modules" % len(r)
    first = next((i for i, (x, y) in enumerate(zip(r, o)) if x != y), min(len(r), len(o)))
    worst, differing = 0.0, 0
    if len(r) == len(o):
        for x, y in zip(r, o):
            if x != y:
                differing += 1
                d = numbers_close(x, y)
                worst = float("inf") if d is None else max(worst, d)
        kind = "rounding" if worst < 1e-4 else "differ"
        return kind, "%d of %d modules differ, largest relative difference %.3g; first at %d: lpfg %s | lcjit %s" % (
            differing, len(r), worst, first + 1, r[first][:80], o[first][:80])
    return "differ", "lpfg %d modules, lcjit %d; first difference at %d: lpfg %s | lcjit %s" % (
        len(r), len(o), first + 1, r[first][:80] if first < len(r) else "<end>", o[first][:80] if first < len(o) else "<end>")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("manifest", nargs="?")
    ap.add_argument("--lcjit", default=os.path.join(ROOT, "build", "lcjit"))
    ap.add_argument("--image-diff", default=os.path.join(ROOT, "build", "tests", "lcjit_image_diff"))
    ap.add_argument("--lpfg-prefix", default="/opt/lpfg-ref")
    ap.add_argument("--work", default="/tmp/lcjit-compat")
    ap.add_argument("--only", action="append", help="run only models whose name contains this (repeatable)")
    ap.add_argument("--no-pictures", action="store_true")
    ap.add_argument("--env", action="store_true", help="also models with environment programs (.e)")
    ap.add_argument("--timeout", type=int, default=300)
    ap.add_argument("--frozen-clock", metavar="TIME",
                    help="derive the strings under `faketime -f TIME` (models that seed rand() with time(0)); "
                         "pictures use the real clock: lpfg's window does not draw on a frozen one")
    ap.add_argument("--vlab", help="a vlab snapshot (bare git dir): write a manifest of its lpfg objects")
    ap.add_argument("--write-manifest")
    ap.add_argument("--export", help="with --vlab: where to export the objects")
    a = ap.parse_args()

    if a.vlab:
        return write_vlab_manifest(a.vlab, a.export, a.write_manifest)
    if not a.manifest:
        ap.error("a manifest is needed")

    models = []
    base = os.path.dirname(os.path.abspath(a.manifest))
    for line in open(a.manifest):
        if not line.strip() or line.startswith("#"):
            continue
        name, folder, cmd = line.rstrip("\n").split("\t")[:3]
        if a.only and not any(o in name for o in a.only):
            continue
        models.append((name, os.path.join(base, folder), cmd))

    env = lpfg_env(a.lpfg_prefix)
    a.clock = ["faketime", "-f", a.frozen_clock] if a.frozen_clock else []
    results = []
    for name, folder, cmd in models:
        args = model_args(cmd)
        has_env = any(x.endswith(".e") for x in args)
        row = {"name": name, "string": "-", "picture": "-", "note": ""}
        results.append(row)
        if has_env and not a.env:
            row["string"] = row["picture"] = "skipped (.e)"
            print_row(row)
            continue
        work = os.path.join(a.work, name)
        lp, lc = os.path.join(work, "lpfg"), os.path.join(work, "lcjit")
        fresh_copy(folder, lp)
        fresh_copy(folder, lc)
        code, log, t_lpfg = run([*a.clock, "lpfg", "-b", "-out", "ref.strb", *args], lp, a.timeout, env)
        open(os.path.join(work, "lpfg.log"), "w").write(log)
        ref_ok = os.path.exists(os.path.join(lp, "ref.strb"))
        code2, log2, t_lcjit = run([*a.clock, a.lcjit, "-b", "-q", "-out", "out.str", *args], lc, a.timeout)
        open(os.path.join(work, "lcjit.log"), "w").write(log2)
        out_ok = code2 == 0 and os.path.exists(os.path.join(lc, "out.str"))
        row["t"] = "lpfg %.1fs lcjit %.1fs" % (t_lpfg, t_lcjit)
        if not ref_ok:
            row["string"] = "lpfg failed"
            row["note"] = last_lines(log)
        elif not out_ok:
            row["string"] = "lcjit failed"
            row["note"] = last_lines(log2)
        else:
            shutil.copy(os.path.join(lp, "ref.strb"), os.path.join(lc, "ref.strb"))
            ref, dlog = decode_ref(a.lcjit, lc, args, "ref.strb")
            if ref is None:
                row["string"] = "undecodable"
                row["note"] = last_lines(dlog)
            else:
                kind, detail = compare_strings(ref, open(os.path.join(lc, "out.str"), errors="replace").read())
                row["string"], row["note"] = kind, detail
        if not a.no_pictures:
            row["picture"] = compare_pictures(a, env, args, lp, lc, work)
        print_row(row)

    counts = {}
    for r in results:
        counts.setdefault(("string", r["string"]), 0)
        counts[("string", r["string"])] += 1
        p = r["picture"].split(" ")[0]
        counts.setdefault(("picture", p), 0)
        counts[("picture", p)] += 1
    print("\nsummary:", ", ".join("%s %s: %d" % (k[0], k[1], v) for k, v in sorted(counts.items())))
    return 0


def compare_pictures(a, env, args, lp, lc, work):
    for f in ("ref.png", "out.png"):
        for d in (lp, lc):
            if os.path.exists(os.path.join(d, f)):
                os.remove(os.path.join(d, f))
    # At 96 dpi (Qt's usual; lcjit's labels assume it) Qt's menu bar takes 20 pixels of lpfg's
    # window: -w 400 420 leaves a 400x400 picture. A multi-view window is saved whole, its
    # bottom 20 rows in the border colour: the top 400 rows are the picture.
    xenv = dict(env)
    xenv.pop("QT_QPA_PLATFORM", None)
    code, log, _ = run(["xvfb-run", "-a", "-s", "-screen 0 1024x768x24 -dpi 96", "lpfg", "-w", "400", "420", "-out",
                        "ref.png", *args], lp, a.timeout, xenv)
    if not os.path.exists(os.path.join(lp, "ref.png")):
        return "lpfg failed"
    run(["convert", "ref.png", "-crop", "400x400+0+0", "+repage", "ref.png"], lp, 60)
    code, log, _ = run([a.lcjit, "-b", "-q", "-w", "400", "400", "-out", "out.png", *args], lc, a.timeout)
    if code != 0:
        return "lcjit failed"
    shutil.copy(os.path.join(lp, "ref.png"), os.path.join(work, "lpfg.png"))
    shutil.copy(os.path.join(lc, "out.png"), os.path.join(work, "lcjit.png"))
    code, log, _ = run([a.image_diff, os.path.join(work, "lpfg.png"), os.path.join(work, "lcjit.png")], work, 60)
    return "match" if code == 0 else "differ " + log.strip().splitlines()[-1] if log.strip() else "differ"


def last_lines(text, n=3):
    lines = [l for l in text.splitlines() if l.strip()]
    return " / ".join(lines[-n:])[:300]


def print_row(r):
    print("%-55s string: %-12s picture: %-10s %s  %s" % (r["name"], r["string"], r["picture"].split(" ")[0],
                                                        r.get("t", ""), r["note"]), flush=True)


def write_vlab_manifest(gitdir, export, manifest):
    if not (export and manifest):
        sys.exit("--vlab needs --export DIR and --write-manifest FILE")
    files = subprocess.run(["git", "--git-dir", gitdir, "ls-tree", "-r", "--name-only", "HEAD", "oofs"],
                           stdout=subprocess.PIPE, text=True, check=True).stdout.split()
    lines = []
    for f in files:
        if not f.endswith("/specifications"):
            continue
        spec = subprocess.run(["git", "--git-dir", gitdir, "show", "HEAD:" + f], stdout=subprocess.PIPE, text=True,
                              errors="replace").stdout
        cmd = next((l.strip() for l in spec.splitlines() if l.strip().startswith("lpfg ")), None)
        if not cmd:
            continue
        d = os.path.dirname(f)
        name = d.replace("oofs/ext/", "").replace("/ext/", "_")
        dst = os.path.join(export, name)
        os.makedirs(dst, exist_ok=True)
        depth = d.count("/") + 1
        tar = subprocess.Popen(["git", "--git-dir", gitdir, "archive", "HEAD", d], stdout=subprocess.PIPE)
        subprocess.run(["tar", "-x", "--strip-components=%d" % depth, "-C", dst], stdin=tar.stdout, check=True)
        tar.wait()
        lines.append("%s\t%s\t%s" % (name, os.path.relpath(dst, os.path.dirname(os.path.abspath(manifest))), cmd))
    with open(manifest, "w") as m:
        m.write("# name\tfolder\tlpfg command line (from the object's specifications)\n")
        m.write("\n".join(sorted(lines)) + "\n")
    print("%d lpfg objects -> %s" % (len(lines), manifest))
    return 0


if __name__ == "__main__":
    sys.exit(main())
