#!/usr/bin/env python3
"""The segments of an OBJ file lcjit wrote (its `l` polylines, each cut into segments), compared
with a NAME.segments file of `x1 y1 z1  x2 y2 z2` lines derived by hand, in drawing order, within
1e-4 (the turtle turns in single precision). Usage: segments.py OBJ EXPECTED"""
import sys


def drawn(path):
    vertices, segments = [], []
    for line in open(path):
        fields = line.split()
        if fields and fields[0] == "v":
            vertices.append(tuple(float(x) for x in fields[1:4]))
        elif fields and fields[0] == "l":
            ids = [int(i.split("/")[0]) - 1 for i in fields[1:]]
            segments += [vertices[a] + vertices[b] for a, b in zip(ids, ids[1:])]
    return segments


def expected(path):
    return [tuple(float(x) for x in line.split()) for line in open(path) if line.strip() and not line.startswith("#")]


got, want = drawn(sys.argv[1]), expected(sys.argv[2])
ok = len(got) == len(want) and all(abs(a - b) <= 1e-4 for g, w in zip(got, want) for a, b in zip(g, w))
if not ok:
    print(f"FAIL: {len(got)} segments drawn, {len(want)} expected")
    for g in got:
        print("  drawn   ", " ".join(f"{x:g}" for x in g))
    for w in want:
        print("  expected", " ".join(f"{x:g}" for x in w))
    sys.exit(1)
print(f"ok: {len(got)} segments as derived by hand")
