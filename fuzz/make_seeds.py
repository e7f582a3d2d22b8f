#!/usr/bin/env python3
"""Seed corpora for the runtime_obj and simplify_obj fuzz targets.

    python3 fuzz/make_seeds.py [SHARED_MESHES_DIR]   # writes fuzz/corpus/{runtime_obj,simplify_obj}

Each seed is a small OBJ (a bumpy grid, a noisy sphere, a torus, a UV-seamed sphere with
normals, a hard-edged cube, a grid with two UV charts, and the small OBJ files of
../shared/meshes/bad when present) behind a few control prefixes: 16 bytes for runtime_obj
(options and a camera walk), 8 for simplify_obj (method, target, candidates, seed).
"""
import math, os, random, sys

def obj(vs, fs, vt=None, vn=None, corner=None):
    out = "".join("v %.5f %.5f %.5f\n" % v for v in vs)
    out += "".join("vt %.4f %.4f\n" % t for t in vt or [])
    out += "".join("vn %.4f %.4f %.4f\n" % n for n in vn or [])
    for f in fs:
        out += "f " + " ".join(corner(c) if corner else str(c + 1) for c in f) + "\n"
    return out

def meshes(shared):
    rnd = random.Random(7)
    m = {}
    w = 14
    vs = [(i / (w - 1), 0.15 * math.sin(i * 1.3) * math.cos(j * 0.9) + 0.03 * rnd.random(), j / (w - 1))
          for j in range(w) for i in range(w)]
    fs = []
    for j in range(w - 1):
        for i in range(w - 1):
            a = j * w + i; b = a + 1; c = a + w; d = c + 1
            fs += [(a, c, b), (b, c, d)] if (i + j) % 3 else [(a, c, d), (a, d, b)]
    m["grid"] = obj(vs, fs)
    s, t = 10, 14
    vs = [(0, 1, 0)]
    for i in range(1, s):
        th = math.pi * i / s
        for k in range(t):
            ph = 2 * math.pi * k / t; r = 1 + 0.08 * rnd.random()
            vs.append((r * math.sin(th) * math.cos(ph), r * math.cos(th), r * math.sin(th) * math.sin(ph)))
    vs.append((0, -1, 0)); last = len(vs) - 1
    fs = [(0, 1 + (k + 1) % t, 1 + k) for k in range(t)]
    for i in range(s - 2):
        for k in range(t):
            a = 1 + i * t + k; b = 1 + i * t + (k + 1) % t
            fs += [(a, b, b + t), (a, b + t, a + t)]
    fs += [(1 + (s - 2) * t + k, 1 + (s - 2) * t + (k + 1) % t, last) for k in range(t)]
    m["sphere"] = obj(vs, fs)
    n, q = 12, 8
    vs = [((1 + 0.3 * math.cos(2 * math.pi * j / q)) * math.cos(2 * math.pi * i / n), 0.3 * math.sin(2 * math.pi * j / q),
           (1 + 0.3 * math.cos(2 * math.pi * j / q)) * math.sin(2 * math.pi * i / n)) for i in range(n) for j in range(q)]
    fs = []
    for i in range(n):
        for j in range(q):
            a = i * q + j; b = ((i + 1) % n) * q + j; c = i * q + (j + 1) % q; d = ((i + 1) % n) * q + (j + 1) % q
            fs += [(a, c, b), (b, c, d)]
    m["torus"] = obj(vs, fs)
    # A sphere band with a UV seam (the first column's coordinates repeated at u = 1) and normals.
    s, t = 8, 12
    vs, vn = [], []
    for i in range(s + 1):
        th = math.pi * i / s
        for k in range(t):
            ph = 2 * math.pi * k / t; r = 1 + 0.05 * rnd.random()
            vs.append((r * math.sin(th) * math.cos(ph), r * math.cos(th), r * math.sin(th) * math.sin(ph)))
            vn.append((math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph)))
    vt = [(k / t, i / s) for i in range(s + 1) for k in range(t + 1)]
    fs = []
    for i in range(1, s - 1):
        for k in range(t):
            a, b, c, d = (i, k), (i, k + 1), (i + 1, k), (i + 1, k + 1)
            fs += [(a, b, d), (a, d, c)]
    pos = lambda p: p[0] * t + p[1] % t + 1
    m["uvsphere"] = obj(vs, fs, vt, vn, lambda p: "%d/%d/%d" % (pos(p), p[0] * (t + 1) + p[1] + 1, pos(p)))
    # A cube with a normal per side (hard edges) and one UV square per side.
    out = "".join("v %d %d %d\n" % (x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1))
    out += "vn -1 0 0\nvn 1 0 0\nvn 0 -1 0\nvn 0 1 0\nvn 0 0 -1\nvn 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    for (a, b, c, d), nn in [((0, 1, 3, 2), 1), ((4, 6, 7, 5), 2), ((0, 4, 5, 1), 3), ((2, 3, 7, 6), 4), ((0, 2, 6, 4), 5), ((1, 5, 7, 3), 6)]:
        out += "f %d/1/%d %d/2/%d %d/3/%d\n" % (a + 1, nn, b + 1, nn, c + 1, nn)
        out += "f %d/1/%d %d/3/%d %d/4/%d\n" % (a + 1, nn, c + 1, nn, d + 1, nn)
    m["cube"] = out
    # A bumpy grid in two UV charts, split down the middle.
    w = 12
    vs = [(i / (w - 1), 0.1 * math.sin(i) * math.cos(j * 1.7), j / (w - 1)) for j in range(w) for i in range(w)]
    vt = [(i / (w - 1) * 0.5, j / (w - 1)) for j in range(w) for i in range(w)]
    vt += [(0.5 + i / (w - 1) * 0.5, j / (w - 1)) for j in range(w) for i in range(w)]
    fs = []
    for j in range(w - 1):
        for i in range(w - 1):
            a = j * w + i; b = a + 1; c = a + w; d = c + 1; o = 0 if i < w // 2 else w * w
            fs += [((a, o), (c, o), (b, o)), ((b, o), (c, o), (d, o))]
    m["grid_uv"] = obj(vs, fs, vt, None, lambda p: "%d/%d" % (p[0] + 1, p[0] + 1 + p[1]))
    bad = os.path.join(shared, "bad")
    if os.path.isdir(bad):
        for f in sorted(os.listdir(bad)):
            path = os.path.join(bad, f)
            if f.endswith(".obj") and os.path.getsize(path) < 20000:
                m[f] = open(path).read()
    return m

