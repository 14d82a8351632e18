#!/usr/bin/env python3
"""The look of an opal render, measured as gemmological grading describes it.

    scripts/look-metrics.py [--face-mm 20] IMAGE.png [IMAGE.png ...]

For each image (an opalray render on a dark backdrop): the stone's face is found as the
ellipse of the pixels that differ from the backdrop (the corners' colour), by their second
moments; then, over the face:

- colour share: pixels of HSV saturation > 0.5 and value > 0.25 (the play of colour);
- hue sextants: the share of the coloured pixels in each 60° hue sextant (red, yellow, green,
  cyan, blue, magenta), and how many hold at least 5 %;
- patches: the coloured pixels labelled by hue sextant, the labels smoothed by a 5 × 5 mode
  filter (so that sample noise does not split a patch), then 4-connected regions of one label
  of at least 0.25 % of the face; their count, median size (the diameter of a disc of the
  same area, in mm: the face's long axis is `--face-mm` across, 20 mm for the gem presets)
  and the largest's share of the face;
- what the rest of the face is: pale (value > 0.25, saturation ≤ 0.5: the gloss, the rim's
  reflections, and colours of several plates mixed), dim colour (saturation > 0.5, value
  ≤ 0.25) and dark (the rest);
- median value of the face (sRGB, 0–1);
- tint: the share of the face at saturation > 0.25 (any value), beside the face's median
  saturation: a milky white opal's play is pastel, under the colour's 0.5, over a body at
  about 0.2;
- edge straightness: the coherence of the colour structure tensor (the sum over R, G, B of
  ∇c ∇cᵀ, smoothed by a Gaussian of σ = 0.4 mm), `(λ₁ − λ₂) / (λ₁ + λ₂)`, averaged over the
  face (its rim excluded) weighted by the tensor's trace, i.e. by edge strength: 1 where the
  edges run straight for a millimetre or so, lower where they wander. At 320 × 240 the
  black opal's straight-edged patches measure 0.71, its ragged ones 0.63 (a doublet 0.76 and
  0.60); the softbox's gloss, a smooth curve, counts as straight, so a stone with few patch
  edges (white, broad flash) measures about 0.8 whatever its outlines.

Prints one line per image. Needs numpy and Pillow.
"""
import sys

import numpy as np
from PIL import Image, ImageFilter

# Smallest patch counted, as a share of the face.
MIN_PATCH = 0.0025


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


def regions(labels):
    """4-connected regions of equal nonzero label: a list of pixel counts."""
    h, w = labels.shape
    seen = np.zeros((h, w), bool)
    sizes = []
    flat = labels.ravel()
    for start in np.flatnonzero(flat):
        if seen.flat[start]:
            continue
        label = flat[start]
        stack = [start]
        seen.flat[start] = True
        n = 0
        while stack:
            i = stack.pop()
            n += 1
            y, x = divmod(i, w)
            for j, ok in ((i - 1, x > 0), (i + 1, x < w - 1), (i - w, y > 0), (i + w, y < h - 1)):
                if ok and not seen.flat[j] and flat[j] == label:
                    seen.flat[j] = True
                    stack.append(j)
        sizes.append(n)
    return sizes


