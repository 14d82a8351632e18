#!/usr/bin/env python3
"""Relative RMS difference of two renders, in linear light, over the stone.

    scripts/image-rms.py a.png reference.png

Both PNGs are decoded from sRGB to linear values; pixels where either image is brighter than
the backdrop (sum of linear RGB above 0.02) count. Prints RMS(a − ref) / RMS(ref) in per cent.
Needs numpy and Pillow (`pip install numpy pillow`); a measuring aid, not part of the tests.
"""
import sys

import numpy as np
from PIL import Image


def linear(path):
    v = np.asarray(Image.open(path).convert("RGB"), dtype=float) / 255.0
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: image-rms.py IMAGE.png REFERENCE.png")
    a, ref = linear(sys.argv[1]), linear(sys.argv[2])
    if a.shape != ref.shape:
        sys.exit(f"sizes differ: {a.shape[1]}x{a.shape[0]} and {ref.shape[1]}x{ref.shape[0]}")
    mask = (a.sum(2) > 0.02) | (ref.sum(2) > 0.02)
    rms = np.sqrt(((a - ref) ** 2)[mask].mean()) / np.sqrt((ref**2)[mask].mean())
    print(f"relative RMS {100 * rms:.2f} % over {mask.sum()} pixels")


if __name__ == "__main__":
    main()
