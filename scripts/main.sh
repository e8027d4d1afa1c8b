#!/usr/bin/env bash
# The main job: set up, build, and shade every bundled mesh; images go to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh
mkdir -p out
for mesh in meshes/*.obj meshes/*.ply meshes/*.off meshes/*.stl; do
  [ -e "$mesh" ] || continue
  name=$(basename "${mesh%.*}")
  ./build/shadelab render "$mesh" --model lambert --albedo 0.8,0.75,0.7 \
      --light dir:1,1.2,1:1,0.95,0.9:1.0 --light dir:-1,0.3,-0.5:0.3,0.35,0.45:1.0 --ambient 0.03,0.03,0.04 \
      --size 640x640 -o "out/${name}_lambert.png" --quiet
  ./build/shadelab render "$mesh" --model lambert --albedo 0.8,0.75,0.7 \
      --light dir:1,1.2,1:1,0.95,0.9:1.0 --size 640x640 -o "out/${name}_lambert.exr" --quiet
done
echo "main job done: images in $(pwd)/out/"
