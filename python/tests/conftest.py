"""Shared fixtures: a small scene (fast renders), the CLI binary to compare with."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

import opalray

REPO = Path(__file__).resolve().parents[2]


def small_scene(**changes) -> "opalray.Scene":
    """The paper's opal at 64 × 48 with a coarse light lattice: a render takes well under a
    second."""
    scene = opalray.Scene.preset("paper").replace(
        render={"width": 64, "height": 48}, light={"rays": 4096}
    )
    return scene.replace(**changes) if changes else scene


@pytest.fixture
def small():
    return small_scene()


@pytest.fixture(scope="session")
def cli() -> str:
    """The `opalray` binary: $OPALRAY_BIN, else the workspace's release build."""
    path = os.environ.get("OPALRAY_BIN") or str(REPO / "target" / "release" / "opalray")
    if not os.path.exists(path):
        if shutil.which("cargo") is None:
            pytest.fail(f"no opalray binary at {path} and no cargo to build it")
        subprocess.run(["cargo", "build", "--release", "-p", "opalray-cli"], cwd=REPO, check=True)
    return path


@pytest.fixture(scope="session")
def dask_client(tmp_path_factory):
    """A LocalCluster of two single-threaded workers, its scratch files in the test's temp
    folder. Threads in this process (processes=False): it starts in a fraction of a second,
    and the tasks are the same; `test_dask_sweep_on_worker_processes` runs worker processes."""
    distributed = pytest.importorskip("dask.distributed")
    import dask

    scratch = tmp_path_factory.mktemp("dask")
    with dask.config.set({"temporary-directory": str(scratch)}):
        cluster = distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0"
        )
        client = distributed.Client(cluster)
        yield client
        client.close()
        cluster.close()
