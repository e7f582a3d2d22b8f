#!/usr/bin/env bash
# Remakes tests/data/draco{,_sequential}.glb and their decoded references (tests/data/README.md):
# the small glTF of scripts/meshopt-fixture-source.py compressed by gltf-pipeline 4 with
# KHR_draco_mesh_compression (Google's encoder, npm draco3d), at its default level
# (EdgeBreaker, quantised) and at level 0 without position quantisation (sequential), each
# decoded by Google's decoder (npm draco3dgltf, scripts/draco-decompress.mjs). Needs node and
# npm (the npm registry).
set -euo pipefail
cd "$(dirname "$0")/.."
tools=$(mktemp -d)
trap 'rm -rf "$tools"' EXIT
npm install --prefix "$tools" --silent gltf-pipeline@4.3.1 draco3dgltf@1.5.7 > /dev/null
(cd "$tools" && python3 "$OLDPWD/scripts/meshopt-fixture-source.py")
pipeline() { "$tools/node_modules/.bin/gltf-pipeline" -i "$tools/source.gltf" -o "tests/data/$1.glb" -d "${@:2}" > /dev/null; }
pipeline draco
pipeline draco_sequential --draco.compressionLevel 0 --draco.quantizePositionBits 0
for v in draco draco_sequential; do
  NODE_PATH="$tools/node_modules" node scripts/draco-decompress.mjs "tests/data/$v.glb" "tests/data/${v}_ref.glb"
done
