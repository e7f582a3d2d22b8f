#!/usr/bin/env bash
# Compresses the bundled bunny's GLB and every GLB in ../shared/meshes/gltf
# - with gltfpack 1.3 four ways: -c; -cc; -cc -ce khr (EXT_ and KHR_meshopt_compression, with
#   and without filters); -mi -cc (repeated meshes as EXT_mesh_gpu_instancing, their
#   transforms compressed); each decoded by meshoptimizer's WebAssembly decoder (the one web
#   engines use: scripts/meshopt-decompress.mjs);
# - with gltf-pipeline 4 (-d: KHR_draco_mesh_compression by Google's encoder), and with
#   gltf-transform 4's quantize then draco (Draco over KHR_mesh_quantization's integer
#   attributes), each decoded by Google's Draco decoder (npm draco3dgltf:
#   scripts/draco-decompress.mjs);
# and has tests/compressed_gltf.rs check that dynlod reads each compressed file as that
# decoder does. The tools come from npm into a temporary folder. Exits 3 if they cannot be
# installed (no network), non-zero on any difference.
#
#   scripts/compression-check.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if ! npm install --prefix "$work" --silent --no-audit --no-fund gltfpack@1.3.0 meshoptimizer@1.3.0 \
  gltf-pipeline@4.3.1 draco3dgltf@1.5.7 @gltf-transform/cli@4 > /dev/null 2>&1; then
  echo "$0: could not install gltfpack, meshoptimizer, gltf-pipeline, draco3dgltf and gltf-transform from npm" >&2
  exit 3
fi
pairs="$work/pairs"
mkdir "$pairs"
inputs=("$root/tests/data/bunny2k.glb")
if [ -d "$root/../shared/meshes/gltf" ]; then
  inputs+=("$root"/../shared/meshes/gltf/*.glb)
fi
tools="$work/node_modules"
for f in "${inputs[@]}"; do
  name=$(basename "$f" .glb)
  for way in "c:-c" "cc:-cc" "khr:-cc -ce khr" "mi:-mi -cc"; do
    out="$pairs/${name}_${way%%:*}.glb"
    # shellcheck disable=SC2086 # the options are words
    "$tools/.bin/gltfpack" -i "$f" -o "$out" ${way#*:} > /dev/null
    NODE_PATH="$tools" node "$root/scripts/meshopt-decompress.mjs" "$out" "${out%.glb}.ref.glb"
  done
  out="$pairs/${name}_draco.glb"
  "$tools/.bin/gltf-pipeline" -i "$f" -o "$out" -d > /dev/null
  NODE_PATH="$tools" node "$root/scripts/draco-decompress.mjs" "$out" "${out%.glb}.ref.glb"
  out="$pairs/${name}_qdraco.glb"
  "$tools/.bin/gltf-transform" quantize "$f" "$work/quantized.glb" > /dev/null 2>&1
  "$tools/.bin/gltf-transform" draco "$work/quantized.glb" "$out" > /dev/null 2>&1
  NODE_PATH="$tools" node "$root/scripts/draco-decompress.mjs" "$out" "${out%.glb}.ref.glb"
done
echo "$(ls "$pairs" | grep -vc '\.ref\.glb$') compressed files from ${#inputs[@]} GLBs"
cd "$root"
status=0
DYNLOD_COMPRESSED_PAIRS="$pairs" cargo test --release --test compressed_gltf -- --ignored --nocapture > "$work/log" 2>&1 ||
  status=$?
grep -E '^(/|test |thread|  left|  right|assertion)' "$work/log" || true
exit "$status"
