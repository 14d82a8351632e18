"""Parameter study: sphere diameter against the colour of the play of colour.

For each silica sphere diameter, prepares the scene (the structure and the cluster optics),
reads the Bragg peak at normal incidence off the optics table, renders the stone and takes the
hue of its brightest patches. Smaller spheres flash green and blue, larger ones orange and red
(docs/model.md, Bragg–Snell). Writes a CSV and, if matplotlib is installed, a plot.

    python examples/diameter_hue.py --out study.csv                     # 9 diameters, 160 × 120
    python examples/diameter_hue.py --diameters 200,250,300 --width 64 --height 48
    python examples/diameter_hue.py --dask                              # on a LocalCluster
"""

import argparse
import colorsys
import csv

import numpy as np

import opalray


def study(scene: opalray.Scene) -> dict:
    """Bragg peak and rendered hue of one scene (a function of a scene only: Dask can run it)."""
    stages = opalray.prepare(scene)
    optics = stages.optics
    peak_nm = float(optics.wavelengths_nm[np.argmax(optics.reflectance[0])])
    image = stages.render()
    # The brightest tenth of the stone's pixels: the flashes.
    rgb = image.rgb.reshape(-1, 3)
    luminance = rgb @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    bright = rgb[luminance >= np.quantile(luminance, 0.9)]
    r, g, b = np.clip(bright.mean(axis=0), 0, None)
    hue_deg = 360.0 * colorsys.rgb_to_hsv(r, g, b)[0]
    return {
        "sphere_diameter_nm": scene["crystal"]["sphere_diameter_nm"],
        "bragg_peak_nm": peak_nm,
        "hue_deg": hue_deg,
        "mean_rgb": [float(r), float(g), float(b)],
    }


def main(argv=None) -> list[dict]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--diameters", default="200,212.5,225,237.5,250,262.5,275,287.5,300",
                        help="sphere diameters, nm, comma-separated")
    parser.add_argument("--width", type=int, default=160)
    parser.add_argument("--height", type=int, default=120)
    parser.add_argument("--rays", type=int, default=16384, help="light.rays")
    parser.add_argument("--light-angle", type=float, default=0.0)
    parser.add_argument("--dask", action="store_true", help="run on a 2-worker LocalCluster")
    parser.add_argument("--out", default=None, help="CSV file to write")
    parser.add_argument("--plot", default=None, help="PNG plot to write (needs matplotlib)")
    args = parser.parse_args(argv)

    base = opalray.Scene.preset("paper").replace(
        render={"width": args.width, "height": args.height},
        light={"rays": args.rays, "angle_deg": args.light_angle},
    )
    scenes = [base.replace(crystal={"sphere_diameter_nm": float(d)})
              for d in args.diameters.split(",")]
    if args.dask:
        from dask.distributed import Client, LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=":0") as cluster, \
                Client(cluster) as client:
            rows = opalray.map(study, scenes, client=client)
    else:
        rows = opalray.map(study, scenes)

    for row in rows:
        print(f"D = {row['sphere_diameter_nm']:6.1f} nm   Bragg peak {row['bragg_peak_nm']:5.0f} nm"
              f"   hue {row['hue_deg']:5.1f}°")
    if args.out:
        with open(args.out, "w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(["sphere_diameter_nm", "bragg_peak_nm", "hue_deg"])
            for row in rows:
                writer.writerow([row["sphere_diameter_nm"], row["bragg_peak_nm"], row["hue_deg"]])
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        d = [row["sphere_diameter_nm"] for row in rows]
        fig, ax = plt.subplots(figsize=(5, 3))
        ax.scatter(d, [row["bragg_peak_nm"] for row in rows],
                   c=[np.clip(row["mean_rgb"], 0, None) / max(max(row["mean_rgb"]), 1e-9) for row in rows])
        ax.set_xlabel("sphere diameter, nm")
        ax.set_ylabel("Bragg peak at normal incidence, nm")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
    return rows


if __name__ == "__main__":
    main()
