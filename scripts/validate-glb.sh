#!/usr/bin/env bash
# Writes a GLB from every mesh in ../shared/meshes, the bundled bunny and tests/data (simplify
# --ratio 0.5, the default method; glTF inputs also with --flatten) and checks each with the Khronos glTF validator, installed
# from npm into a temporary folder. Exits 1 if the validator finds an error in any of them, 3
# if the validator cannot be installed (no network).
#
#   scripts/validate-glb.sh DYNLOD_BINARY
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 DYNLOD_BINARY" >&2; exit 2; }
bin=$(realpath "$1")
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if ! (cd "$work" && npm install --silent --no-audit --no-fund gltf-validator@2.0.0-dev.3.10 > /dev/null 2>&1); then
  echo "$0: could not install gltf-validator from npm" >&2
  exit 3
fi
inputs=("$root/examples/data/bun_zipper.ply.gz" "$root"/tests/data/*.glb "$root/tests/data/textured_quad.obj")
# The fuzz seeds' GLBs, the way exporters write them (a skinned, morphing torus among them).
seeds="$work/seeds"
if python3 "$root/fuzz/make_seeds.py" "$root/../shared/meshes" "$seeds" > /dev/null 2>&1; then
  inputs+=("$seeds"/load_gltf/*.glb)
fi
if [ -d "$root/../shared/meshes" ]; then
  inputs+=("$root"/../shared/meshes/{scans,gltf,bad}/*)
fi
outputs=()
for f in "${inputs[@]}"; do
  out="$work/$(basename "$f").glb"
  # Files dynlod refuses (the deliberately broken ones, compressed glTF) have nothing to check.
  if "$bin" simplify "$f" "$out" --ratio 0.5 > /dev/null 2>&1; then
    outputs+=("$out")
  fi
  # glTF inputs keep their scene by default; baked into one mesh with --flatten.
  if [[ $f == *.glb || $f == *.gltf ]]; then
    flat="$work/$(basename "$f").flat.glb"
    if "$bin" simplify "$f" "$flat" --ratio 0.5 --flatten > /dev/null 2>&1; then
      outputs+=("$flat")
    fi
  fi
done
echo "${#outputs[@]} GLB files written"
NODE_PATH="$work/node_modules" node "$root/scripts/validate-glb.js" "${outputs[@]}"
