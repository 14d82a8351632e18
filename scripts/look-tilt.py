#!/usr/bin/env python3
"""How an opal's play of colour changes as the stone is rocked under fixed lights.

    scripts/look-tilt.py [--preset NAME | SCENE.toml] [--tilts -30,-20,-10,0,10,20,30]
                         [--width 320 --height 240 --spp 8] [--out DIR]

Renders the stone at each tilt (`opalray render --tilt`, which turns the lights with the
camera) with the release binary ($OPALRAY_BIN, else target/release/opalray) and measures each
image as scripts/look-metrics.py does. Then, as gemmological grading asks:

- the coloured share at each tilt, and its smallest over the tilts against half its largest
  (a stone that goes dead in some directions is "directional");
- the share of the face whose colour changes between tilt 0 and tilt 10: pixels coloured in
  one image and not the other, or coloured in both with hues more than 30° apart.

Needs numpy and Pillow.
"""
import argparse
import importlib.util
import os
import pathlib
import subprocess
import sys

import numpy as np

here = pathlib.Path(__file__).resolve().parent
spec = importlib.util.spec_from_file_location("look_metrics", here / "look-metrics.py")
look = importlib.util.module_from_spec(spec)
spec.loader.exec_module(look)


def changed_share(a, b):
    """Share of the face (both masks) whose colour differs between measurements a and b."""
    face = a["mask"] & b["mask"]
    ca, cb = a["coloured"] & face, b["coloured"] & face
    dh = np.abs(a["hue"] - b["hue"]) % 360.0
    dh = np.minimum(dh, 360.0 - dh)
    changed = (ca ^ cb) | (ca & cb & (dh > 30.0))
    return changed.sum() / max(face.sum(), 1)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene", nargs="?", help="scene file (TOML)")
    p.add_argument("--preset", default=None)
    p.add_argument("--tilts", default="-30,-20,-10,0,10,20,30")
    p.add_argument("--width", default="320")
    p.add_argument("--height", default="240")
    p.add_argument("--spp", default="8")
    p.add_argument("--out", default="look-tilt")
    a = p.parse_args()
    if (a.scene is None) == (a.preset is None):
        sys.exit("look-tilt.py: give a scene file or --preset NAME (one of the two)")
    tilts = [float(t) for t in a.tilts.split(",")]
    if 0.0 not in tilts or 10.0 not in tilts:
        sys.exit("look-tilt.py: --tilts must hold 0 and 10 (the change between them is measured)")
    binary = os.environ.get("OPALRAY_BIN", str(here.parent / "target/release/opalray"))
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    source = ["--preset", a.preset] if a.preset else [a.scene]
    measured = {}
    for t in tilts:
        png = out / f"tilt{t:+.0f}.png"
        cmd = [binary, "render", *source, "--tilt", str(t), "--width", a.width,
               "--height", a.height, "--spp", a.spp, "-o", str(png)]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode:
            sys.exit(f"look-tilt.py: {' '.join(cmd)} failed: {r.stderr.strip()}")
        measured[t] = look.measure(str(png))
        m = measured[t]
        print(f"tilt {t:+5.0f}°: colour {100 * m['colour_share']:5.1f} %, "
              f"{m['sextants_over_5pct']} sextants ≥ 5 %, {m['patches']} patches "
              f"(median {m['median_patch_mm']:.1f} mm)  {png}")
    shares = [measured[t]["colour_share"] for t in tilts]
    lo, hi = min(shares), max(shares)
    print(f"coloured share over the tilts: {100 * lo:.1f} … {100 * hi:.1f} % "
          f"(smallest {'≥' if lo >= 0.5 * hi else '<'} half the largest)")
    print(f"colour changed between 0° and 10°: {100 * changed_share(measured[0.0], measured[10.0]):.1f} % "
          "of the face")


if __name__ == "__main__":
    main()
