#!/usr/bin/env python3
"""Seed corpora for the fuzz targets.

    python3 fuzz/make_seeds.py [SHARED_MESHES_DIR [OUT]]   # writes OUT/<target> (fuzz/corpus)

Each seed is a small mesh file behind a few control prefixes: 16 bytes for runtime (options
and a camera walk), 8 for simplify (method, target, candidates, seed). The files:

* OBJ: a bumpy grid, a noisy sphere, a torus, a UV-seamed sphere with normals, a hard-edged
  cube, a grid with two UV charts, and the small OBJ files of ../shared/meshes/bad when
  present;
* GLB, the way exporters write them: the sphere as two primitives with vertex arrays of their
  own (one with normals, one without) and two materials under a scaled, translated node; the
  torus drawn twice, once mirrored; the grid as triangle strips with 16-bit indices; the
  UV-seamed sphere with a texture (an embedded 1x1 PNG), and the same quantized as gltfpack
  writes it (KHR_mesh_quantization with a texture transform); the two-primitive sphere
  painted (8-bit RGBA colours and tangents on one primitive, float RGB colours and two UV
  sets on the other; valid by the Khronos glTF validator); the torus skinned to two joints,
  with weights, an `_ID` and a morph target, a skin and an animation;
* OBJ again: the bumpy grid with vertex colours (`v x y z r g b`).

The loader targets get the files alone: load_obj the OBJ seeds, load_gltf and gltf_scene
the GLB ones,
load_ply and load_off small files with colours, normals, UVs, polygons and strips (ascii
and binary), load_stl an ascii and a binary tetrahedron; load_obj, load_off and load_ply a
concave-capped prism, a ring written as one bridged polygon and a pentagram (the ear-clipping
path); an OBJ with points, a polyline and short faces; files with a byte-order mark, Latin-1 or UTF-16 text, a nameless `usemtl`, ascii STL
with a nameless or tabbed `solid` line and a binary STL whose header is a `solid` line; plus the shared files of each format under 20 kB when present.
"""
import json, math, os, random, struct, sys

PNG_1x1 = bytes.fromhex("89504e470d0a1a0a0000000d49484452000000010000000108060000001f15c489"
                        "0000000d4944415478da63f8ffff3f0005fe02fea7d6a4c40000000049454e44ae426082")

