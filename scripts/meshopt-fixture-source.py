# A small glTF with what gltfpack's compression has a filter for: normals, tangents,
# colours, texture coordinates, a node animation (translation, rotation, scale), and lines.
import json, math, base64
from gltf_blob import Blob, sphere_triangles
rings, segs = 10, 16
pos, nor, uv, col, tan = [], [], [], [], []
for i in range(rings + 1):
    th = math.pi * i / rings
    for j in range(segs + 1):
        ph = 2 * math.pi * j / segs
        n = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
        pos.append(tuple(0.7 * c for c in n)); nor.append(n)
        uv.append((j / segs, i / rings))
        col.append((0.5 + 0.5 * n[0], 0.5 + 0.5 * n[1], 0.5 + 0.5 * n[2], 0.25 + 0.75 * i / rings))
        tan.append((-math.sin(ph), 0.0, math.cos(ph), 1.0))
idx = sphere_triangles(rings, segs)
line = [k for j in range(segs) for k in (j, j + 1)]
times = [k / 4 for k in range(9)]
rot = [(0, math.sin(t * 0.7), 0, math.cos(t * 0.7)) for t in times]
tra = [(math.sin(t), 0.1 * t, 0) for t in times]
sca = [(1 + 0.1 * t, 1, 1 - 0.05 * t) for t in times]
blob = Blob(); add = blob.add
P = add('3f', pos, 'VEC3', 5126, 34962, True); N = add('3f', nor, 'VEC3', 5126, 34962)
T = add('4f', tan, 'VEC4', 5126, 34962); U = add('2f', uv, 'VEC2', 5126, 34962); C = add('4f', col, 'VEC4', 5126, 34962)
I = add('H', idx, 'SCALAR', 5123, 34963); L = add('H', line, 'SCALAR', 5123, 34963)
tm = add('f', times, 'SCALAR', 5126); blob.accessors[tm]["min"] = [0]; blob.accessors[tm]["max"] = [times[-1]]
R = add('4f', rot, 'VEC4', 5126); TT = add('3f', tra, 'VEC3', 5126); S = add('3f', sca, 'VEC3', 5126)
attrs = {"POSITION": P, "NORMAL": N, "TANGENT": T, "TEXCOORD_0": U, "COLOR_0": C}
doc = {
  "asset": {"version": "2.0", "generator": "dynlod scripts/make-meshopt-fixtures.sh"},
  "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "ball"}],
  "meshes": [{"primitives": [{"attributes": attrs, "indices": I, "material": 0},
                             {"attributes": {"POSITION": P}, "indices": L, "mode": 1}]}],
  "materials": [{"name": "striped", "normalTexture": {"index": 0}, "alphaMode": "BLEND"}],
  "textures": [{"source": 0}],
  "images": [{"uri": "data:image/png;base64," + base64.b64encode(bytes.fromhex(
      "89504e470d0a1a0a0000000d4948445200000001000000010802000000907753de0000000c4944415408d763f8ffbf1f0005fe02fe0dcc59c70000000049454e44ae426082")).decode()}],
  "animations": [{"channels": [{"sampler": 0, "target": {"node": 0, "path": "rotation"}},
                               {"sampler": 1, "target": {"node": 0, "path": "translation"}},
                               {"sampler": 2, "target": {"node": 0, "path": "scale"}}],
                  "samplers": [{"input": tm, "output": R}, {"input": tm, "output": TT}, {"input": tm, "output": S}]}],
  "buffers": [{"byteLength": len(blob.data), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob.data).decode()}],
  "bufferViews": blob.views, "accessors": blob.accessors,
}
json.dump(doc, open('source.gltf', 'w'))  # in the working directory
