#!/usr/bin/env python3
"""Error of a path-traced render against a long reference render of the same scene.

    scripts/error-vs-reference.py IMAGE.exr REFERENCE.exr [--reference-stats REF.json]

Both images are opalray's linear EXR output (`-o x.exr`) of one scene at one size; the test
image rendered with another `integrator.seed` than the reference, so that their noise is
independent. Over the stone (pixels where either image's linear RGB sums above 0.02), the
luminance Y = 0.2126 R + 0.7152 G + 0.0722 B of each is compared:

    error = sqrt(mean((Y − Y_ref)²) − (n_ref · mean(Y_ref))²) / mean(Y_ref)

where n_ref is the reference's own relative noise (`path.noise.relative_rms` in its
`--stats` JSON; 0 without `--reference-stats`): the reference's noise, independent of the
image's, is taken out of the mean square. For a raw render the error should match its own
`--stats` noise estimate; for a denoised one it is the noise left plus the filter's bias.
Also prints the ratio of mean luminances (a filter that loses or gains light shows there).

Needs numpy and the OpenEXR Python package (`pip install numpy OpenEXR`); a measuring aid,
not part of the tests.
"""
import argparse
import json
import sys

import numpy as np

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def load(path):
    try:
        import OpenEXR
    except ImportError:
        sys.exit("error-vs-reference.py needs the OpenEXR package: pip install OpenEXR")
    try:
        with OpenEXR.File(path) as f:
            channels = f.channels()
            if "RGB" in channels:
                return np.asarray(channels["RGB"].pixels, dtype=float)
            return np.stack([np.asarray(channels[c].pixels, dtype=float) for c in "RGB"], -1)
    except Exception as e:  # the reader's own exceptions vary by version
        sys.exit(f"cannot read {path} as an RGB OpenEXR image: {e}")


def main():
    parser = argparse.ArgumentParser(
        description="Relative RMS error of a render's luminance against a reference render."
    )
    parser.add_argument("image", help="linear EXR render to measure")
    parser.add_argument("reference", help="linear EXR reference (many more samples)")
    parser.add_argument(
        "--reference-stats",
        metavar="REF.json",
        help="the reference's --stats JSON: its own noise is subtracted from the error",
    )
    args = parser.parse_args()
    image, ref = load(args.image), load(args.reference)
    if image.shape != ref.shape:
        sys.exit(
            f"sizes differ: {image.shape[1]}x{image.shape[0]} and {ref.shape[1]}x{ref.shape[0]}"
        )
    noise_ref = 0.0
    if args.reference_stats:
        try:
            with open(args.reference_stats) as f:
                noise_ref = json.load(f)["path"]["noise"]["relative_rms"]
        except (OSError, ValueError, KeyError, TypeError) as e:
            sys.exit(f"--reference-stats: no path.noise.relative_rms in {args.reference_stats}: {e}")
    mask = (image.sum(2) > 0.02) | (ref.sum(2) > 0.02)
    if not mask.any():
        sys.exit("no stone: every pixel of both images is backdrop")
    y, y_ref = (image @ LUMINANCE)[mask], (ref @ LUMINANCE)[mask]
    mean_ref = y_ref.mean()
    mse = ((y - y_ref) ** 2).mean()
    error = np.sqrt(max(mse - (noise_ref * mean_ref) ** 2, 0.0)) / mean_ref
    print(
        f"error {100 * error:.2f} % (raw {100 * np.sqrt(mse) / mean_ref:.2f} %, "
        f"reference noise {100 * noise_ref:.2f} % taken out), mean ratio "
        f"{y.mean() / mean_ref:.3f}, over {mask.sum()} pixels"
    )


if __name__ == "__main__":
    main()
