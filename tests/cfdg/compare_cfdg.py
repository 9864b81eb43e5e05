#!/usr/bin/env python3
"""Runs Context Free (`cfdg`, the oracle, at test time) and lcjit on designs and compares
- the pictures' shape lists (`-V` SVG): the same shapes in the same order, each with the same fill
  colour and opacity and the same matrix (within what 8 significant digits can say); a path's
  commands each with the same paint (fill or stroke, colour, rule, width, cap, join) and outline;
- the PNGs, decoded: the same size, channels, bit depth and every sample (with --image-diff, the
  suite's image_diff tool, run with --exact);
- with --frames N (and --image-diff), an animation instead: the N PNG frames of `-a N`, frame by
  frame, and the frame of `-a N -f K` for each K given by --frame (cfdg writes no SVG of a frame);
  --zoom adds -z.

usage: compare_cfdg.py --lcjit BIN [--size N] [--variations A,B,C] [--crop] [--define N=V] [--list FILE]
                       [--frames N [--frame K]... [--zoom]] DESIGN...
       compare_cfdg.py --svg REF GOT   (two pictures already written: cfdg's -V and one of lcjit's)
Exit status 0 when every design that lcjit runs matches, 1 otherwise; a summary per design."""
import argparse, os, re, subprocess, sys, tempfile

# A primitive (<rect>, <circle>, <use> of the triangle) or a path command: a group with its paint
# and transform holding the path's outline, or a use of an outline written before.
ELEMENT = re.compile(r'<(rect|circle)\b(.*?)/>|<use xlink:href="#TRIANGLE"(.*?)/>'
                     r'|<g\b([^>]*)>\s*(?:<path id="([^"]*)" d="([^"]*)"\s*/>|<use xlink:href="#([^"]*)"\s*/>)\s*</g>', re.S)
ATTR = re.compile(r'([a-z-]+)="([^"]*)"')
NUMBER = re.compile(r'[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?')
SIZE = re.compile(r'<svg width="(\d+)px" height="(\d+)px"')
def size(svg):
    m = SIZE.search(svg)
    return m.groups() if m else None

def shapes(svg):
    out, outlines = [], {}
    for m in ELEMENT.finditer(svg):
        kind, attrs = (m.group(1), m.group(2)) if m.group(1) else ('use', m.group(3)) if m.group(3) is not None else ('path', m.group(4))
        a = dict(ATTR.findall(attrs))
        matrix = [float(v) for v in a['transform'][7:-1].split()] if 'transform' in a else []
        if kind != 'path':
            out.append((kind, a['fill'].lower(), float(a.get('fill-opacity', 1)), matrix, []))
            continue
        if m.group(5): outlines[m.group(5)] = m.group(6)
        d = outlines.get(m.group(5) or m.group(7), '')
        # An iso-width outline is written in pixels; cfdg's use of one written before (a path it
        # cached) shows the first one's pixels: not compared.
        if m.group(7) and not matrix: d = None
        paint = tuple(a.get(k, '').lower() for k in ('fill', 'stroke', 'fill-rule', 'stroke-linecap', 'stroke-linejoin'))
        numbers = [float(a.get(k, 1)) for k in ('fill-opacity', 'stroke-opacity', 'stroke-width', 'stroke-miterlimit')]
        out.append(('path', paint, numbers, matrix, None if d is None else (re.sub(NUMBER, '#', d), [float(x) for x in NUMBER.findall(d)])))
    return out

# The two programs write the same elements with different spacing (cfdg pads matrix numbers to a
# width). Written alike once spacing is set aside, the pictures are the same shape for shape, and
# the slow element-by-element comparison (seconds for 100,000 shapes) is not needed.
def same_text(ref, got):
    canonical = lambda svg: ' '.join(svg[svg.find('<svg'):].split()).replace('( ', '(').replace(' )', ')')
    return canonical(ref) == canonical(got)

def close(a, b):
    return abs(a - b) <= 2e-7 * max(abs(a), abs(b)) + 1e-6

