#!/usr/bin/env python3
"""Time the Python package against the CLI, in alternating rounds.

1. The default scene (paper, 640 × 480): `opalray render -o x.png` as a process, against
   `opalray.render()` + `.save("x.png")` in this process (the extension already imported).
2. A sweep (9 frames, 320 × 240): `opalray.sweep` here against the same on a Dask
   LocalCluster of 2 single-threaded workers (processes, started and with opalray imported
   before the clock), the same without the tail split (`_tail_split`: every frame on one
   worker thread, as before it), and `opalray sweep` as a process.

    python scripts/bench_python.py --rounds 5 [--sweep-only] [--bin target/release/opalray]
        [--json out.json]

Prints the median and fastest seconds of each; run it from the venv scripts/test.sh makes.
"""

import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time
from unittest import mock

import opalray
from opalray import _sweep


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
    parser.add_argument("--sweep-only", action="store_true", help="skip the render comparison")
    args = parser.parse_args()
    tmp = tempfile.mkdtemp(prefix="opalray-bench-")
    os.environ.setdefault("DASK_TEMPORARY_DIRECTORY", os.path.join(tmp, "dask"))
    out = os.path.join(tmp, "x.png")

    # 1. One render of the default scene.
    cli_render, py_render, py_core = [], [], []
    opalray.render(opalray.Scene.preset().replace(render={"width": 64, "height": 48}))  # warm
    for k in range(0 if args.sweep_only else args.rounds):
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
    local, dask_times, dask_untailed, cli_sweep, loads = [], [], [], [], []
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        # A worker process imports opalray (numpy, the extension) once, with its first task:
        # a cost of the cluster's start, not of each sweep, kept out of the clock.
        client.run(lambda: __import__("opalray") and None)
        for k in range(args.rounds):
            loads.append(os.getloadavg()[0])

            def run_local():
                opalray.sweep(scene, angles)

            def run_dask():
                # A fresh scene per round (another seed would change the work): clear the
                # workers' prepared scenes so each round prepares as a first run does.
                client.run(lambda: __import__("opalray._sweep")._sweep._prepared.clear())
                opalray.sweep(scene, angles, client=client)

            def run_dask_untailed():
                client.run(lambda: __import__("opalray._sweep")._sweep._prepared.clear())
                with mock.patch.object(_sweep, "_tail_split", lambda client, frames: (0, None)):
                    opalray.sweep(scene, angles, client=client)

            def run_cli_sweep():
                subprocess.run([args.bin, "sweep", scene_path, "--width", "320", "--height", "240",
                                "--frames", str(args.frames), "--sheet", os.path.join(tmp, "s.png")],
                               check=True, capture_output=True)

            four = [(local, run_local), (dask_times, run_dask), (dask_untailed, run_dask_untailed),
                    (cli_sweep, run_cli_sweep)]
            for times, fn in (four if k % 2 == 0 else four[::-1]):
                times.append(timed(fn))
            print(f"round {k + 1}: load {loads[-1]:.1f}, local {local[-1]:.3f} s, LocalCluster "
                  f"{dask_times[-1]:.3f} s ({100 * (dask_times[-1] / local[-1] - 1):+.0f} %), "
                  f"untailed {dask_untailed[-1]:.3f} s, cli {cli_sweep[-1]:.3f} s", flush=True)

    rows = []
    if not args.sweep_only:
        rows += [
            summary("cli render (process, default scene)", cli_render),
            summary("python render + save (default scene)", py_render),
            summary("python render, core's own total", py_core),
        ]
    rows += [
        summary(f"cli sweep ({args.frames} frames, 320x240)", cli_sweep),
        summary(f"python sweep, local ({args.frames} frames)", local),
        summary(f"python sweep, LocalCluster 2 workers x 1 thread ({args.frames} frames)", dask_times),
        summary("  the same, every frame on one thread (no tail split)", dask_untailed),
    ]
    for row in rows:
        print(f"{row['name']:<66} median {row['median_s']:.3f} s   min {row['min_s']:.3f} s   ({row['runs']} runs)")
    result = {"rows": rows, "load_1min": loads}
    if not args.sweep_only:
        r = statistics.median(py_render) / statistics.median(cli_render) - 1
        print(f"python render over the CLI: {100 * r:+.1f} %")
        result["python_over_cli"] = r
    # Per round (the contenders ran back to back), then the spread over rounds.
    for name, times in (("LocalCluster", dask_times), ("untailed", dask_untailed)):
        ratios = sorted(100 * (d / l - 1) for d, l in zip(times, local))
        print(f"{name} over local, per round: median {statistics.median(ratios):+.1f} %, "
              f"range {ratios[0]:+.1f} … {ratios[-1]:+.1f} %")
        result[f"{name}_over_local_pct"] = ratios
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()
