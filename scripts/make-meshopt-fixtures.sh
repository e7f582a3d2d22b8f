#!/usr/bin/env bash
# Remakes tests/data/meshopt_{ext,khr}.glb and their decoded references (tests/data/README.md):
# a small glTF written by scripts/meshopt-fixture-source.py, compressed by gltfpack 1.3 with
# every filter it has, and decoded by meshoptimizer's WebAssembly decoder
# (scripts/meshopt-decompress.mjs). Needs node and npm (the npm registry).
set -euo pipefail
cd "$(dirname "$0")/.."
tools=$(mktemp -d)
trap 'rm -rf "$tools"' EXIT
npm install --prefix "$tools" --silent gltfpack@1.3.0 meshoptimizer@1.3.0 > /dev/null
(cd "$tools" && python3 "$OLDPWD/scripts/meshopt-fixture-source.py")
pack() { "$tools/node_modules/.bin/gltfpack" -i "$tools/source.gltf" -o "tests/data/$1.glb" "${@:2}" > /dev/null; }
# EXT: 16-bit octahedral normals, float positions (EXPONENTIAL); KHR: 8-bit colours (COLOR).
pack meshopt_ext -cc -kv -vn 16 -vpf
pack meshopt_khr -cc -ce khr -kv -vc 8
for v in ext khr; do
  NODE_PATH="$tools/node_modules" node scripts/meshopt-decompress.mjs "tests/data/meshopt_$v.glb" "tests/data/meshopt_${v}_ref.glb"
done
