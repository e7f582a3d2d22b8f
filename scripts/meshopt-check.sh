#!/usr/bin/env bash
# Compresses the bundled bunny's GLB and every GLB in ../shared/meshes/gltf with gltfpack 1.3
# four ways (-c; -cc; -cc -ce khr, i.e. EXT_ and KHR_meshopt_compression with and without
# filters; and -mi -cc, repeated meshes as EXT_mesh_gpu_instancing with their transforms
# compressed), decodes each with meshoptimizer's WebAssembly decoder (the one web engines use:
# scripts/meshopt-decompress.mjs), and has tests/meshopt_compression.rs check that dynlod
# reads each compressed file as that decoder does. Both tools come from npm into a temporary
# folder. Exits 3 if they cannot be installed (no network), non-zero on any difference.
#
#   scripts/meshopt-check.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if ! npm install --prefix "$work" --silent --no-audit --no-fund gltfpack@1.3.0 meshoptimizer@1.3.0 > /dev/null 2>&1; then
  echo "$0: could not install gltfpack and meshoptimizer from npm" >&2
  exit 3
fi
pairs="$work/pairs"
mkdir "$pairs"
inputs=("$root/tests/data/bunny2k.glb")
if [ -d "$root/../shared/meshes/gltf" ]; then
  inputs+=("$root"/../shared/meshes/gltf/*.glb)
fi
for f in "${inputs[@]}"; do
  name=$(basename "$f" .glb)
  for way in "c:-c" "cc:-cc" "khr:-cc -ce khr" "mi:-mi -cc"; do
    out="$pairs/${name}_${way%%:*}.glb"
    # shellcheck disable=SC2086 # the options are words
    "$work/node_modules/.bin/gltfpack" -i "$f" -o "$out" ${way#*:} > /dev/null
    NODE_PATH="$work/node_modules" node "$root/scripts/meshopt-decompress.mjs" "$out" "${out%.glb}.ref.glb"
  done
done
echo "$(ls "$pairs" | grep -vc '\.ref\.glb$') compressed files from ${#inputs[@]} GLBs"
cd "$root"
status=0
DYNLOD_MESHOPT_PAIRS="$pairs" cargo test --release --test meshopt_compression -- --ignored --nocapture > "$work/log" 2>&1 ||
  status=$?
grep -E '^(/|test |thread|  left|  right|assertion)' "$work/log" || true
exit "$status"
