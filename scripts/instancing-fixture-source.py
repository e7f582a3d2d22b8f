# A small glTF scene with one mesh drawn by several nodes under different transforms (one
# mirrored, one stretched, all under a turned parent) and a second mesh drawn once: what
# gltfpack -mi turns into EXT_mesh_gpu_instancing. Writes source.gltf in the working directory.
import json, math, base64
from gltf_blob import Blob, sphere_triangles
rings, segs = 8, 12
pos, nor = [], []
for i in range(rings + 1):
    th = math.pi * i / rings
    for j in range(segs + 1):
        ph = 2 * math.pi * j / segs
        n = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
        # An egg, so that rotations show.
        pos.append((0.5 * n[0], 0.8 * n[1] + 0.1 * n[0], 0.4 * n[2])); nor.append(n)
idx = sphere_triangles(rings, segs)
box = [(x, y, z) for x in (-0.3, 0.3) for y in (0, 0.2) for z in (-0.3, 0.3)]
box_idx = [0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1, 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3]
blob = Blob(); add = blob.add
P = add('3f', pos, 'VEC3', 5126, 34962, True); N = add('3f', nor, 'VEC3', 5126, 34962)
I = add('H', idx, 'SCALAR', 5123, 34963)
BP = add('3f', box, 'VEC3', 5126, 34962, True); BI = add('H', box_idx, 'SCALAR', 5123, 34963)
def quat(axis, deg):
    s = math.sin(math.radians(deg) / 2); l = math.sqrt(sum(c * c for c in axis))
    return [axis[0] / l * s, axis[1] / l * s, axis[2] / l * s, math.cos(math.radians(deg) / 2)]
eggs = [
    {"translation": [0, 0, 0]},
    {"translation": [1.5, 0, 0], "rotation": quat((0, 1, 0), 90)},
    {"translation": [-1.5, 0.2, 0], "rotation": quat((1, 1, 0), 40), "scale": [0.5, 0.5, 0.5]},
    {"translation": [0, 0, 1.5], "scale": [1.2, 0.6, 1.0]},
    {"translation": [0, 0, -1.5], "rotation": quat((0, 0, 1), -30), "scale": [1.3, 1.3, 1.3]},
    {"translation": [3, 1, -2], "rotation": quat((0.2, 1, 0.3), 135), "scale": [0.8, 0.8, 0.8]},
    {"translation": [-3, 0, 1], "scale": [-1, 1, 1]},
]
nodes = [{"name": "group", "translation": [0.5, -0.25, 2], "rotation": quat((0, 1, 0), 25), "children": list(range(1, 9))}]
nodes += [dict(e, mesh=0, name="egg %d" % k) for k, e in enumerate(eggs)]
nodes += [{"mesh": 1, "name": "crate", "translation": [0, -1, 0]}]
doc = {
  "asset": {"version": "2.0", "generator": "dynlod scripts/make-instancing-fixtures.sh"},
  "scene": 0, "scenes": [{"nodes": [0]}], "nodes": nodes,
  "meshes": [{"name": "egg", "primitives": [{"attributes": {"POSITION": P, "NORMAL": N}, "indices": I}]},
             {"name": "crate", "primitives": [{"attributes": {"POSITION": BP}, "indices": BI}]}],
  "buffers": [{"byteLength": len(blob.data), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob.data).decode()}],
  "bufferViews": blob.views, "accessors": blob.accessors,
}
json.dump(doc, open('source.gltf', 'w'))
