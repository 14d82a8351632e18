#!/usr/bin/env python3
"""A long path-traced reference, rendered in chunks that can be stopped and resumed.

    scripts/path-reference.py PRESET|SCENE.toml --dir DIR [--width 160] [--height 120]
                              [--spp 1024] [--chunk 64] [--first-seed 1001]
                              [--bin target/release/opalray]

Renders the stone of PRESET (or a scene file) by the path tracer, raw (`--method path
--no-denoise`), in `spp / chunk` renders of `--chunk` samples per pixel, each with its own
`integrator.seed` (`--first-seed` on; the stone's own seed, `structure.seed`, is not
touched): `DIR/NAME-WxH-seedS.exr`. A chunk already in DIR is kept, so the command picks up
where it was stopped, on this machine or another. The mean of the chunks is the path tracer at
`spp` samples per pixel (independent streams, equal weights), written as

- `DIR/NAME-path.png`: 8-bit sRGB encoded as `opalray render` encodes its PNG (the scene's
  hue-preserving gamut mapping, then the sRGB curve), checked against the renderer's own PNG
  of the first chunk, byte for byte, before anything is averaged;
- `DIR/NAME-path.json`: the chunks averaged, their seeds and the samples per pixel;
- `DIR/NAME-WxH-seedS.json`: each chunk's `--stats` (its light by class of path, its time).

`scripts/lobe-vs-path.py --width W --height H --keep DIR --reuse PRESET` then compares the
lobe integrator with that reference. With `--chunks-only`, no average is made.

Needs numpy, Pillow and the OpenEXR Python package (`pip install numpy Pillow OpenEXR`).
"""
import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np
from PIL import Image

here = os.path.dirname(os.path.abspath(__file__))

# The luminance weights of sRGB (the Y row of its RGB -> XYZ matrix), as the renderer's gamut
# mapping uses them.
LUMINANCE_SRGB = np.array([0.2126729, 0.7151522, 0.0721750])


def load_exr(path):
    try:
        import OpenEXR
    except ImportError:
        sys.exit("path-reference.py needs the OpenEXR package: pip install OpenEXR")
    with OpenEXR.File(path) as f:
        channels = f.channels()
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float64)
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float64) for c in "RGB"], -1)


def encode_srgb8(rgb):
    """Linear RGB -> 8-bit sRGB, as `color::gamut_map` (hue-preserving) then `encode_srgb8`."""
    c = np.where(np.isfinite(rgb), rgb, 0.0)
    y = c @ LUMINANCE_SRGB
    low = c.min(axis=2)
    # 1. Towards the colour's grey until the smallest component is 0.
    t = np.where(low < 0, y / np.where(y - low > 0, y - low, 1.0), 1.0)
    c = np.where((low < 0)[..., None], y[..., None] + t[..., None] * (c - y[..., None]), c)
    # 2. Scaled down so that the largest component is 1.
    high = c.max(axis=2)
    c = np.where((high > 1)[..., None], c / np.where(high > 1, high, 1.0)[..., None], c)
    c = np.where((y <= 0)[..., None], 0.0, np.clip(c, 0.0, 1.0))
    e = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    return np.floor(e * 255.0 + 0.5).astype(np.uint8)


def scene_text(binary, preset):
    args = [preset] if preset.endswith(".toml") else ["--preset", preset]
    return subprocess.run([binary, "scene"] + args, check=True, capture_output=True,
                          text=True).stdout


def seeded(text, seed, gamut_check):
    """`text` with `integrator.seed = seed`; the colour section must map hue-preserving in sRGB."""
    head, sep, tail = text.partition("[integrator]")
    if not sep:
        sys.exit("error: no [integrator] section in `opalray scene`'s output")
    if gamut_check and 'gamut = "hue-preserving"' not in head:
        sys.exit("error: the scene's color.gamut is not \"hue-preserving\"; this script encodes "
                 "PNGs that way only")
    lines = [l for l in tail.splitlines() if not l.startswith("seed =")]
    lines.insert(1, f"seed = {seed}")
    return head + sep + "\n".join(lines) + "\n"


def merged_orders(stats_paths):
    """The chunks' `path.bragg_orders` merged: each share of the summary as the chunks'
    luminance in that class over their luminance (equal pixels and samples per chunk), its
    standard error the spread of the chunks' shares over sqrt(chunks); `union` the light of
    two or more Bragg events or of one after an internal reflection (the classes' index bits:
    Bragg events 0-3, + 4 after an internal reflection, + 8 body, + 16 backing). None when a
    chunk has no stats (rendered before they were kept)."""
    if not all(os.path.exists(p) for p in stats_paths):
        return None
    orders = [json.load(open(p))["path"]["bragg_orders"] for p in stats_paths]
    y = np.array([o["mean_luminance"] for o in orders])

    def merged(shares):
        shares = np.asarray(shares)
        share = float((shares * y).sum() / y.sum())
        error = float(shares.std(ddof=1) / np.sqrt(len(shares))) if len(shares) > 1 else None
        return {"share": share, "standard_error": error}

    summary = {k: merged([o["summary"][k]["share"] for o in orders])
               for k in orders[0]["summary"]}

    def union_share(o):
        return sum(c["share"] for c in o["classes"]
                   if c["bragg"] != "0" and (c["bragg"] in ("2", "3+")
                                            or c["bragg_after_internal_reflection"]))

    summary["two_or_more_or_after_internal_reflection"] = merged([union_share(o) for o in orders])
    return {"mean_luminance": float(y.mean()), "chunks": len(orders),
            "standard_error_is": "the spread of the chunks' shares over sqrt(chunks)",
            "summary": summary}


