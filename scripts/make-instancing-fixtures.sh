#!/usr/bin/env bash
# Remakes tests/data/instancing_*.gltf/.glb (tests/data/README.md): a small scene written by
# scripts/instancing-fixture-source.py (one mesh drawn by seven nodes, one of them mirrored),
# and gltfpack 1.3's EXT_mesh_gpu_instancing of it, plain (-mi) and meshopt-compressed with
# filters (-mi -cc). Needs node and npm (the npm registry).
set -euo pipefail
cd "$(dirname "$0")/.."
tools=$(mktemp -d)
trap 'rm -rf "$tools"' EXIT
npm install --prefix "$tools" --silent gltfpack@1.3.0 > /dev/null
(cd "$tools" && python3 "$OLDPWD/scripts/instancing-fixture-source.py")
cp "$tools/source.gltf" tests/data/instancing_source.gltf
"$tools/node_modules/.bin/gltfpack" -i "$tools/source.gltf" -o tests/data/instancing_gltfpack.glb -mi > /dev/null
"$tools/node_modules/.bin/gltfpack" -i "$tools/source.gltf" -o tests/data/instancing_gltfpack_c.glb -mi -cc > /dev/null
