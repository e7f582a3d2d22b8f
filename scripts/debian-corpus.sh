#!/usr/bin/env bash
# Real files from other tools' test suites, as Debian packages them: assimp's test models
# (OBJ, PLY, OFF, STL, glTF from many exporters, broken ones among them), OpenSCAD's STL
# test data, PrusaSlicer's shape gallery, Cura's printer beds (STL and OBJ from CAD tools),
# Minetest's OBJ models and CGAL's data files (OFF above all: polygon meshes, shuffled
# windings, RGB colours, point clouds; shipped as a tarball inside the package).
# `dynlod info` runs on every file of a format we read; what it says (loaded: triangles and
# validity; or refused) must match tests/data/debian-corpus.expected, and nothing may crash. A file that starts loading, or
# stops, shows up as a difference.
#
#   bash scripts/debian-corpus.sh BIN           check against the expected list
#   bash scripts/debian-corpus.sh BIN --write   write the list from BIN's answers
#
# Exit 3 when the packages cannot be downloaded (no network, no apt) or are not the versions
# the list was made from: the check is skipped, not failed.
set -euo pipefail
bin=$(realpath "$1")
mode=${2:-check}
expected=$(realpath "$(dirname "$0")/../tests/data/debian-corpus.expected")
packages="assimp-testmodels openscad-testing-data prusa-slicer cura minetest-data libcgal-demo"

command -v apt-get > /dev/null || { echo "no apt-get: skipping"; exit 3; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
apt-get download $packages > download.log 2>&1 || { echo "could not download $packages: skipping"; exit 3; }
versions=""
for deb in *.deb; do
  versions+="$(dpkg-deb -f "$deb" Package)=$(dpkg-deb -f "$deb" Version) "
  dpkg-deb -x "$deb" x
done
if [ -f x/usr/share/doc/libcgal-dev/data.tar.gz ]; then
  mkdir -p x/usr/share/cgal
  tar -xzf x/usr/share/doc/libcgal-dev/data.tar.gz -C x/usr/share/cgal
fi
versions=${versions% }

outcome() {
  local out rc=0
  out=$(timeout 60 "$bin" info "$1" 2>&1) || rc=$?
  if [ "$rc" = 0 ]; then
    local tris valid
    tris=$(echo "$out" | awk '$1 == "triangles" { print $2 }')
    valid=$(echo "$out" | awk '$1 == "valid" { print $2 }')
    echo "loaded $tris triangles, valid $valid"
  elif [ "$rc" = 2 ]; then
    echo "refused"
  else
    echo "CRASHED (exit $rc)"
  fi
}

actual=$work/actual
echo "# $versions" > "$actual"
find x \( -type f -o -type l \) | grep -iE '\.(obj|ply|off|stl|gltf|glb)$' | LC_ALL=C sort | while read -r f; do
  printf '%s\t%s\n' "${f#x/usr/share/}" "$(outcome "$f")"
done >> "$actual"

if [ "$mode" = "--write" ]; then
  cp "$actual" "$expected"
  echo "wrote $(($(wc -l < "$expected") - 1)) files to $expected"
  exit 0
fi
if [ "$(head -1 "$expected")" != "# $versions" ]; then
  echo "the list was made from $(head -1 "$expected" | cut -c3-), not $versions: skipping"
  exit 3
fi
if grep -q CRASHED "$actual"; then
  grep CRASHED "$actual"
  exit 1
fi
if ! diff -u "$expected" "$actual"; then
  echo "dynlod answers differently on the files above (- expected, + now)"
  exit 1
fi
echo "$(($(wc -l < "$actual") - 1)) files answered as expected ($versions)"
