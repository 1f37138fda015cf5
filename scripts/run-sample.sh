#!/usr/bin/env bash
# The main job on the bundled sample room. With a display: the workbench, opened on it. Headless
# (or RELUME_HEADLESS=1): reconstruct it from its photos (COLMAP, and
# the clicked corners triangulated into a project), preprocess it for relighting (textures,
# estimates, real shadows removed), relight it several ways, and score it against its truth
# renders. Everything lands in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
room=resources/sample_room
# With a display, the main job is the workbench: it opens the sample room, preprocesses it (a job
# with a progress bar and Cancel) and shows it relit, ready for the Lights panel.
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ] && [ -z "${RELUME_HEADLESS:-}" ]; then
  exec ./build/app/workbench/relume-workbench "$room"
fi
relume=./build/app/cli/relume
mkdir -p out
# From photographs: COLMAP's cameras (with the camera's known intrinsics), their error against the
# true cameras, and the polygons of resources/sample_room/clicks.json as a project, relit.
cam=$(awk '!/^#/ && NF {print $2":"$5","$6","$7","$8; exit}' "$room/colmap/cameras.txt")
$relume reconstruct "$room/photos" --out out/workspace --camera "$cam"
$relume align out/workspace --to "$room" --json out/workspace/camera_errors.json
$relume triangulate "$room/colmap" --clicks "$room/clicks.json" -o out/from_clicks.relume
$relume preprocess out/from_clicks.relume -o out/from_clicks_lit.relume
$relume relight out/from_clicks_lit.relume --lamp A=0 -o out/relit_from_clicks_A_off.png
$relume preprocess "$room" -o out/sample.relume
$relume relight out/sample.relume -o out/relit_original.png
$relume relight out/sample.relume --lamp A=0 -o out/relit_A_off.png
$relume relight out/sample.relume --lamp B=2 -o out/relit_B_double.png
$relume relight out/sample.relume --lamp A=0 --lamp C=1.6,1.1,0.6 -o out/relit_warm.png
$relume relight out/sample.relume --virtual-object resources/examples/virtual_box.json -o out/relit_virtual_box.png
$relume relight out/sample.relume --lamp A=0 --lamp B=0 --lamp C=0 --virtual-lamp resources/examples/virtual_lamp.json \
  -o out/relit_virtual_lamp.png
$relume relight out/sample.relume --virtual-lamp resources/examples/virtual_downlight.json -o out/relit_virtual_downlight.png
$relume relight out/sample.relume --lamp A=0 --method ratio-only -o out/relit_A_off_ratio_only.png
# An image-based object (Dinh, Metoyer, Turk): the example vase's image fan, placed by
# resources/examples/image_object.json, drawn into the relit photo with its shadows, lamps A and B off.
$relume ibr-fan resources/examples/vase.obj -o out/vase.fan
cp resources/examples/image_object.json out/image_object.json
$relume relight out/sample.relume --lamp A=0 --lamp B=0 --virtual-object out/image_object.json -o out/relit_vase.png
$relume evaluate "$room" --out out/evaluation
$relume render "$room" --camera main --show leaves -o out/main_leaves.png
echo "Wrote the COLMAP workspace out/workspace (camera errors in camera_errors.json), the project built from"
echo "clicks out/from_clicks.relume, the relit images out/relit_*.png (out/relit_vase.png: an image-based vase),"
echo "the project out/sample.relume and"
echo "out/evaluation/report.json"
echo "(out/evaluation/*.png: photo | ratio-only | full | truth, side by side)."