def glb(prims, nodes=None, materials=None, image=False, extensions=(), more=None):
    """A GLB of one mesh whose primitives are dicts: pos, idx, optional nrm and uv (one per
    position), `extra` attributes (semantic: (rows, type, struct format, component type,
    normalized)), mode (4 lists, 5 strips), material, 16-bit indices when `short`, and with
    `quant` its attributes quantized as gltfpack writes them (KHR_mesh_quantization:
    positions and UVs UNSIGNED_SHORT, not normalized, normals normalized BYTE; the caller's
    node and texture transform dequantise); `targets`, morph targets as dicts like `extra`.
    `more(doc, attribute, accessors, views)` adds to the document (skins, animations) before it is packed."""
    binary, views, accessors = bytearray(), [], []
    def view(data, target=None):
        views.append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(data)})
        if target:
            views[-1]["target"] = target
        binary.extend(data)
        binary.extend(b"\0" * (-len(binary) % 4))
        return len(views) - 1
    def attribute(rows, kind, fmt, ctype=5126, normalized=False):
        """A vertex attribute: rows packed by `fmt`, each padded to 4 bytes (integers, as
        KHR_mesh_quantization requires; FLOAT rows need none)."""
        pad = -struct.calcsize(fmt) % 4
        data = b"".join(struct.pack(fmt, *r) + b"\0" * pad for r in rows)
        a = {"bufferView": view(data, 34962), "componentType": ctype, "count": len(rows), "type": kind}
        if pad:
            views[-1]["byteStride"] = struct.calcsize(fmt) + pad
        if normalized:
            a["normalized"] = True
        if kind == "VEC3":
            a["min"] = [min(r[i] for r in rows) for i in range(3)]
            a["max"] = [max(r[i] for r in rows) for i in range(3)]
        accessors.append(a)
        return len(accessors) - 1
    out = []
    for p in prims:
        if p.get("quant"):
            attrs = {"POSITION": attribute(p["pos"], "VEC3", "<3H", 5123)}
            if p.get("nrm"):
                attrs["NORMAL"] = attribute([[round(127 * c) for c in n] for n in p["nrm"]], "VEC3", "<3b", 5120, True)
            if p.get("uv"):
                attrs["TEXCOORD_0"] = attribute(p["uv"], "VEC2", "<2H", 5123)
        else:
            attrs = {"POSITION": attribute(p["pos"], "VEC3", "<3f")}
            if p.get("nrm"):
                attrs["NORMAL"] = attribute(p["nrm"], "VEC3", "<3f")
            if p.get("uv"):
                attrs["TEXCOORD_0"] = attribute(p["uv"], "VEC2", "<2f")
        for name, (rows, kind, fmt, ctype, normalized) in p.get("extra", {}).items():
            attrs[name] = attribute(rows, kind, fmt, ctype, normalized)
        fmt, ctype = ("<%dH", 5123) if p.get("short") else ("<%dI", 5125)
        data = struct.pack(fmt % len(p["idx"]), *p["idx"])
        accessors.append({"bufferView": view(data, 34963), "componentType": ctype, "count": len(p["idx"]), "type": "SCALAR"})
        prim = {"attributes": attrs, "indices": len(accessors) - 1, "mode": p.get("mode", 4)}
        if p.get("targets"):
            prim["targets"] = [{name: attribute(*spec) for name, spec in t.items()} for t in p["targets"]]
        if "material" in p:
            prim["material"] = p["material"]
        out.append(prim)
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": list(range(len(nodes or [0])))}],
           "nodes": nodes or [{"mesh": 0}], "meshes": [{"name": "seed", "primitives": out}]}
    if materials:
        doc["materials"] = materials
    if extensions:
        doc["extensionsUsed"] = doc["extensionsRequired"] = list(extensions)
    if more:
        more(doc, attribute, accessors, views)
    if image:
        doc["images"] = [{"bufferView": view(PNG_1x1), "mimeType": "image/png"}]
        doc["textures"] = [{"source": 0}]
    doc["buffers"] = [{"byteLength": len(binary)}]
    doc["bufferViews"], doc["accessors"] = views, accessors
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    body = struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(binary), b"BIN\0") + bytes(binary)
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body

def own_vertices(vs, fs, attrs=()):
    """The faces `fs` with a vertex array of their own (as each glTF primitive has)."""
    used = sorted({v for f in fs for v in f})
    at = {v: i for i, v in enumerate(used)}
    return [[a[v] for v in used] for a in [vs, *attrs]], [at[v] for f in fs for v in f]

def obj(vs, fs, vt=None, vn=None, corner=None):
    out = "".join("v %.5f %.5f %.5f\n" % v for v in vs)
    out += "".join("vt %.4f %.4f\n" % t for t in vt or [])
    out += "".join("vn %.4f %.4f %.4f\n" % n for n in vn or [])
    for f in fs:
        out += "f " + " ".join(corner(c) if corner else str(c + 1) for c in f) + "\n"
    return out

