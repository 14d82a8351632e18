#!/usr/bin/env bash
# Regenerate the pictures on the README's front page from the default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin=target/release/opalray
"$bin" render --preset paper --output docs/images/paper.png
"$bin" sweep --preset paper --frames 7 --width 240 --height 180 --sheet docs/images/paper-sweep.png
"$bin" structure --preset paper --output docs/images/structure.png --scale 4
"$bin" structure --output docs/images/black-opal-structure.png --scale 4
"$bin" render --preset paper --body-tone 8 --light-angle 45 --output docs/images/white-opal.png --width 320 --height 240
"$bin" render --preset paper --diameter 215 --light-angle 20 --output docs/images/blue-green.png --width 320 --height 240
"$bin" spectrum --angles 0,30,60 --plot docs/images/spectrum.png > /dev/null
# The gem presets by their method, the lobe integrator (seconds each), and the default stone
# by the path tracer beside it (the reference: about two minutes at 8 spp, denoised).
for p in black-opal harlequin broad-flash ribbon white crystal boulder doublet triplet pinfire; do
    "$bin" render --preset "$p" --width 320 --height 240 --output "docs/images/$p.png"
done
"$bin" render --preset black-opal --method path --denoise --spp 8 --width 320 --height 240 \
    --output docs/images/black-opal-path.png
"$bin" sweep --preset paper-path --from -30 --to 30 --frames 3 --columns 3 --width 256 \
    --height 192 --spp 4 --sheet docs/images/paper-path-sweep.png
