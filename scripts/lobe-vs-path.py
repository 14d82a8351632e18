#!/usr/bin/env python3
"""The lobe integrator against the path tracer, preset by preset.

    scripts/lobe-vs-path.py [--width 64] [--height 48] [--spp 256] [--bin target/release/opalray]
                            [--keep DIR [--reuse]] [--floor] PRESET|SCENE.toml [...]

For each preset (or scene file): the same stone rendered by the lobe integrator (the preset's own method) and
by the path tracer (`--method path`, raw: not denoised, `--spp` samples per pixel), both as
8-bit sRGB PNGs decoded to linear RGB and blurred by a Gaussian of σ = 1.5 px; over the
stone's face (scripts/look-metrics.py's ellipse of the pixels that differ from the backdrop):

- the ratio of the mean luminances (lobe / path);
- CIEDE2000 per pixel (CIELAB against D65 white, luminance 1 = sRGB white): median and 90th
  percentile;
- colour coverage (look-metrics' share of the face at saturation > 0.5 and value > 0.25) of
  each, unblurred, and their difference.

With `--floor`, the path tracer is run a second time with another `integrator.seed` (the same
stone) and the same figures are given between its two images: the reference's own noise,
the floor under which a difference from the lobe integrator cannot be told from it.

Prints one line per preset. Needs numpy and Pillow.
"""
import argparse
import importlib.util
import os
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

here = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location("look_metrics", os.path.join(here, "look-metrics.py"))
look = importlib.util.module_from_spec(spec)
spec.loader.exec_module(look)


def linear(srgb8):
    c = srgb8.astype(np.float64) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def blur(img, sigma=1.5):
    r = int(np.ceil(3 * sigma))
    k = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
    k /= k.sum()
    out = img.copy()
    for axis in (0, 1):
        pad = [(0, 0)] * img.ndim
        pad[axis] = (r, r)
        p = np.pad(out, pad, mode="edge")
        out = sum(k[i] * np.take(p, range(i, i + img.shape[axis]), axis=axis) for i in range(2 * r + 1))
    return out


M = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]])
WHITE = M.sum(axis=1)


def lab(rgb):
    xyz = rgb @ M.T / WHITE
    d = 6.0 / 29.0
    f = np.where(xyz > d**3, np.cbrt(xyz), xyz / (3 * d * d) + 4.0 / 29.0)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])], -1)


def ciede2000(a, b):
    """CIEDE2000 (Sharma, Wu & Dalal 2005) between CIELAB arrays."""
    l1, a1, b1 = a[..., 0], a[..., 1], a[..., 2]
    l2, a2, b2 = b[..., 0], b[..., 1], b[..., 2]
    cbar = 0.5 * (np.hypot(a1, b1) + np.hypot(a2, b2))
    g = 0.5 * (1 - np.sqrt(cbar**7 / (cbar**7 + 25.0**7)))
    a1p, a2p = (1 + g) * a1, (1 + g) * a2
    c1, c2 = np.hypot(a1p, b1), np.hypot(a2p, b2)
    h1 = np.mod(np.arctan2(b1, a1p), 2 * np.pi)
    h2 = np.mod(np.arctan2(b2, a2p), 2 * np.pi)
    dl, dc = l2 - l1, c2 - c1
    dh = h2 - h1
    dh = np.where(dh > np.pi, dh - 2 * np.pi, np.where(dh < -np.pi, dh + 2 * np.pi, dh))
    dh = np.where(c1 * c2 == 0, 0, dh)
    dhh = 2 * np.sqrt(c1 * c2) * np.sin(dh / 2)
    lbar, cpbar = 0.5 * (l1 + l2), 0.5 * (c1 + c2)
    hsum = h1 + h2
    hbar = np.where(np.abs(h1 - h2) <= np.pi, hsum / 2,
                    np.where(hsum < 2 * np.pi, (hsum + 2 * np.pi) / 2, (hsum - 2 * np.pi) / 2))
    hbar = np.where(c1 * c2 == 0, hsum, hbar)
    t = (1 - 0.17 * np.cos(hbar - np.pi / 6) + 0.24 * np.cos(2 * hbar)
         + 0.32 * np.cos(3 * hbar + np.pi / 30) - 0.20 * np.cos(4 * hbar - 63 * np.pi / 180))
    dtheta = np.pi / 6 * np.exp(-(((hbar * 180 / np.pi) - 275) / 25) ** 2)
    rc = 2 * np.sqrt(cpbar**7 / (cpbar**7 + 25.0**7))
    sl = 1 + 0.015 * (lbar - 50) ** 2 / np.sqrt(20 + (lbar - 50) ** 2)
    sc, sh = 1 + 0.045 * cpbar, 1 + 0.015 * cpbar * t
    rt = -np.sin(2 * dtheta) * rc
    return np.sqrt((dl / sl) ** 2 + (dc / sc) ** 2 + (dhh / sh) ** 2 + rt * (dc / sc) * (dhh / sh))