def meshes(shared):
    """Seed files by name: OBJ text as str, GLB as bytes."""
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
    # The same grid at a survey's coordinates, to the millimetre (read relative to its centre:
    # src/mesh/origin.rs), and placed there by a glTF node.
    m["grid_far"] = "".join("v %.3f %.3f %.3f\n" % (512345 + v[0], 4123456 + v[1], 100 + v[2]) for v in vs) + \
        "".join("f %d %d %d\n" % tuple(c + 1 for c in f) for f in fs)
    m["grid_far.glb"] = glb([{"pos": vs, "idx": [c for f in fs for c in f]}],
                            [{"mesh": 0, "translation": [4123456, 512345, 100]}])
    m["grid_coloured"] = "".join("v %.5f %.5f %.5f %.3f %.3f %.3f\n" % (*v, v[0], v[2], (i % 5) / 4)
                                 for i, v in enumerate(vs)) + "".join("f %d %d %d\n" % tuple(c + 1 for c in f) for f in fs)
    # The same grid textured, with a UV slit cut in from the border and ending inside (a
    # seam's end, which the engines move): the faces just above the slit read copies of its
    # vertices' texture coordinates, opened by up to 0.05 in v.
    row, cut = w // 2, w // 2
    vt = [(v[0], v[2]) for v in vs] + [(i / (w - 1), row / (w - 1) + 0.05 * (cut - i) / cut) for i in range(cut)]
    above = lambda f: min(c // w for c in f) == row
    corner_of = lambda f: lambda c: "%d/%d" % (c + 1, (len(vs) + c % w + 1) if above(f) and c // w == row and c % w < cut else c + 1)
    m["grid_dart"] = obj(vs, [], vt=vt) + "".join("f " + " ".join(corner_of(f)(c) for c in f) + "\n" for f in fs)
    # The same grid as one triangle strip per row, joined by repeated indices.
    strip = []
    for j in range(w - 1):
        row = [x for i in range(w) for x in (j * w + i, (j + 1) * w + i)]
        strip += ([strip[-1], row[0]] if strip else []) + row
    m["grid_strips.glb"] = glb([{"pos": vs, "idx": strip, "mode": 5, "short": True}])
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
    top = [f for f in fs if sum(vs[v][1] for v in f) >= 0]
    (pa, na), ia = own_vertices(vs, top, [[tuple(c / math.dist(p, (0, 0, 0)) for c in p) for p in vs]])
    (pb,), ib = own_vertices(vs, [f for f in fs if sum(vs[v][1] for v in f) < 0])
    m["sphere_parts.glb"] = glb([{"pos": pa, "nrm": na, "idx": ia, "material": 0}, {"pos": pb, "idx": ib, "material": 1}],
                                [{"mesh": 0, "translation": [1, 2, 3], "scale": [2, 2, 2]}],
                                [{"name": "top"}, {"name": "bottom", "doubleSided": True}])
    # The same halves painted: 8-bit RGBA colours and tangents on top (one colour per band of
    # latitude, so neighbouring bands meet at colour seams once welded), float RGB colours
    # and two UV sets below.
    rgba = [[min(255, round(255 * abs(p[1]))), 40 * (i % 3), 200, 255 - i % 7] for i, p in enumerate(pa)]
    tangents = [[-p[2] / math.hypot(p[0], p[2]), 0.0, p[0] / math.hypot(p[0], p[2]), 1.0 if i % 2 else -1.0]
                if math.hypot(p[0], p[2]) > 0 else [1.0, 0.0, 0.0, 1.0] for i, p in enumerate(pa)]
    rgb = [[min(1.0, max(0.0, 0.5 + 0.5 * p[0])), 0.25, min(1.0, max(0.0, 0.5 - 0.5 * p[2]))] for p in pb]
    uv0 = [[0.5 + 0.5 * p[0], 0.5 + 0.5 * p[1]] for p in pb]
    uv1 = [[0.5 + 0.5 * p[0], 0.5 + 0.5 * p[2]] for p in pb]
    m["sphere_painted.glb"] = glb(
        [{"pos": pa, "nrm": na, "idx": ia, "extra": {"COLOR_0": (rgba, "VEC4", "<4B", 5121, True),
                                                       "TANGENT": (tangents, "VEC4", "<4f", 5126, False)}},
         {"pos": pb, "uv": uv0, "idx": ib, "extra": {"COLOR_0": (rgb, "VEC3", "<3f", 5126, False),
                                          "TEXCOORD_1": (uv1, "VEC2", "<2f", 5126, False)}}],
        [{"mesh": 0}, {"mesh": 0, "scale": [1, -1, 1], "translation": [0, 0, 4]}])
    n, q = 12, 8
    vs = [((1 + 0.3 * math.cos(2 * math.pi * j / q)) * math.cos(2 * math.pi * i / n), 0.3 * math.sin(2 * math.pi * j / q),
           (1 + 0.3 * math.cos(2 * math.pi * j / q)) * math.sin(2 * math.pi * i / n)) for i in range(n) for j in range(q)]
    fs = []
    for i in range(n):
        for j in range(q):
            a = i * q + j; b = ((i + 1) % n) * q + j; c = i * q + (j + 1) % q; d = ((i + 1) % n) * q + (j + 1) % q
            fs += [(a, c, b), (b, c, d)]
    m["torus"] = obj(vs, fs)
    (pt,), it = own_vertices(vs, fs)
    # The torus skinned to two joints and morphing, as a scene-keeping load reads it: joints
    # (UNSIGNED_BYTE), weights (FLOAT), an application-specific _ID (UNSIGNED_SHORT) and one
    # morph target; a skin and an animation around them.
    def skin_and_animation(doc, attribute, accessors, views):
        doc["nodes"] += [{"name": "root", "children": [2]}, {"name": "arm", "translation": [1, 0, 0]}]
        doc["nodes"][0]["skin"] = 0
        doc["scenes"][0]["nodes"] = [0, 1]
        identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
        doc["skins"] = [{"joints": [1, 2], "inverseBindMatrices": attribute([identity, identity], "MAT4", "<16f")}]
        times = attribute([[0.0], [1.0]], "SCALAR", "<f")
        accessors[times]["min"], accessors[times]["max"] = [0.0], [1.0]
        rotations = attribute([[0, 0, 0, 1], [0, 0, 0.6, 0.8]], "VEC4", "<4f")
        doc["animations"] = [{"channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}}],
                              "samplers": [{"input": times, "output": rotations}]}]
        doc["meshes"][0]["weights"] = [0.5]
        for a in (doc["skins"][0]["inverseBindMatrices"], times, rotations):
            del views[accessors[a]["bufferView"]]["target"]  # not vertex data
    joints = [[int(p[0] > 0), 1 - int(p[0] > 0), 0, 0] for p in pt]
    weights = [[0.25 + 0.5 * (0.5 + 0.5 * p[1] / 0.3), 0.75 - 0.5 * (0.5 + 0.5 * p[1] / 0.3), 0.0, 0.0] for p in pt]
    m["torus_skinned.glb"] = glb(
        [{"pos": pt, "idx": it, "short": True,
          "extra": {"JOINTS_0": (joints, "VEC4", "<4B", 5121, False), "WEIGHTS_0": (weights, "VEC4", "<4f", 5126, False),
                    "_ID": ([[i] for i in range(len(pt))], "SCALAR", "<H", 5123, False)},
          "targets": [{"POSITION": ([[0.0, 0.1 * p[0], 0.0] for p in pt], "VEC3", "<3f", 5126, False)}]}],
        more=skin_and_animation)
    m["torus_twice.glb"] = glb([{"pos": pt, "idx": it}], [{"mesh": 0}, {"mesh": 0, "scale": [-1, 1, 1], "translation": [3, 0, 0]}])
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
    # One glTF vertex per (position, UV) pair, as exporters split a seam.
    corners = sorted({(i, k) for f in fs for (i, k) in f})
    at = {c: n for n, c in enumerate(corners)}
    m["uvsphere_textured.glb"] = glb([{"pos": [vs[pos(c) - 1] for c in corners], "nrm": [vn[pos(c) - 1] for c in corners],
                                       "uv": [vt[c[0] * (t + 1) + c[1]] for c in corners],
                                       "idx": [at[c] for f in fs for c in f], "material": 0}],
                                     materials=[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], image=True)
    # The same, quantized as gltfpack does by default: positions on a 16-bit grid over the
    # bounding box (the node's scale and translation dequantise), UVs on a 1024 grid (the
    # material's texture transform scales them back), normals in 8 bits.
    lo = [min(v[i] for v in vs) for i in range(3)]
    ext = max(max(v[i] for v in vs) - lo[i] for i in range(3))
    grid = lambda p: [round((p[i] - lo[i]) / ext * 65535) for i in range(3)]
    m["uvsphere_quantized.glb"] = glb(
        [{"pos": [grid(vs[pos(c) - 1]) for c in corners], "nrm": [vn[pos(c) - 1] for c in corners],
          "uv": [[round(1024 * x) for x in vt[c[0] * (t + 1) + c[1]]] for c in corners],
          "idx": [at[c] for f in fs for c in f], "material": 0, "quant": True}],
        [{"mesh": 0, "translation": lo, "scale": [ext / 65535] * 3}],
        [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {
            "KHR_texture_transform": {"scale": [1 / 1024, 1 / 1024]}}}}}],
        image=True, extensions=["KHR_mesh_quantization", "KHR_texture_transform"])
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

