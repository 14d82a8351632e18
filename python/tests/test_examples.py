"""The examples run, at small sizes."""

import runpy
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def run_example(name, argv):
    module = runpy.run_path(str(REPO / "examples" / name), run_name="example")
    return module["main"](argv)


def test_diameter_study_moves_the_peak_to_longer_waves(tmp_path):
    rows = run_example("diameter_hue.py", ["--diameters", "210,250,290", "--width", "48",
                                           "--height", "36", "--rays", "2048",
                                           "--out", str(tmp_path / "study.csv")])
    peaks = [row["bragg_peak_nm"] for row in rows]
    assert peaks == sorted(peaks) and peaks[0] < peaks[-1]
    assert (tmp_path / "study.csv").read_text().count("\n") == 4


def test_distributed_sweep_runs_and_resumes(tmp_path, monkeypatch):
    pytest.importorskip("dask.distributed")
    monkeypatch.setenv("DASK_TEMPORARY_DIRECTORY", str(tmp_path / "dask"))
    argv = ["--out", str(tmp_path / "out"), "--frames", "3", "--width", "48", "--height", "36",
            "--rays", "2048", "--threads"]
    first = run_example("distributed_sweep.py", argv)
    assert first.rendered == [0, 1, 2]
    (tmp_path / "out" / "frame-0002.png").unlink()
    assert run_example("distributed_sweep.py", argv).rendered == [2]
    assert (tmp_path / "out" / "sweep.png").exists() and (tmp_path / "out" / "play.gif").exists()
