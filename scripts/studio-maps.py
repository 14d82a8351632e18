#!/usr/bin/env python3
"""The built-in studio as environment maps, with its softbox split into smaller ones.

    scripts/studio-maps.py OUT_DIR

Writes equirectangular OpenEXR maps (2048 × 1024, the layout `environment.kind = "file"`
reads: row 0 at the zenith, pixel (u, v) looking along θ = π v from +z, azimuth 3π/2 − 2π u
from +x) of the room `studio` builds in (src/path/env.rs): a dark room (0.004) over black
velvet (0.0004), strip lights of 0.8 and 0.5 at the right and left, and

- `one.exr`: the softbox as built in, 22° in radius, 50° from the zenith towards +y;
- `four.exr`: four softboxes of 11° spread over that disc (the same solid angle, less their
  overlap);
- `seven.exr`: seven of 8.3°, one at the centre and six around it.

A scene that sets `environment.kind = "file"`, `path` to one of them and the studio's
intensity renders under it; scripts/look-tilt.py then measures how the colour changes as
the stone is rocked under one light or several (BENCHMARKS.md, "what holds the colour when
the stone is rocked"). Needs numpy and OpenEXR.
"""
import pathlib
import sys

import Imath
import numpy as np
import OpenEXR

WIDTH, HEIGHT = 2048, 1024


def directions():
    u = (np.arange(WIDTH) + 0.5) / WIDTH
    v = (np.arange(HEIGHT) + 0.5) / HEIGHT
    uu, vv = np.meshgrid(u, v)
    theta, phi = np.pi * vv, 1.5 * np.pi - 2 * np.pi * uu
    return np.stack(
        [np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1
    )


def axis(zenith_deg, azimuth_deg):
    z, a = np.radians(zenith_deg), np.radians(azimuth_deg)
    return np.array([np.sin(z) * np.cos(a), np.sin(z) * np.sin(a), np.cos(z)])


def studio(d, boxes):
    """The room with softboxes `(zenith°, azimuth°, radius°)` of value 1."""
    elevation = np.degrees(np.arcsin(np.clip(d[..., 2], -1, 1)))
    azimuth = np.degrees(np.arctan2(d[..., 1], d[..., 0]))
    img = np.full(d.shape[:2], 0.004, np.float32)
    for centre, value in ((180.0, 0.5), (0.0, 0.8)):
        off = (azimuth - centre + 180) % 360 - 180
        img[(np.abs(off) <= 30) & (elevation >= 10) & (elevation <= 25)] = value
    for zenith, az, radius in boxes:
        img[d @ axis(zenith, az) >= np.cos(np.radians(radius))] = 1.0
    img[d[..., 2] < 0] = 0.0004
    return img


def write(path, img):
    header = OpenEXR.Header(WIDTH, HEIGHT)
    channel = Imath.Channel(Imath.PixelType(Imath.PixelType.FLOAT))
    header["channels"] = {c: channel for c in "RGB"}
    out = OpenEXR.OutputFile(str(path), header)
    data = img.tobytes()
    out.writePixels({c: data for c in "RGB"})
    out.close()


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: scripts/studio-maps.py OUT_DIR")
    out = pathlib.Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    d = directions()
    # Azimuth 90° is +y; the softbox's centre is 50° from the zenith.
    ring = [(np.cos(np.radians(60 * k)), np.sin(np.radians(60 * k))) for k in range(6)]
    variants = {
        "one": [(50, 90, 22)],
        "four": [(50 + dz, 90 + da, 11) for dz, da in [(-13, 0), (13, 0), (0, -17), (0, 17)]],
        "seven": [(50, 90, 8.3)]
        + [(50 + 15 * c, 90 + 15 * s / np.sin(np.radians(50)), 8.3) for c, s in ring],
    }
    for name, boxes in variants.items():
        write(out / f"{name}.exr", studio(d, boxes))
        print(out / f"{name}.exr")


if __name__ == "__main__":
    main()
