#!/usr/bin/env python3
"""The colour of each segment of an OBJ file lcjit wrote (its material's Kd in the .mtl beside
it), compared with a NAME.colours file of `x1 y1 z1  x2 y2 z2  COLOUR` lines derived by hand (in
any order: the OBJ groups lines by material), within 1e-4; the colours are the names of the XL
quick reference's colour table (its appendix: 0 black … 15 white), their RGB the EGA's, or
GroIMP's named shaders (RED …), java.awt.Color's. A `faces x1 y1 z1  x2 y2 z2  COLOUR` line: the
faces of that colour span that box (their corners' least and greatest coordinates), within 1e-4.
Usage: colours.py OBJ EXPECTED"""
import os
import sys

EGA = {  # name: (r, g, b) of 255; IBM's EGA palette, which GroIMP's turtle indexes
    "black": (0, 0, 0), "blue": (0, 0, 170), "green": (0, 170, 0), "cyan": (0, 170, 170),
    "red": (170, 0, 0), "magenta": (170, 0, 170), "brown": (170, 85, 0), "light grey": (170, 170, 170),
    "dark grey": (85, 85, 85), "light blue": (85, 85, 255), "light green": (85, 255, 85),
    "light cyan": (85, 255, 255), "light red": (255, 85, 85), "light magenta": (255, 85, 255),
    "yellow": (255, 255, 85), "white": (255, 255, 255),
    # GroIMP's named shaders (RGBAShader.RED …): java.awt.Color's constants
    "RED": (255, 0, 0), "GREEN": (0, 255, 0), "BLUE": (0, 0, 255), "ORANGE": (255, 200, 0),
    "PINK": (255, 175, 175), "GRAY": (128, 128, 128),
}


def segment_colours(obj):
    kd, current, material, vertices = {}, None, None, []
    for line in open(os.path.join(os.path.dirname(obj) or ".", open(obj).read().split("mtllib ")[1].split()[0])):
        f = line.split()
        if f and f[0] == "newmtl":
            material = f[1]
        elif f and f[0] == "Kd":
            kd[material] = tuple(float(x) for x in f[1:4])
    segments, faces = [], {}
    for line in open(obj):
        f = line.split()
        if f and f[0] == "v":
            vertices.append(tuple(float(x) for x in f[1:4]))
        elif f and f[0] == "usemtl":
            current = kd[f[1]]
        elif f and f[0] == "l":
            ids = [int(i.split("/")[0]) - 1 for i in f[1:]]
            segments += [(vertices[a] + vertices[b], current) for a, b in zip(ids, ids[1:])]
        elif f and f[0] == "f":
            faces.setdefault(current, []).extend(vertices[int(i.split("/")[0]) - 1] for i in f[1:])
    return segments, faces


def expected(path, kind):
    out = []
    for line in open(path):
        line = line.split("#")[0].split()
        if line and (line[0] == "faces") == (kind == "faces"):
            line = line[1:] if kind == "faces" else line
            out.append((tuple(float(x) for x in line[:6]), " ".join(line[6:])))
    return out


(got, faces), want = segment_colours(sys.argv[1]), expected(sys.argv[2], "segments")
ok = True
for box, name in expected(sys.argv[2], "faces"):
    colour = tuple(e / 255 for e in EGA[name])
    corners = next((v for c, v in faces.items() if all(abs(a - b) < 1e-5 for a, b in zip(c, colour))), [])
    span = tuple(min(v[k] for v in corners) for k in range(3)) + tuple(max(v[k] for v in corners) for k in range(3)) if corners else ()
    if not span or not all(abs(a - b) <= 1e-4 for a, b in zip(span, box)):
        ok = False
        print(f"FAIL: the faces in {name} span {span}, expected {box}")
unmatched = list(got)
ok = ok and len(got) == len(want)
for where, name in want:
    hit = next((g for g in unmatched if all(abs(a - b) <= 1e-4 for a, b in zip(g[0], where)) and
                all(abs(c - e / 255) < 1e-5 for c, e in zip(g[1], EGA[name]))), None)
    if hit is None:
        ok = False
        print(f"FAIL: no segment {' '.join(f'{x:g}' for x in where)} in {name}")
    else:
        unmatched.remove(hit)
if not ok:
    for g in got:
        print("  drawn", " ".join(f"{x:g}" for x in g[0]), "in", " ".join(f"{x * 255:.0f}" for x in g[1]))
    sys.exit(1)
print(f"ok: {len(got)} segments in their colours")
