#!/usr/bin/env bash
# The main job: set up, build, then shade the bundled scenes and every bundled mesh in one batch
# (one OpenCL context); images, a contact sheet of every model, and a JSON/CSV report go to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh
./build/shadelab batch scenes/*.json --meshes meshes --scene scenes/templates/studio.json --out out --contact
echo "main job done: scene images in $(pwd)/out/, one image per bundled mesh in $(pwd)/out/studio/,"
echo "contact sheet $(pwd)/out/contact_sheet.png, report $(pwd)/out/batch_report.json and .csv"