def patches(hue, coloured, mask, face_mm):
    """Count, median diameter (mm) and largest share of the face of the colour patches."""
    labels = np.where(coloured, 1 + np.minimum((hue // 60).astype(int), 5), 0).astype(np.uint8)
    smooth = np.asarray(Image.fromarray(labels * 40).filter(ImageFilter.ModeFilter(5))) // 40
    smooth = np.where(mask, smooth, 0)
    face = mask.sum()
    sizes = [n for n in regions(smooth) if n >= MIN_PATCH * face]
    ys, xs = np.nonzero(mask)
    mm_per_px = face_mm / max(xs.max() - xs.min() + 1, 1) if len(xs) else 0.0
    diameters = [2.0 * np.sqrt(n / np.pi) * mm_per_px for n in sizes]
    return {
        "patches": len(sizes),
        "median_patch_mm": float(np.median(diameters)) if sizes else 0.0,
        "largest_patch_share": float(max(sizes) / face) if sizes else 0.0,
    }


def gaussian_blur(a, sigma):
    r = max(int(3 * sigma), 1)
    x = np.arange(-r, r + 1)
    k = np.exp(-x * x / (2 * sigma * sigma))
    k /= k.sum()
    a = np.apply_along_axis(lambda v: np.convolve(v, k, "same"), 0, a)
    return np.apply_along_axis(lambda v: np.convolve(v, k, "same"), 1, a)


def edge_straightness(rgb, mask, face_mm, sigma_mm=0.4, rim_px=6):
    """Trace-weighted coherence of the colour structure tensor over the face's inside."""
    ys, xs = np.nonzero(mask)
    if len(xs) == 0:
        return 0.0
    sigma = sigma_mm / (face_mm / (xs.max() - xs.min() + 1))
    inside = mask.copy()
    for _ in range(rim_px):
        inside &= np.roll(inside, 1, 0) & np.roll(inside, -1, 0)
        inside &= np.roll(inside, 1, 1) & np.roll(inside, -1, 1)
    jxx = jyy = jxy = 0.0
    for c in range(3):
        gy, gx = np.gradient(rgb[..., c])
        jxx, jyy, jxy = jxx + gx * gx, jyy + gy * gy, jxy + gx * gy
    jxx, jyy, jxy = (gaussian_blur(a, sigma) for a in (jxx, jyy, jxy))
    trace = jxx + jyy
    spread = np.sqrt((jxx - jyy) ** 2 + 4 * jxy**2)
    coherence = np.where(trace > 1e-12, spread / np.maximum(trace, 1e-12), 0.0)
    weight = trace * inside
    return float((coherence * weight).sum() / max(weight.sum(), 1e-12))


def measure(path, face_mm=20.0):
    rgb = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0
    mask = face_mask(rgb)
    hue, sat, val = hsv(rgb)
    coloured = mask & (sat > 0.5) & (val > 0.25)
    face = mask.sum()
    share = coloured.sum() / max(face, 1)
    pale = mask & (sat <= 0.5) & (val > 0.25)
    dim = mask & (sat > 0.5) & (val <= 0.25)
    sextants = np.histogram(hue[coloured], bins=6, range=(0, 360))[0]
    sextant_share = sextants / max(coloured.sum(), 1)
    return {
        "face_px": int(face),
        "colour_share": float(share),
        "pale_share": float(pale.sum() / max(face, 1)),
        "dim_share": float(dim.sum() / max(face, 1)),
        "sextants": [round(float(v), 3) for v in sextant_share],
        "sextants_over_5pct": int((sextant_share >= 0.05).sum()),
        "median_value": float(np.median(val[mask])) if face else 0.0,
        "tint_share": float((mask & (sat > 0.25)).sum() / max(face, 1)),
        "median_saturation": float(np.median(sat[mask])) if face else 0.0,
        "hue": hue,
        "coloured": coloured,
        "mask": mask,
        "edge_straightness": edge_straightness(rgb, mask, face_mm),
        **patches(hue, coloured, mask, face_mm),
    }


def main():
    args = sys.argv[1:]
    face_mm = 20.0
    if args[:1] == ["--face-mm"] and len(args) > 1:
        face_mm = float(args[1])
        args = args[2:]
    if not args:
        sys.exit("usage: scripts/look-metrics.py [--face-mm 20] IMAGE.png [IMAGE.png ...]")
    for path in args:
        m = measure(path, face_mm)
        print(
            f"{path}: colour {100 * m['colour_share']:.1f} % of the face "
            f"({m['face_px']} px; pale {100 * m['pale_share']:.1f} %, dim colour "
            f"{100 * m['dim_share']:.1f} %); hue sextants R Y G C B M = {m['sextants']} "
            f"({m['sextants_over_5pct']} of 6 ≥ 5 %); {m['patches']} patches, median "
            f"{m['median_patch_mm']:.1f} mm, largest {100 * m['largest_patch_share']:.0f} % of "
            f"the face; median value {m['median_value']:.2f}; edge straightness "
            f"{m['edge_straightness']:.2f}; tint {100 * m['tint_share']:.1f} % (S > 0.25), "
            f"median saturation {m['median_saturation']:.2f}"
        )


if __name__ == "__main__":
    main()
