#!/usr/bin/env bash
# Hashes every output a dynlod binary writes from ../shared/meshes and the bundled bunny, so
# that a change meant to leave results alone can be shown to: run it with the binaries built
# before and after, then diff the two lists.
#
#   scripts/output-hashes.sh OLD_BINARY old.md5
#   scripts/output-hashes.sh target/release/dynlod new.md5
#   diff old.md5 new.md5
#
# Covers `simplify --method parallel` on every shared mesh (two ratios and one
# view-dependent cut), every method on the bunny at 50 % and 1 %, and `fly` frames (orbit,
# dolly and zoom on the bunny; dollies on three shared meshes; budget mode, three cameras and
# kept scenes) with the timing columns dropped. Where a command fails, its error message is
# hashed instead, so a changed error shows too. About a minute on two cores.
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 DYNLOD_BINARY OUT.md5" >&2; exit 2; }
bin=$(realpath "$1")
list=$(realpath -m "$2")
root=$(cd "$(dirname "$0")/.." && pwd)
shared="$root/../shared/meshes"
[ -d "$shared" ] || { echo "$0: $shared not found" >&2; exit 2; }
bunny="$root/examples/data/bun_zipper.ply.gz"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

run() { # NAME COMMAND...: runs the command; a refusal's message is kept under NAME
  local name=$1
  shift
  if ! "$@" > /dev/null 2> "$out/stderr"; then
    sed "s|$out|OUT|g" "$out/stderr" > "$out/$name.refused"
  fi
  rm -f "$out/stderr"
}

# glTF to GLB keeps the scene by default since session 33; --flatten (where the binary has it)
# gives the baked outputs these hashes covered before, and the kept-scene outputs are hashed
# besides.
flatten=()
# (The help is read whole first: `grep -q` stops reading at its match, and under pipefail the
# binary's SIGPIPE would then fail the test at random.)
help=$("$bin" simplify --help)
grep -q -- --flatten <<< "$help" && flatten=(--flatten)
for f in "$shared"/scans/* "$shared"/gltf/*.glb "$shared"/bad/*; do
  b=$(basename "$f")
  ext=obj
  [[ $f == *.glb ]] && ext=glb
  for r in 0.5 0.1; do
    run "parallel_${b}_$r" "$bin" simplify "$f" "$out/parallel_${b}_$r.$ext" --method parallel --ratio "$r" "${flatten[@]}"
  done
  run "view_$b" "$bin" simplify "$f" "$out/view_$b.$ext" --method parallel --eye 0,0,3 --pixel-error 2 "${flatten[@]}"
done
if [ ${#flatten[@]} -gt 0 ]; then
  for f in "$shared"/gltf/*.glb; do
    for m in qem parallel; do
      run "scene_${m}_$(basename "$f")" "$bin" simplify "$f" "$out/scene_${m}_$(basename "$f")" --method "$m" --ratio 0.25
    done
  done
fi
for m in mca qem mca-qem qem-batch parallel; do
  for r in 0.5 0.01; do
    run "bunny_${m}_$r" "$bin" simplify "$bunny" "$out/bunny_${m}_$r.obj" --method "$m" --ratio "$r"
  done
done
for p in orbit dolly zoom cuts; do
  run "fly_bunny_$p" "$bin" fly "$bunny" --path "$p" --frames 60 --csv "$out/fly_bunny_$p.csv"
done
for f in "$shared"/gltf/DamagedHelmet.glb "$shared"/scans/armadillo_libigl.obj "$shared"/gltf/2CylinderEngine.glb; do
  run "fly_$(basename "$f")" "$bin" fly "$f" --path dolly --frames 40 --csv "$out/fly_$(basename "$f").csv"
done
# Budget mode, several cameras and kept scenes (the last two where the binary has them:
# session 44 on; a scene's budget from session 45 on, refused before, its message hashed).
for p in orbit cuts; do
  run "fly_bunny_budget_$p" "$bin" fly "$bunny" --path "$p" --frames 60 --budget 3000 --csv "$out/fly_bunny_budget_$p.csv"
done
if "$bin" fly --help | grep -q -- --instanced; then
  run "fly_bunny_cameras" "$bin" fly "$bunny" --path orbit --frames 60 --cameras 3 --csv "$out/fly_bunny_cameras.csv"
  for f in "$shared"/gltf/2CylinderEngine.glb "$shared"/gltf/CesiumMilkTruck.glb; do
    b=$(basename "$f")
    run "fly_kept_$b" "$bin" fly "$f" --instanced --path dolly --frames 40 --csv "$out/fly_kept_$b.csv"
    run "fly_kept_budget_$b" "$bin" fly "$f" --instanced --path dolly --frames 40 --budget 20000 --csv "$out/fly_kept_budget_$b.csv"
  done
fi
# Frame times differ from run to run: keep every column but those in milliseconds.
for c in "$out"/*.csv; do
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) keep[i] = ($i !~ /_ms$/) }
           { s = ""; for (i = 1; i <= NF; i++) if (keep[i]) s = s (s == "" ? "" : ",") $i; print s }' "$c" > "$c.frames"
  rm "$c"
done
(cd "$out" && md5sum -- *) > "$list"
echo "$(wc -l < "$list") outputs hashed into $list"