def coverage(srgb8, face):
    rgb = srgb8.astype(np.float64) / 255.0
    mx, mn = rgb.max(axis=2), rgb.min(axis=2)
    sat = np.where(mx > 0, (mx - mn) / np.maximum(mx, 1e-9), 0)
    return float(((sat > 0.5) & (mx > 0.25) & face).sum() / max(face.sum(), 1))


def reseeded(binary, preset, folder):
    """A scene file of `preset` with `integrator.seed = 1` (the same stone)."""
    scene = [preset] if preset.endswith(".toml") else ["--preset", preset]
    text = subprocess.run([binary, "scene"] + scene, check=True, capture_output=True,
                          text=True).stdout
    head, sep, tail = text.partition("[integrator]")
    if not sep:
        sys.exit(f"error: {preset}: no [integrator] section in `opalray scene`'s output")
    lines = [l for l in tail.splitlines() if not l.startswith("seed =")]
    lines.insert(1, "seed = 1")
    name = os.path.splitext(os.path.basename(preset))[0]
    out = os.path.join(folder, f"{name}-seed1.toml")
    with open(out, "w") as f:
        f.write(head + sep + "\n".join(lines) + "\n")
    return out


def compare(lobe8, path8, face):
    """Mean-luminance ratio, ΔE00 median and 90th percentile of two 8-bit images."""
    lo, pa = blur(linear(lobe8)), blur(linear(path8))
    y = lambda rgb: (rgb @ M[1])[face].mean()
    de = ciede2000(lab(lo), lab(pa))[face]
    return y(lo) / y(pa), np.median(de), np.percentile(de, 90)


def render(binary, preset, out, extra):
    scene = [preset] if preset.endswith(".toml") else ["--preset", preset]
    subprocess.run([binary, "render"] + scene + ["--output", out] + extra,
                   check=True, capture_output=True)
    return np.asarray(Image.open(out).convert("RGB"))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("presets", nargs="+")
    p.add_argument("--width", type=int, default=64)
    p.add_argument("--height", type=int, default=48)
    p.add_argument("--spp", type=int, default=256)
    p.add_argument("--bin", default=os.path.join(here, "..", "target", "release", "opalray"))
    p.add_argument("--keep", help="folder to keep both renders in")
    p.add_argument("--reuse", action="store_true",
                   help="take the path tracer's image from --keep where one of this size is there")
    p.add_argument("--floor", action="store_true",
                   help="also run the path tracer with integrator.seed = 1 and compare its two images")
    a = p.parse_args()
    size = ["--width", str(a.width), "--height", str(a.height)]
    folder = a.keep or tempfile.mkdtemp()
    os.makedirs(folder, exist_ok=True)
    print("preset  Y(lobe)/Y(path)  dE00 median  dE00 p90  colour lobe  colour path"
          + ("  | floor: Y ratio  dE00 median  dE00 p90" if a.floor else ""))
    for preset in a.presets:
        name = os.path.splitext(os.path.basename(preset))[0]
        lobe8 = render(a.bin, preset, os.path.join(folder, f"{name}-lobe.png"),
                       size + ["--method", "lobe"])
        kept = os.path.join(folder, f"{name}-path.png")
        path8 = np.asarray(Image.open(kept).convert("RGB")) if a.reuse and os.path.exists(kept) else None
        if path8 is None or path8.shape != lobe8.shape:
            path8 = render(a.bin, preset, kept,
                           size + ["--method", "path", "--no-denoise", "--spp", str(a.spp)])
        face = look.face_mask(lobe8.astype(np.float64) / 255.0)
        ratio, median, p90 = compare(lobe8, path8, face)
        line = (f"{preset}  {ratio:.3f}  {median:.2f}  {p90:.2f}  "
                f"{coverage(lobe8, face):.3f}  {coverage(path8, face):.3f}")
        if a.floor:
            kept1 = os.path.join(folder, f"{name}-path-seed1.png")
            other = None
            if a.reuse and os.path.exists(kept1):
                other = np.asarray(Image.open(kept1).convert("RGB"))
            if other is None or other.shape != lobe8.shape:
                other = render(a.bin, reseeded(a.bin, preset, folder), kept1,
                               size + ["--method", "path", "--no-denoise", "--spp", str(a.spp)])
            line += "  | {:.3f}  {:.2f}  {:.2f}".format(*compare(other, path8, face))
        print(line, flush=True)


if __name__ == "__main__":
    sys.exit(main())