def loader_seeds(shared):
    """Seed files of the loader targets, by target and name."""
    tet_v = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    tet_f = [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)]
    ply_head = "ply\nformat %s 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    colour = "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
    faces = "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
    rgba = [(255, 0, 0, 255), (0, 255, 0, 128), (0, 0, 255, 255), (10, 20, 30, 0)]
    ply = {
        "tet_colour.ply": (ply_head % "ascii" + colour + faces
                           + "".join("%d %d %d %d %d %d %d\n" % (*v, *c) for v, c in zip(tet_v, rgba))
                           + "".join("3 %d %d %d\n" % f for f in tet_f)).encode(),
        "tet_colour_binary.ply": (ply_head % "binary_little_endian" + colour + faces).encode()
            + b"".join(struct.pack("<3f4B", *v, *c) for v, c in zip(tet_v, rgba))
            + b"".join(struct.pack("<B3i", 3, *f) for f in tet_f),
        "tet_normals_uv_float_colour.ply": (ply_head % "ascii" + "property float nx\nproperty float ny\nproperty float nz\n"
            "property float u\nproperty float v\nproperty float diffuse_red\nproperty float diffuse_green\n"
            "property float diffuse_blue\n" + faces
            + "".join("%d %d %d 0 0 1 %d %d 0.5 0.25 1\n" % (*v, v[0], v[1]) for v in tet_v)
            + "".join("3 %d %d %d\n" % f for f in tet_f)).encode(),
        "strips.ply": (ply_head % "ascii" + "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
                       + "".join("%d %d %d\n" % v for v in tet_v) + "6 0 1 2 3 -1 0\n").encode(),
    }
    off = {
        "tet_coff_bytes.off": ("COFF\n4 4 0\n" + "".join("%d %d %d %d %d %d %d\n" % (*v, *c) for v, c in zip(tet_v, rgba))
                               + "".join("3 %d %d %d 255 255 255\n" % f for f in tet_f)).encode(),
        "tet_coff_unit.off": ("COFF\n4 4 0\n" + "".join("%d %d %d 1 0.5 0 1\n" % v for v in tet_v)
                              + "".join("3 %d %d %d\n" % f for f in tet_f)).encode(),
        "quad_stoff.off": b"STOFF\n4 1 0\n0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n",
    }
    normal = lambda f: (0.0, 0.0, 1.0)
    stl_ascii = "solid t\n" + "".join(
        "facet normal 0 0 1\nouter loop\n" + "".join("vertex %d %d %d\n" % tet_v[i] for i in f) + "endloop\nendfacet\n"
        for f in tet_f) + "endsolid t\n"
    stl_binary = b"\0" * 80 + struct.pack("<I", len(tet_f)) + b"".join(
        struct.pack("<3f", *normal(f)) + b"".join(struct.pack("<3f", *tet_v[i]) for i in f) + b"\0\0" for f in tet_f)
    # Concave polygons (an L-shaped prism whose top cap folds as a fan), a ring written as one
    # polygon with a bridge, and a pentagram (crosses itself): the ear-clipping path.
    ell = [(1, 2), (0, 2), (0, 0), (2, 0), (2, 1), (1, 1)]
    poly_v = [(x, y, z) for z in (0, 1) for x, y in ell]
    poly_f = [list(range(5, -1, -1)), list(range(6, 12))] + [[i, (i + 1) % 6, (i + 1) % 6 + 6, i + 6] for i in range(6)]
    ring_v = [(2 * math.cos(math.tau * i / 8), 2 * math.sin(math.tau * i / 8), 0) for i in range(8)] + [
        (math.cos(math.tau * i / 4), math.sin(math.tau * i / 4), 0) for i in range(4)]
    ring_f = [list(range(8)) + [0, 8, 11, 10, 9, 8]]
    star_v = [(math.cos(math.tau * 2 * i / 5), math.sin(math.tau * 2 * i / 5), 0) for i in range(5)]
    star_f = [list(range(5))]
    def off_text(vs, fs):
        return ("OFF\n%d %d 0\n" % (len(vs), len(fs)) + "".join("%g %g %g\n" % v for v in vs)
                + "".join("%d %s\n" % (len(f), " ".join(map(str, f))) for f in fs))
    def ply_text(vs, fs):
        return (ply_head.replace("vertex 4", "vertex %d" % len(vs)) % "ascii"
                + "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(fs)
                + off_text(vs, fs).split("\n", 2)[2])
    def obj_text(vs, fs):
        return "".join("v %g %g %g\n" % v for v in vs) + "".join("f %s\n" % " ".join(str(i + 1) for i in f) for f in fs)
    seeds = {"load_ply": ply, "load_off": off, "load_stl": {"tet.stl": stl_ascii.encode(), "tet_binary.stl": stl_binary},
             "load_obj": {}, "load_gltf": {}, "gltf_scene": {}}
    # Encodings and headers as exporters write them (`text.rs`, `stl.rs`).
    bom = b"\xef\xbb\xbf"
    tet_obj = "o Terrainda\u00e6k\nusemtl \n" + obj_text(tet_v, [list(f) for f in tet_f])
    seeds["load_obj"]["lines.obj"] = (obj_text(tet_v, [list(tet_f[0])]) + "l 1 2 3 4 1\np 4\nf 1 2\nf\n").encode()
    seeds["load_obj"].update({"bom.obj": bom + tet_obj.encode(), "latin1.obj": tet_obj.encode("latin-1"),
                              "utf16.obj": tet_obj.encode("utf-16")})
    seeds["load_off"]["bom.off"] = bom + off_text(tet_v, tet_f).encode()
    seeds["load_ply"]["bom.ply"] = bom + ply["tet_colour.ply"]
    # MeshLab's textured PLY: texture coordinates per face corner, a texture number per face.
    seeds["load_ply"]["wedges.ply"] = (
        "ply\nformat ascii 1.0\ncomment TextureFile a.png\ncomment TextureFile b.png\nelement vertex 4\n"
        "property float x\nproperty float y\nproperty float z\nelement face 2\n"
        "property list uchar int vertex_indices\nproperty list uchar float texcoord\nproperty int texnumber\n"
        "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2 6 0 0 1 0 1 1 1\n3 0 2 3 6 0.5 0.5 1 1 0 1 0\n").encode()
    # Blender 2.4x's bare credit line and a blank line in the header (ply_header.rs).
    seeds["load_ply"]["blender247.ply"] = ply["tet_colour_binary.ply"].replace(
        b"1.0\n", b"1.0\nCreated by Blender3D 247 - www.blender.org, source file: \n\n", 1)
    seeds["load_stl"].update({"nameless.stl": stl_ascii.replace("solid t", "solid", 1).encode(),
                              "tabbed.stl": bom + stl_ascii.replace("solid t", "solid\tt", 1).encode(),
                              "solid_binary.stl": b"solid binary\n" + stl_binary[13:],
                              "upper.stl": stl_ascii.upper().encode(),
                              "latin1.stl": stl_ascii.replace("solid t", "solid \u00c6ble", 1).encode("latin-1")})
    for name, vs, fs in [("lprism", poly_v, poly_f), ("ring", ring_v, ring_f), ("star", star_v, star_f)]:
        seeds["load_obj"][name + ".obj"] = obj_text(vs, fs).encode()
        seeds["load_off"][name + ".off"] = off_text(vs, fs).encode()
        seeds["load_ply"][name + ".ply"] = ply_text(vs, fs).encode()
    for name, file in meshes(shared).items():
        seeds["load_gltf" if isinstance(file, bytes) else "load_obj"][name] = file if isinstance(file, bytes) else file.encode()
        if isinstance(file, bytes):
            seeds["gltf_scene"][name] = file
    # POSITION accessors without their min and max (read and recorded: gltf.rs `validate`),
    # the keys renamed so that the chunk lengths stay.
    twice = seeds["load_gltf"].get("torus_twice.glb")
    if twice:
        seeds["load_gltf"]["unbounded.glb"] = twice.replace(b'"min":', b'"nim":').replace(b'"max":', b'"xam":')
        # A scene without `nodes` (optional in glTF 2.0; gltf_parse.rs patches it in).
        seeds["load_gltf"]["nodeless_scene.glb"] = twice.replace(b'"scenes":[{"nodes"', b'"scenes":[{"nodez"', 1)
    # gltfpack's meshopt compression, every mode and filter, and its EXT_mesh_gpu_instancing,
    # plain and compressed; gltf-pipeline's Draco, both encoders (tests/data/README.md).
    data = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data")
    for name in ("meshopt_ext.glb", "meshopt_khr.glb", "bunny2k_gltfpack_c.glb", "instancing_gltfpack.glb",
                 "instancing_gltfpack_c.glb", "draco.glb", "draco_sequential.glb"):
        if os.path.exists(os.path.join(data, name)):
            seeds["load_gltf"][name] = seeds["gltf_scene"][name] = open(os.path.join(data, name), "rb").read()
    for target, ext in [("load_ply", ".ply"), ("load_off", ".off"), ("load_stl", ".stl")]:
        for sub in ("scans", "bad"):
            d = os.path.join(shared, sub)
            if os.path.isdir(d):
                for f in sorted(os.listdir(d)):
                    if f.endswith(ext) and os.path.getsize(os.path.join(d, f)) < 20000:
                        seeds[target][f] = open(os.path.join(d, f), "rb").read()
    return seeds

