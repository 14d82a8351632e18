"""The paper's fig. 11 on a Dask cluster: one task per frame, files into a folder, resumable.

    python examples/distributed_sweep.py --out sweep-out                  # LocalCluster, 2 workers
    python examples/distributed_sweep.py --scheduler tcp://host:8786      # a running cluster
    python examples/distributed_sweep.py --frames 4 --width 64 --height 48 --threads

Run it twice into the same folder: the second run renders only the frames missing there.
"""

import argparse

import opalray


def main(argv=None) -> opalray.Sweep:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="sweep-out", help="output folder")
    parser.add_argument("--frames", type=int, default=9)
    parser.add_argument("--width", type=int, default=320)
    parser.add_argument("--height", type=int, default=240)
    parser.add_argument("--rays", type=int, default=None, help="light.rays")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--threads", action="store_true",
                        help="workers as threads of this process (processes=False)")
    parser.add_argument("--scheduler", default=None, help="address of a running scheduler")
    args = parser.parse_args(argv)

    from dask.distributed import Client, LocalCluster

    scene = opalray.Scene.preset("paper").replace(render={"width": args.width, "height": args.height})
    if args.rays:
        scene = scene.replace(light={"rays": args.rays})
    angles = opalray.sweep_angles(args.frames, -60, 60)
    if args.scheduler:
        cluster, client = None, Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1,
                               processes=not args.threads, dashboard_address=":0")
        client = Client(cluster)
    try:
        result = opalray.sweep(scene, angles, client=client, out_dir=args.out,
                               animation="play.gif", progress=True)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    print(f"{len(result.rendered)} of {len(angles)} frames rendered in {result.seconds:.2f} s; "
          f"wrote {result.sheet} and {result.animation}")
    return result


if __name__ == "__main__":
    main()