def compare(ref, got):
    if len(ref) != len(got):
        return f'{len(got)} shapes, cfdg drew {len(ref)}'
    for i, (r, g) in enumerate(zip(ref, got)):
        if r[0] != g[0] or r[1] != g[1]:
            return f'shape {i + 1}: {g[:3]}, cfdg {r[:3]}'
        if r[0] == 'path':
            if not all(close(x, y) for x, y in zip(r[2], g[2])):
                return f'shape {i + 1} (path): paint {g[2]}, cfdg {r[2]}'
            if r[4] and g[4] and (r[4][0] != g[4][0] or not all(close(x, y) for x, y in zip(r[4][1], g[4][1]))):
                return f'shape {i + 1} (path): outline {g[4][0][:60]}…, cfdg {r[4][0][:60]}…'
        elif abs(r[2] - g[2]) > 1e-6:
            return f'shape {i + 1}: {g[:3]}, cfdg {r[:3]}'
        if len(r[3]) != len(g[3]) or not all(close(x, y) for x, y in zip(r[3], g[3])):
            return f'shape {i + 1}: matrix {g[3]}, cfdg {r[3]}'
    return None

# An animation: each frame's PNG, and each single frame (-f K), sample for sample.
def compare_frames(a, design, v, work):
    options = [x for d in a.define for x in ('-D', d)] + ['-s', str(a.size), '-v', v] + (['-z'] if a.zoom else [])
    for frame in [0] + a.frame:
        for f in os.listdir(work):
            if f.endswith('.png'): os.remove(os.path.join(work, f))
        only = ['-f', str(frame)] if frame else []
        r = subprocess.run(['cfdg', '-q', '-a', str(a.frames)] + only + options + ['-o', os.path.join(work, 'ref_%f.png'), design],
                           capture_output=True, text=True)
        if r.returncode != 0: return f'cfdg failed ({r.returncode})'
        g = subprocess.run([a.lcjit, 'cfdg', '-q', '-a', str(a.frames)] + only + options + ['-o', os.path.join(work, 'got_%f.png'), design],
                           capture_output=True, text=True)
        if g.returncode != 0: return f'lcjit failed: {g.stderr.strip()[:300]}'
        refs = sorted(f for f in os.listdir(work) if f.startswith('ref_'))
        gots = sorted(f for f in os.listdir(work) if f.startswith('got_'))
        if [f[4:] for f in refs] != [f[4:] for f in gots]: return f'frames {gots}, cfdg wrote {refs}'
        for ref in refs:
            d = subprocess.run([a.image_diff, os.path.join(work, ref), os.path.join(work, 'got_' + ref[4:]), '--exact'],
                               capture_output=True, text=True)
            if d.returncode: return f'{"-f " + str(frame) + " " if frame else ""}frame {ref[4:-4]}: {d.stdout.strip()}'
    return None