def orders_row(name, spp, orders):
    """A row of `docs/model.md`'s table of the light by class of path, in %."""
    s = orders["summary"]
    keys = ["gloss", "bragg_0", "bragg_1", "bragg_2", "bragg_3_or_more",
            "bragg_after_internal_reflection", "body", "backing", "bragg_with_body_or_backing",
            "beyond_lobe", "two_or_more_or_after_internal_reflection"]
    cells = [f"{100 * s[k]['share']:.1f}" for k in keys]
    largest = max(v["standard_error"] or 0.0 for v in s.values())
    return (f"| {name} | {spp} | {orders['mean_luminance']:.3f} | " + " | ".join(cells)
            + f" | {100 * largest:.2f} |")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("preset")
    p.add_argument("--dir", required=True, help="folder of the chunks and the reference")
    p.add_argument("--width", type=int, default=160)
    p.add_argument("--height", type=int, default=120)
    p.add_argument("--spp", type=int, default=1024)
    p.add_argument("--chunk", type=int, default=64, help="samples per pixel of one chunk")
    p.add_argument("--first-seed", type=int, default=1001)
    p.add_argument("--bin", default=os.path.join(here, "..", "target", "release", "opalray"))
    p.add_argument("--chunks-only", action="store_true", help="render the chunks, average none")
    a = p.parse_args()
    if a.spp < 1 or a.chunk < 1 or a.spp % a.chunk:
        sys.exit(f"error: --spp {a.spp} must be a positive multiple of --chunk {a.chunk}")
    os.makedirs(a.dir, exist_ok=True)
    name = os.path.splitext(os.path.basename(a.preset))[0]
    text = scene_text(a.bin, a.preset)
    size = ["--width", str(a.width), "--height", str(a.height)]
    seeds = [a.first_seed + k for k in range(a.spp // a.chunk)]
    chunks = []
    for k, seed in enumerate(seeds):
        out = os.path.join(a.dir, f"{name}-{a.width}x{a.height}-seed{seed}.exr")
        chunks.append(out)
        if os.path.exists(out):
            continue
        scene = os.path.join(a.dir, f"{name}-seed{seed}.toml")
        with open(scene, "w") as f:
            f.write(seeded(text, seed, gamut_check=k == 0))
        start = time.time()
        # Each chunk's `--stats` beside it: its light by class of path (`path.bragg_orders`).
        outputs = ["--output", out, "--stats", out[:-len(".exr")] + ".json"]
        if k == 0:
            # The renderer's own PNG of the first chunk, to check the encoding against.
            check = os.path.join(a.dir, f"{name}-{a.width}x{a.height}-seed{seed}.png")
            subprocess.run([a.bin, "render", scene, "--method", "path", "--no-denoise",
                            "--spp", str(a.chunk), "--output", check] + size,
                           check=True, capture_output=True)
        subprocess.run([a.bin, "render", scene, "--method", "path", "--no-denoise",
                        "--spp", str(a.chunk)] + size + outputs, check=True, capture_output=True)
        print(f"chunk {k + 1} of {len(seeds)} (seed {seed}): {time.time() - start:.0f} s",
              flush=True)
    if a.chunks_only:
        return 0
    first_png = os.path.join(a.dir, f"{name}-{a.width}x{a.height}-seed{seeds[0]}.png")
    if os.path.exists(first_png):
        mine = encode_srgb8(load_exr(chunks[0]))
        theirs = np.asarray(Image.open(first_png).convert("RGB"))
        if mine.shape != theirs.shape or (mine != theirs).any():
            sys.exit("error: this script's PNG encoding differs from the renderer's on the first "
                     "chunk; the reference would not be comparable")
    orders = merged_orders([c[:-len(".exr")] + ".json" for c in chunks])
    mean = sum(load_exr(c) for c in chunks) / len(chunks)
    png = os.path.join(a.dir, f"{name}-path.png")
    Image.fromarray(encode_srgb8(mean)).save(png)
    with open(os.path.join(a.dir, f"{name}-path.json"), "w") as f:
        json.dump({"preset": a.preset, "width": a.width, "height": a.height, "spp": a.spp,
                   "chunk_spp": a.chunk, "seeds": seeds, "bragg_orders": orders}, f, indent=1)
    print(f"wrote {png}: the mean of {len(chunks)} chunks, {a.spp} spp")
    if orders:
        print(orders_row(name, a.spp, orders))
    return 0


if __name__ == "__main__":
    sys.exit(main())
