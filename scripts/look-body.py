#!/usr/bin/env python3
"""The body of an opal render against its body tone's Munsell value, under diffuse light.

    scripts/look-body.py [--preset white | --scene FILE] [--light tent,uniform]
                         [--width 160 --height 120] [--spp 8] [--max-depth N] [--out DIR]

A body tone N1…N9 is a grey chip of Munsell value V seen under diffuse white light; its
luminous reflectance is Y(V) (ASTM D1535: N9 0.767). The preset's scene (`opalray scene
--preset`), or the scene file given, is rendered with the release binary ($OPALRAY_BIN, else
target/release/opalray) under each diffuse environment asked for, at intensity 1 and
exposure 0, so that a pixel's linear luminance is the stone's reflectance there:

- `tent`: the light tent, white from 10° above the horizon up, over black velvet: the stone
  as a grader sees it on a dark tray (light through the stone is lost below);
- `uniform`: white from every direction, the calibration's furnace (light through the stone
  from below comes back up).

The face is the ellipse found as scripts/look-metrics.py finds it (on the tent's dark
velvet; under `uniform` the tent's face is used); its body is its pixels that are not
colour (HSV saturation ≤ 0.5). Prints each light's median body luminance Y beside Y(V).
The surface's gloss is in the image (about 3 % face-on), as it is in a photograph; pixels
are read from the 8-bit sRGB PNG, so a body near 1 (the furnace) reads a little low where
its noise clips.

Needs numpy and Pillow.
"""
import argparse
import importlib.util
import os
import pathlib
import re
import subprocess
import sys

import numpy as np
from PIL import Image

here = pathlib.Path(__file__).resolve().parent


def sibling(name, file):
    spec = importlib.util.spec_from_file_location(name, here / file)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


look = sibling("look_metrics", "look-metrics.py")
image_rms = sibling("image_rms", "image-rms.py")


def munsell_y(v):
    """ASTM D1535: luminous reflectance of Munsell value v, as a fraction."""
    return v * (1.1914 + v * (-0.22533 + v * (0.23352 + v * (-0.020484 + v * 0.00081939)))) / 100


def luminance(path):
    srgb = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0
    return srgb, image_rms.linear(path) @ np.array([0.2126, 0.7152, 0.0722])


def with_environment(scene, kind, max_depth):
    """The scene's TOML under the environment `kind` at intensity 1, exposure 0."""
    section = re.search(r"(?ms)^\[environment\]\n.*?(?=^\[|\Z)", scene)
    if section is None:
        sys.exit("look-body.py: the scene has no [environment] section")
    env = re.sub(r'(?m)^kind = ".*"$', f'kind = "{kind}"', section.group(0))
    env = re.sub(r"(?m)^intensity = .*$", "intensity = 1.0", env)
    scene = scene[: section.start()] + env + scene[section.end() :]
    scene = re.sub(r"(?m)^exposure_ev = .*$", "exposure_ev = 0.0", scene)
    if max_depth is not None:
        scene = re.sub(r"(?m)^max_depth = .*$", f"max_depth = {max_depth}", scene)
    return scene


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--preset", default="white")
    p.add_argument("--scene", default=None, help="a scene file instead of --preset")
    p.add_argument("--light", default="tent,uniform")
    p.add_argument("--width", default="160")
    p.add_argument("--height", default="120")
    p.add_argument("--spp", default="8")
    p.add_argument("--max-depth", type=int, default=None)
    p.add_argument("--out", default="look-body")
    a = p.parse_args()
    lights = a.light.split(",")
    if any(k not in ("tent", "uniform") for k in lights):
        sys.exit("look-body.py: --light takes tent and/or uniform, comma-separated")
    binary = os.environ.get("OPALRAY_BIN", str(here.parent / "target/release/opalray"))
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    if a.scene is not None:
        scene = pathlib.Path(a.scene).read_text()
        a.preset = pathlib.Path(a.scene).stem
    else:
        scene = subprocess.run(
            [binary, "scene", "--preset", a.preset], check=True, capture_output=True, text=True
        ).stdout
    tone = int(re.search(r"(?m)^body_tone = (\d+)$", scene).group(1))
    target = munsell_y(tone)
    # The face is found on the tent's dark velvet, so the tent is rendered first.
    order = sorted(set(lights) | {"tent"}, key=lambda k: k != "tent")
    mask = None
    for kind in order:
        toml = out / f"{a.preset}-{kind}.toml"
        png = out / f"{a.preset}-{kind}.png"
        toml.write_text(with_environment(scene, kind, a.max_depth))
        cmd = [binary, "render", str(toml), "--width", a.width, "--height", a.height]
        subprocess.run(cmd + ["--spp", a.spp, "--output", str(png)], check=True)
        srgb, y = luminance(png)
        if mask is None:
            mask = look.face_mask(srgb)
        _, sat, _ = look.hsv(srgb)
        body = mask & (sat <= 0.5)
        if kind not in lights:
            continue
        median = float(np.median(y[body])) if body.any() else 0.0
        print(
            f"{a.preset} under {kind}: body median Y {median:.3f} over {body.sum()} px "
            f"({100 * body.sum() / max(mask.sum(), 1):.0f} % of the face); N{tone} is "
            f"Y {target:.3f}: {'within' if abs(median - target) <= 0.1 else 'not within'} 0.1"
        )


if __name__ == "__main__":
    main()
