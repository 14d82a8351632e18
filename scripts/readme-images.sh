#!/usr/bin/env bash
# Regenerate the pictures on the README's front page from the default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin=target/release/opalray
"$bin" render --output docs/images/opal.png
"$bin" sweep --frames 7 --width 240 --height 180 --sheet docs/images/sweep.png
"$bin" structure --output docs/images/structure.png --scale 4
"$bin" render --body-tone 8 --light-angle 45 --output docs/images/white-opal.png --width 320 --height 240
"$bin" render --diameter 215 --light-angle 20 --output docs/images/blue-green.png --width 320 --height 240
"$bin" spectrum --angles 0,30,60 --plot docs/images/spectrum.png > /dev/null
# The Python quick start's picture, by the README's own lines (needs `pip install .`).
if python3 -c "import opalray" 2> /dev/null; then
    python3 -c '
import opalray
scene = opalray.Scene.preset("paper").replace(render={"width": 320, "height": 240})
opalray.render(scene, light={"angle_deg": -45}).save("docs/images/python-flash.png")'
fi
