#!/usr/bin/env python3
"""The segments of an OBJ file lcjit wrote (its `l` polylines, each cut into segments), compared
with a NAME.segments file of `x1 y1 z1  x2 y2 z2` lines derived by hand, in drawing order, within
1e-4 (the turtle turns in single precision); and its spheres, each a `sphere x y z r` line: the
OBJ's faces make up that many meshes whose vertices all lie r from (x, y, z) (within 1e-3), in
drawing order; and its polygons, each a `polygon x1 y1 z1  x2 y2 z2 …` line of its corners: the
OBJ's faces have those corners and no others (within 1e-4). Usage: segments.py OBJ EXPECTED"""
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
    return [tuple(float(x) for x in line.split()) for line in open(path)
            if line.strip() and not line.startswith("#") and not line.startswith("sphere")
            and not line.startswith("polygon")]


def meshes(path):
    """The OBJ's meshes: its faces grouped by the objects (`o`/`g`) they follow, each its vertices."""
    vertices, groups = [], [[]]
    for line in open(path):
        fields = line.split()
        if fields and fields[0] == "v":
            vertices.append(tuple(float(x) for x in fields[1:4]))
        elif fields and fields[0] in ("o", "g") and groups[-1]:
            groups.append([])
        elif fields and fields[0] == "f":
            groups[-1] += [vertices[int(i.split("/")[0]) - 1] for i in fields[1:]]
    return [g for g in groups if g]


spheres = [tuple(float(x) for x in line.split()[1:5]) for line in open(sys.argv[2]) if line.startswith("sphere")]
if spheres:
    found = meshes(sys.argv[1])
    on = lambda mesh, s: all(abs(sum((a - b) ** 2 for a, b in zip(v, s[:3])) ** 0.5 - s[3]) <= 1e-3 for v in mesh)
    if len(found) != len(spheres) or not all(on(m, s) for m, s in zip(found, spheres)):
        print(f"FAIL: {len(found)} meshes drawn, expected the spheres {spheres}")
        for m in found:
            print("  a mesh of", len(m), "face corners, the first at", m[0])
        sys.exit(1)

polygons = [[float(x) for x in line.split()[1:]] for line in open(sys.argv[2]) if line.startswith("polygon")]
if polygons:
    corners = [tuple(p[k:k + 3]) for p in polygons for k in range(0, len(p), 3)]
    faces = {v for mesh in meshes(sys.argv[1]) for v in mesh}
    near = lambda a, b: all(abs(x - y) <= 1e-4 for x, y in zip(a, b))
    unmatched = [c for c in corners if not any(near(c, v) for v in faces)]
    extra = [v for v in faces if not any(near(c, v) for c in corners)]
    if unmatched or extra:
        print(f"FAIL: corners not drawn {unmatched}; face vertices not expected {extra}")
        sys.exit(1)

got, want = drawn(sys.argv[1]), expected(sys.argv[2])
ok = len(got) == len(want) and all(abs(a - b) <= 1e-4 for g, w in zip(got, want) for a, b in zip(g, w))
if not ok:
    print(f"FAIL: {len(got)} segments drawn, {len(want)} expected")
    for g in got:
        print("  drawn   ", " ".join(f"{x:g}" for x in g))
    for w in want:
        print("  expected", " ".join(f"{x:g}" for x in w))
    sys.exit(1)
print(f"ok: {len(got)} segments, {len(spheres)} spheres and {len(polygons)} polygons as derived by hand")
