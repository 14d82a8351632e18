#!/usr/bin/env python3
"""Time the Python package against the CLI, in alternating rounds.

1. The default scene (paper, 640 × 480): `opalray render -o x.png` as a process, against
   `opalray.render()` + `.save("x.png")` in this process (the extension already imported).
2. A sweep (9 frames, 320 × 240): `opalray.sweep` here against the same on a Dask
   LocalCluster of 2 single-threaded workers (processes, started before the clock), and
   against `opalray sweep` as a process.

    python scripts/bench_python.py --rounds 5 [--bin target/release/opalray] [--json out.json]

Prints the median and fastest seconds of each; run it from the venv scripts/test.sh makes.
"""

import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time

import opalray


def timed(fn):
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def summary(name, times):
    return {"name": name, "median_s": statistics.median(times), "min_s": min(times), "runs": len(times)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--bin", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "opalray"))
    parser.add_argument("--frames", type=int, default=9)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    tmp = tempfile.mkdtemp(prefix="opalray-bench-")
    os.environ.setdefault("DASK_TEMPORARY_DIRECTORY", os.path.join(tmp, "dask"))
    out = os.path.join(tmp, "x.png")

    # 1. One render of the default scene.
    cli_render, py_render, py_core = [], [], []
    opalray.render(opalray.Scene.preset().replace(render={"width": 64, "height": 48}))  # warm
    for k in range(args.rounds):
        def run_cli():
            subprocess.run([args.bin, "render", "-o", out], check=True, capture_output=True)

        def run_py():
            image = opalray.render()
            image.save(out)
            py_core.append(image.stats["time_s"]["total"])

        # Alternate the order: the one run second has the warmer caches.
        pair = [(cli_render, run_cli), (py_render, run_py)]
        for times, fn in (pair if k % 2 == 0 else pair[::-1]):
            times.append(timed(fn))

    # 2. A sweep, here and on a LocalCluster.
    from dask.distributed import Client, LocalCluster

    scene = opalray.Scene.preset().replace(render={"width": 320, "height": 240})
    angles = opalray.sweep_angles(args.frames)
    scene_path = os.path.join(tmp, "sweep.toml")
    scene.save(scene_path)
    local, dask_times, cli_sweep = [], [], []
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        client.run(lambda: None)
        for k in range(args.rounds):
            def run_local():
                opalray.sweep(scene, angles)

            def run_dask():
                # A fresh scene per round (another seed would change the work): clear the
                # workers' prepared scenes so each round prepares as a first run does.
                client.run(lambda: __import__("opalray._sweep")._sweep._prepared.clear())
                opalray.sweep(scene, angles, client=client)

            def run_cli_sweep():
                subprocess.run([args.bin, "sweep", scene_path, "--width", "320", "--height", "240",
                                "--frames", str(args.frames), "--sheet", os.path.join(tmp, "s.png")],
                               check=True, capture_output=True)

            trio = [(local, run_local), (dask_times, run_dask), (cli_sweep, run_cli_sweep)]
            for times, fn in (trio if k % 2 == 0 else trio[::-1]):
                times.append(timed(fn))

    rows = [
        summary("cli render (process, default scene)", cli_render),
        summary("python render + save (default scene)", py_render),
        summary("python render, core's own total", py_core),
        summary(f"cli sweep ({args.frames} frames, 320x240)", cli_sweep),
        summary(f"python sweep, local ({args.frames} frames)", local),
        summary(f"python sweep, LocalCluster 2 workers x 1 thread ({args.frames} frames)", dask_times),
    ]
    for row in rows:
        print(f"{row['name']:<66} median {row['median_s']:.3f} s   min {row['min_s']:.3f} s   ({row['runs']} runs)")
    r = statistics.median(py_render) / statistics.median(cli_render) - 1
    d = statistics.median(dask_times) / statistics.median(local) - 1
    print(f"python render over the CLI: {100 * r:+.1f} %; LocalCluster sweep over local: {100 * d:+.1f} %")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"rows": rows, "python_over_cli": r, "dask_over_local": d}, f, indent=1)


if __name__ == "__main__":
    main()