RUNTIME = [bytes([0, 2, 0x4a, 30, 7, 10, 200, 64, 90, 40, 8, 250, 128, 3, 60, 100]),
           bytes([0x1f, 0x31, 0x13, 12, 15, 0, 128, 2, 255, 0, 1, 128, 128, 16, 200, 50]),
           bytes([6, 0x80, 0xff, 0, 3, 64, 64, 255, 10, 250, 5, 70, 33, 44, 55, 66]),
           bytes([9, 0x03, 0x20, 200, 11, 30, 30, 30, 20, 20, 20, 10, 10, 10, 5, 5])]
SIMPLIFY = [bytes([0, 0, 128, 5, 1, 0, 0, 0]), bytes([1, 1, 25, 5, 2, 0, 0, 0]), bytes([2, 2, 3, 0, 3, 30, 0, 0]),
            bytes([3, 3, 200, 9, 4, 0, 0, 0]), bytes([0, 4, 60, 5, 5, 0, 0, 0]), bytes([1, 0, 10, 2, 6, 0, 0, 0])]

if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    shared = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "shared", "meshes")
    for target, prefixes in [("runtime_obj", RUNTIME), ("simplify_obj", SIMPLIFY)]:
        out = os.path.join(here, "corpus", target)
        os.makedirs(out, exist_ok=True)
        for name, text in meshes(shared).items():
            for i, p in enumerate(prefixes):
                with open(os.path.join(out, "%s_%d" % (name, i)), "wb") as f:
                    f.write(p + text.encode())
    print("seeds written under", os.path.join(here, "corpus"))