RUNTIME = [bytes([0, 2, 0x4a, 30, 7, 10, 200, 64, 90, 40, 8, 250, 128, 3, 60, 100]),
           bytes([0x1f, 0x31, 0x13, 12, 15, 0, 128, 2, 255, 0, 1, 128, 128, 16, 200, 50]),
           bytes([6, 0x80, 0xff, 0, 3, 64, 64, 255, 10, 250, 5, 70, 33, 44, 55, 66]),
           bytes([9, 0x03, 0x20, 200, 11, 30, 30, 30, 20, 20, 20, 10, 10, 10, 5, 5])]
SIMPLIFY = [bytes([0, 0, 128, 5, 1, 0, 0, 0]), bytes([1, 1, 25, 5, 2, 0, 0, 0]), bytes([2, 2, 3, 0, 3, 30, 0, 0]),
            bytes([3, 3, 200, 9, 4, 0, 0, 0]), bytes([0, 4, 60, 5, 5, 0, 0, 0]), bytes([1, 0, 10, 2, 6, 0, 0, 0]),
            # Attributes weighed (ctl[0] & 4): qem, every kind at 1; qem-batch under a bound,
            # normals and colours at 4.
            bytes([4, 1, 30, 5, 7, 0, 0x0f, 16]), bytes([6, 3, 60, 3, 8, 40, 0x05, 64])]

if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    shared = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "shared", "meshes")
    corpus = sys.argv[2] if len(sys.argv) > 2 else os.path.join(here, "corpus")
    for target, prefixes in [("runtime", RUNTIME), ("simplify", SIMPLIFY)]:
        out = os.path.join(corpus, target)
        os.makedirs(out, exist_ok=True)
        for name, file in meshes(shared).items():
            for i, p in enumerate(prefixes):
                with open(os.path.join(out, "%s_%d" % (name, i)), "wb") as f:
                    f.write(p + (file if isinstance(file, bytes) else file.encode()))
    for target, files in loader_seeds(shared).items():
        out = os.path.join(corpus, target)
        os.makedirs(out, exist_ok=True)
        for name, data in files.items():
            with open(os.path.join(out, name), "wb") as f:
                f.write(data)
    print("seeds written under", corpus)
