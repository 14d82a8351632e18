#!/usr/bin/env python3
"""The look of an opal render, measured as gemmological grading describes it.

    scripts/look-metrics.py IMAGE.png [IMAGE.png ...]

For each image (an opalray render on a dark backdrop): the stone's face is found as the
ellipse of the pixels that differ from the backdrop (the corners' colour), by their second
moments; then, over the face:

- colour share: pixels of HSV saturation > 0.5 and value > 0.25 (the play of colour);
- hue sextants: the share of the coloured pixels in each 60° hue sextant (red, yellow, green,
  cyan, blue, magenta), and how many hold at least 5 %;
- median value of the face (sRGB, 0–1).

Prints one line per image. Needs numpy and Pillow.
"""
import sys

import numpy as np
from PIL import Image


def face_mask(rgb):
    h, w, _ = rgb.shape
    corners = np.concatenate([rgb[:4, :4].reshape(-1, 3), rgb[-4:, -4:].reshape(-1, 3)])
    backdrop = np.median(corners, axis=0)
    differs = np.abs(rgb - backdrop).max(axis=2) > 0.03
    ys, xs = np.nonzero(differs)
    if len(xs) < 10:
        return np.zeros((h, w), bool)
    cx, cy = xs.mean(), ys.mean()
    cov = np.cov(np.stack([xs - cx, ys - cy]))
    inv = np.linalg.inv(cov * 4.0)  # a uniform ellipse's second moments are a²/4
    yy, xx = np.mgrid[0:h, 0:w]
    d = np.stack([xx - cx, yy - cy], axis=-1)
    r2 = np.einsum("...i,ij,...j->...", d, inv, d)
    return r2 <= 1.0


def hsv(rgb):
    mx = rgb.max(axis=2)
    mn = rgb.min(axis=2)
    delta = mx - mn
    sat = np.where(mx > 0, delta / np.maximum(mx, 1e-9), 0.0)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    safe = np.maximum(delta, 1e-9)
    hue = np.where(
        mx == r,
        ((g - b) / safe) % 6,
        np.where(mx == g, (b - r) / safe + 2, (r - g) / safe + 4),
    )
    return hue * 60.0, sat, mx


def measure(path):
    rgb = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0
    mask = face_mask(rgb)
    hue, sat, val = hsv(rgb)
    coloured = mask & (sat > 0.5) & (val > 0.25)
    face = mask.sum()
    share = coloured.sum() / max(face, 1)
    sextants = np.histogram(hue[coloured], bins=6, range=(0, 360))[0]
    sextant_share = sextants / max(coloured.sum(), 1)
    return {
        "face_px": int(face),
        "colour_share": float(share),
        "sextants": [round(float(v), 3) for v in sextant_share],
        "sextants_over_5pct": int((sextant_share >= 0.05).sum()),
        "median_value": float(np.median(val[mask])) if face else 0.0,
    }


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: scripts/look-metrics.py IMAGE.png [IMAGE.png ...]")
    for path in sys.argv[1:]:
        m = measure(path)
        print(
            f"{path}: colour {100 * m['colour_share']:.1f} % of the face "
            f"({m['face_px']} px); hue sextants R Y G C B M = {m['sextants']} "
            f"({m['sextants_over_5pct']} of 6 ≥ 5 %); median value {m['median_value']:.2f}"
        )


if __name__ == "__main__":
    main()
