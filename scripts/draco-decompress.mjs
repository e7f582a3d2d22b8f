// Writes an uncompressed copy of a GLB whose primitives are compressed with
// KHR_draco_mesh_compression, decoded by Google's Draco decoder (npm package `draco3dgltf`:
// the C++ decoder built to WebAssembly, as three.js and Babylon.js load it), for checking
// dynlod's decoding (`src/io/gltf_draco.rs`, the pure Rust `draco-core`) against. Each
// attribute is read as its accessor's component type (Draco's GetAttributeDataArrayForAllPoints
// converting by value), the faces as the indices accessor's type.
// Usage: node draco-decompress.mjs IN.glb OUT.glb   (NODE_PATH must reach `draco3dgltf`)
import fs from 'fs';
import { createRequire } from 'module';
const require = createRequire(import.meta.url);
const draco3d = require(require.resolve('draco3dgltf', { paths: (process.env.NODE_PATH || '').split(':') }));
const draco = await draco3d.createDecoderModule({});

const NAME = 'KHR_draco_mesh_compression';
const input = fs.readFileSync(process.argv[2]);
const jsonLength = input.readUInt32LE(12);
const json = JSON.parse(input.subarray(20, 20 + jsonLength).toString());
const bin = input.subarray(20 + jsonLength + 8);
const types = {
  5120: [Int8Array, draco.DT_INT8], 5121: [Uint8Array, draco.DT_UINT8], 5122: [Int16Array, draco.DT_INT16],
  5123: [Uint16Array, draco.DT_UINT16], 5125: [Uint32Array, draco.DT_UINT32], 5126: [Float32Array, draco.DT_FLOAT32],
};
const width = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 };

// Every view of the source stays as it is; the decoded values go after them.
const parts = [bin];
let length = bin.length;
function addView(bytes) {
  while (length % 4) { parts.push(Buffer.alloc(1)); length += 1; }
  json.bufferViews.push({ buffer: 0, byteOffset: length, byteLength: bytes.byteLength });
  parts.push(Buffer.from(bytes.buffer, bytes.byteOffset, bytes.byteLength));
  length += bytes.byteLength;
  return json.bufferViews.length - 1;
}

for (const mesh of json.meshes || []) {
  for (const prim of mesh.primitives) {
    const ext = (prim.extensions || {})[NAME];
    if (!ext) continue;
    const view = json.bufferViews[ext.bufferView];
    const stream = bin.subarray(view.byteOffset || 0, (view.byteOffset || 0) + view.byteLength);
    const decoder = new draco.Decoder();
    const dmesh = new draco.Mesh();
    const status = decoder.DecodeArrayToMesh(stream, stream.length, dmesh);
    if (!status.ok()) throw new Error(`${process.argv[2]}: ${status.error_msg()}`);
    const points = dmesh.num_points();
    for (const [semantic, id] of Object.entries(ext.attributes)) {
      const accessor = json.accessors[prim.attributes[semantic]];
      const [Array_, dt] = types[accessor.componentType];
      const n = points * width[accessor.type];
      const ptr = draco._malloc(n * Array_.BYTES_PER_ELEMENT);
      decoder.GetAttributeDataArrayForAllPoints(dmesh, decoder.GetAttributeByUniqueId(dmesh, id), dt,
        n * Array_.BYTES_PER_ELEMENT, ptr);
      const values = new Array_(draco.HEAPF32.buffer, ptr, n).slice();
      draco._free(ptr);
      accessor.bufferView = addView(values);
    }
    const accessor = json.accessors[prim.indices];
    const n = dmesh.num_faces() * 3;
    const ptr = draco._malloc(n * 4);
    decoder.GetTrianglesUInt32Array(dmesh, n * 4, ptr);
    const faces = new Uint32Array(draco.HEAPF32.buffer, ptr, n).slice();
    draco._free(ptr);
    accessor.bufferView = addView(accessor.componentType === 5125 ? faces
      : accessor.componentType === 5123 ? Uint16Array.from(faces) : Uint8Array.from(faces));
    draco.destroy(dmesh);
    draco.destroy(decoder);
    delete prim.extensions[NAME];
  }
}
for (const key of ['extensionsUsed', 'extensionsRequired']) {
  if (json[key]) json[key] = json[key].filter((e) => e !== NAME);
  if (json[key] && json[key].length === 0) delete json[key];
}
while (length % 4) { parts.push(Buffer.alloc(1)); length += 1; }
json.buffers[0].byteLength = length;
let text = Buffer.from(JSON.stringify(json));
text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
const header = Buffer.alloc(20);
header.write('glTF', 0);
header.writeUInt32LE(2, 4);
header.writeUInt32LE(20 + text.length + 8 + length, 8);
header.writeUInt32LE(text.length, 12);
header.write('JSON', 16);
const binHeader = Buffer.alloc(8);
binHeader.writeUInt32LE(length, 0);
binHeader.write('BIN\0', 4);
fs.writeFileSync(process.argv[3], Buffer.concat([header, text, binHeader, ...parts]));
