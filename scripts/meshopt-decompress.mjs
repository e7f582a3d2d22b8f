// Writes an uncompressed copy of a GLB compressed with EXT_ or KHR_meshopt_compression,
// decoded by the decoder web engines use (npm package `meshoptimizer`, `MeshoptDecoder`:
// meshoptimizer's C decoder built to WebAssembly, as three.js and Babylon.js load it), for
// checking dynlod's decoding (its buffer views, strides, modes and filters) against.
// The package's pure-JavaScript reference decoder differs from the C one by a unit in the
// last place on some octahedral normals, so it is not the one used.
// Usage: node meshopt-decompress.mjs IN.glb OUT.glb   (NODE_PATH must reach `meshoptimizer`)
import fs from 'fs';
import { createRequire } from 'module';
import { pathToFileURL } from 'url';
const require = createRequire(import.meta.url);
const main = require.resolve('meshoptimizer', { paths: (process.env.NODE_PATH || '').split(':') });
const { MeshoptDecoder } = await import(pathToFileURL(main));
await MeshoptDecoder.ready;

const names = ['EXT_meshopt_compression', 'KHR_meshopt_compression'];
const input = fs.readFileSync(process.argv[2]);
const jsonLength = input.readUInt32LE(12);
const json = JSON.parse(input.subarray(20, 20 + jsonLength).toString());
const bin = input.subarray(20 + jsonLength + 8);
const buffers = json.buffers.map((b, i) => (i === 0 && b.uri === undefined ? bin : null));

const parts = [];
let length = 0;
for (const view of json.bufferViews) {
  const ext = names.map((n) => (view.extensions || {})[n]).find((e) => e);
  let bytes;
  if (ext) {
    bytes = new Uint8Array(ext.count * ext.byteStride);
    const source = buffers[ext.buffer].subarray(ext.byteOffset || 0, (ext.byteOffset || 0) + ext.byteLength);
    MeshoptDecoder.decodeGltfBuffer(bytes, ext.count, ext.byteStride, source, ext.mode, ext.filter);
    for (const n of names) delete view.extensions[n];
    if (Object.keys(view.extensions).length === 0) delete view.extensions;
  } else {
    bytes = buffers[view.buffer].subarray(view.byteOffset || 0, (view.byteOffset || 0) + view.byteLength);
  }
  const padding = (4 - (length % 4)) % 4;
  if (padding) parts.push(new Uint8Array(padding));
  length += padding;
  view.buffer = 0;
  view.byteOffset = length;
  parts.push(bytes);
  length += bytes.length;
}
const padding = (4 - (length % 4)) % 4;
parts.push(new Uint8Array(padding));
length += padding;
json.buffers = [{ byteLength: length }];
for (const key of ['extensionsUsed', 'extensionsRequired']) {
  if (json[key]) json[key] = json[key].filter((e) => !names.includes(e));
  if (json[key] && json[key].length === 0) delete json[key];
}
let text = Buffer.from(JSON.stringify(json));
text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
const chunk = (type, data) => {
  const header = Buffer.alloc(8);
  header.writeUInt32LE(data.length, 0);
  header.write(type, 4, 'ascii');
  return Buffer.concat([header, data]);
};
const body = Buffer.concat([chunk('JSON', text), chunk('BIN\0', Buffer.concat(parts.map((p) => Buffer.from(p))))]);
const head = Buffer.alloc(12);
head.write('glTF', 0, 'ascii');
head.writeUInt32LE(2, 4);
head.writeUInt32LE(12 + body.length, 8);
fs.writeFileSync(process.argv[3], Buffer.concat([head, body]));