def main():
    if len(sys.argv) == 4 and sys.argv[1] == '--svg':
        ref, got = (open(f).read() for f in sys.argv[2:])
        why = None if same_text(ref, got) else compare(shapes(ref), shapes(got))
        if not why and size(ref) != size(got): why = f'picture {size(got)}, cfdg {size(ref)}'
        print(f'{sys.argv[3]}: {"DIFFERENT: " + why if why else "equal"}')
        return 1 if why else 0
    ap = argparse.ArgumentParser()
    ap.add_argument('--lcjit', required=True)
    ap.add_argument('--size', type=int, default=400)
    ap.add_argument('--variations', default='A,BCD,XYZZY')
    ap.add_argument('--max-shapes', type=int, default=0)
    ap.add_argument('--define', action='append', default=[], help='NAME=VALUE, given to both as -D')
    ap.add_argument('--crop', action='store_true', help='both with -c: the fitted block alone')
    ap.add_argument('--image-diff', help='the image_diff tool: compare the PNGs too')
    ap.add_argument('--list', help='a file naming designs, one per line (# comments)')
    ap.add_argument('--part', default='1/1', help='K/N: every Nth design from the Kth (the suite runs parts in parallel)')
    ap.add_argument('--frames', type=int, default=0, help='compare the PNG frames of an animation of N frames')
    ap.add_argument('--frame', type=int, action='append', default=[], help='with --frames: also -f K alone')
    ap.add_argument('--zoom', action='store_true', help='with --frames: both with -z (each frame fitted to its shapes)')
    ap.add_argument('designs', nargs='*')
    a = ap.parse_args()
    if a.list:
        for line in open(a.list):
            line = line.split('#')[0].strip()
            # "design.cfdg" or "design.cfdg -v A,B" (its own variations); "@/x.cfdg": beside the list
            if line.startswith('@/'): line = os.path.join(os.path.dirname(os.path.abspath(a.list)), line[2:])
            if line: a.designs.append(line)
    k, n = (int(x) for x in a.part.split('/'))
    a.designs = a.designs[k - 1::n]
    failures = 0
    work = tempfile.mkdtemp(prefix='cfdg-compare-')
    for entry in a.designs:
        design, _, own = entry.partition(' -v ')
        name = os.path.basename(design)
        if not os.path.exists(design):  # a listed design that is not there is no pass
            print(f'{name}: no such design'); failures += 1; continue
        for v in (own.strip() or a.variations).split(','):
            if a.frames:
                why = compare_frames(a, design, v, work)
                if why:
                    print(f'{name} {v}: DIFFERENT: {why}'); failures += 1; break
                print(f'{name} {v}: equal ({a.frames} frames{", frames " + ",".join(map(str, a.frame)) if a.frame else ""})')
                continue
            ref_svg, got_svg = os.path.join(work, 'ref.svg'), os.path.join(work, 'got.svg')
            for f in (ref_svg, got_svg):
                if os.path.exists(f): os.remove(f)
            options = [x for d in a.define for x in ('-D', d)] + (['-c'] if a.crop else [])
            cmd = ['cfdg', '-q', '-V', '-s', str(a.size), '-v', v] + options
            if a.max_shapes: cmd += ['-m', str(a.max_shapes)]
            r = subprocess.run(cmd + [design, ref_svg], capture_output=True, text=True)
            if r.returncode != 0 or not os.path.exists(ref_svg):
                print(f'{name} {v}: cfdg failed ({r.returncode}): skipped'); continue
            cmd = [a.lcjit, 'cfdg', '-q', '-s', str(a.size), '-v', v] + options
            if a.max_shapes: cmd += ['-m', str(a.max_shapes)]
            g = subprocess.run(cmd + [design, got_svg], capture_output=True, text=True)
            if g.returncode != 0:
                print(f'{name} {v}: lcjit failed: {g.stderr.strip()[:300]}'); failures += 1; break
            ref, got = open(ref_svg).read(), open(got_svg).read()
            count = len(re.findall(r'<(?:rect|circle|path)\b|<use xlink:href="#TRIANGLE"', ref))
            why = None if same_text(ref, got) else compare(shapes(ref), shapes(got))
            if not why and size(ref) != size(got):
                why = f'picture {"x".join(size(got) or "?")}, cfdg {"x".join(size(ref) or "?")}'
            if why:
                print(f'{name} {v}: DIFFERENT: {why}'); failures += 1; break
            if a.image_diff:
                ref_png, got_png = os.path.join(work, 'ref.png'), os.path.join(work, 'got.png')
                limit = (['-m', str(a.max_shapes)] if a.max_shapes else []) + options
                subprocess.run(['cfdg', '-q', '-s', str(a.size), '-v', v] + limit + [design, ref_png], capture_output=True)
                g = subprocess.run([a.lcjit, 'cfdg', '-q', '-s', str(a.size), '-v', v] + limit + [design, got_png],
                                   capture_output=True, text=True)
                d = subprocess.run([a.image_diff, ref_png, got_png, '--exact'], capture_output=True, text=True)
                why = f'lcjit failed: {g.stderr.strip()[:300]}' if g.returncode else d.stdout.strip() if d.returncode else None
                if why:
                    print(f'{name} {v}: DIFFERENT PNG: {why}'); failures += 1; break
            print(f'{name} {v}: equal ({count} shapes{", PNG" if a.image_diff else ""})')
    return 1 if failures else 0

if __name__ == '__main__':
    sys.exit(main())
