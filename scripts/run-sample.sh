#!/usr/bin/env bash
# The main job on the bundled sample room: solve it and write the rendered images to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
room=resources/sample_room
mkdir -p out
./build/app/cli/relume solve "$room" --json out/sample_solution.json
for cam in main view0 view3; do
  ./build/app/cli/relume render "$room" --camera "$cam" -o "out/$cam.png"
  ./build/app/cli/relume render "$room" --camera "$cam" -o "out/$cam.exr"
done
for show in leaves links visibility; do
  ./build/app/cli/relume render "$room" --camera main --show "$show" -o "out/main_$show.png"
done
echo "Wrote out/sample_solution.json and the images in out/ (compare out/main.png with $room/photos/main.png)."
