"""Sweeps, locally and on a Dask LocalCluster, and resume; `opalray.map`."""

import subprocess

import numpy as np
import pytest

import opalray
from opalray import _opalray
from conftest import small_scene

ANGLES = [-60.0, -20.0, 20.0, 60.0]


def test_sweep_angles_are_the_clis():
    assert opalray.sweep_angles(9) == [-60 + 120 * k / 8 for k in range(9)]
    assert opalray.sweep_angles(1, 10, 20) == [10.0]
    with pytest.raises(ValueError, match="frames"):
        opalray.sweep_angles(0)
    with pytest.raises(ValueError, match="light angle"):
        opalray.sweep(small_scene(), [100.0])


def test_local_sweep_matches_the_cli(tmp_path, cli, small):
    scene_path = tmp_path / "small.toml"
    small.save(scene_path)
    subprocess.run(
        [cli, "sweep", str(scene_path), "--width", "64", "--height", "48", "--frames", "4",
         "--from", "-60", "--to", "60", "--sheet", str(tmp_path / "cli-sheet.png"),
         "--animation", str(tmp_path / "cli.gif")],
        check=True, capture_output=True,
    )
    result = opalray.sweep(small, opalray.sweep_angles(4), sheet=tmp_path / "sheet.png",
                           animation=tmp_path / "play.gif")
    assert result.rendered == [0, 1, 2, 3]
    assert len(result.frames) == 4 and result.frames[0].shape == (48, 64, 3)
    assert (tmp_path / "sheet.png").read_bytes() == (tmp_path / "cli-sheet.png").read_bytes()
    assert (tmp_path / "play.gif").read_bytes() == (tmp_path / "cli.gif").read_bytes()
    for frame, angle in zip(result.frames, result.angles_deg):
        np.testing.assert_array_equal(frame, opalray.render(small, light={"angle_deg": angle}).srgb8)


def test_dask_sweep_equals_the_local_one(tmp_path, dask_client, small):
    local = opalray.sweep(small, ANGLES, out_dir=tmp_path / "local", animation="play.png")
    remote = opalray.sweep(small, ANGLES, client=dask_client, out_dir=tmp_path / "dask",
                           animation="play.png")
    assert remote.rendered == [0, 1, 2, 3]
    for a, b in zip(local.frames, remote.frames):
        np.testing.assert_array_equal(a, b)
    for name in ["sweep.png", "play.png"] + [f"frame-{k:04d}.png" for k in range(4)]:
        assert (tmp_path / "local" / name).read_bytes() == (tmp_path / "dask" / name).read_bytes(), name


@pytest.mark.parametrize("distributed", [False, True], ids=["local", "dask"])
def test_resumed_sweep_renders_only_the_missing_frames(tmp_path, request, small, distributed):
    client = request.getfixturevalue("dask_client") if distributed else None
    out = tmp_path / "out"
    first = opalray.sweep(small, ANGLES, client=client, out_dir=out, animation="play.gif")
    sheet = (out / "sweep.png").read_bytes()
    gif = (out / "play.gif").read_bytes()
    (out / "frame-0001.png").unlink()
    (out / "frame-0003.png").unlink()
    (out / "sweep.png").unlink()
    seen = []
    again = opalray.sweep(small, ANGLES, client=client, out_dir=out, animation="play.gif",
                          progress=lambda stage, done, total: seen.append(done))
    assert again.rendered == [1, 3]
    assert sorted(seen) == [3, 4]
    assert (out / "sweep.png").read_bytes() == sheet
    assert (out / "play.gif").read_bytes() == gif
    for a, b in zip(first.frames, again.frames):
        np.testing.assert_array_equal(a, b)
    # Nothing missing: nothing rendered.
    assert opalray.sweep(small, ANGLES, client=client, out_dir=out).rendered == []
    # Another scene into the same folder is refused.
    with pytest.raises(ValueError, match="another scene"):
        opalray.sweep(small.replace(crystal={"sphere_diameter_nm": 215}), ANGLES, out_dir=out)


def _peak_nm(scene):
    image = opalray.render(scene)
    spectrum = image.spectral.reshape(-1, image.spectral.shape[-1]).mean(axis=0)
    return float(image.wavelengths_nm[np.argmax(spectrum)])


def test_map_runs_locally_and_on_dask(dask_client, small):
    scenes = [small.replace(crystal={"sphere_diameter_nm": d}) for d in (215, 250)]
    local = opalray.map(_peak_nm, scenes)
    assert opalray.map(_peak_nm, scenes, client=dask_client) == local
    images = opalray.map(opalray.render, scenes, client=dask_client)
    for image, scene in zip(images, scenes):
        np.testing.assert_array_equal(image.srgb8, opalray.render(scene).srgb8)


def test_dask_sweep_on_worker_processes(tmp_path, small):
    # Real worker processes: the scene and the frames cross process boundaries (pickled).
    distributed = pytest.importorskip("dask.distributed")
    import dask

    with dask.config.set({"temporary-directory": str(tmp_path / "dask")}):
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                      dashboard_address=":0") as cluster, \
                distributed.Client(cluster) as client:
            remote = opalray.sweep(small, ANGLES, client=client)
            images = opalray.map(opalray.render, [small], client=client)
    local = opalray.sweep(small, ANGLES)
    for a, b in zip(local.frames, remote.frames):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(images[0].srgb8, opalray.render(small).srgb8)
    assert images[0].stats["energy"] == opalray.render(small).stats["energy"]


def test_a_folder_of_other_angles_is_refused(tmp_path, small):
    out = tmp_path / "out"
    opalray.sweep(small, [0.0], out_dir=out)
    with pytest.raises(ValueError, match="other angles"):
        opalray.sweep(small, [10.0], out_dir=out)


def test_dask_sweep_spreads_its_tail_over_the_idle_threads(dask_client, small):
    # Two single-threaded workers: of 3 frames the last renders on both threads, after the
    # others; with an even count every frame has a thread of its own.
    from opalray._sweep import _tail_split

    assert _tail_split(dask_client, 3) == (1, 2)
    assert _tail_split(dask_client, 9) == (1, 2)
    assert _tail_split(dask_client, 4) == (0, None)
    angles = [-60.0, 0.0, 60.0]
    remote = opalray.sweep(small, angles, client=dask_client)
    local = opalray.sweep(small, angles)
    for a, b in zip(local.frames, remote.frames):
        np.testing.assert_array_equal(a, b)


def test_out_dir_follows_the_frames_folder_rules(tmp_path, small):
    # A folder of the user's own files (no manifest of ours) is refused, untouched.
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "frame-0000.png").write_bytes(b"my picture")
    (mine / "sweep.json").write_text('{"mine": 1}')
    with pytest.raises(ValueError, match="not written by opalray"):
        opalray.sweep(small, ANGLES, out_dir=mine)
    (mine / "sweep.json").unlink()
    with pytest.raises(ValueError, match="no sweep.json"):
        opalray.sweep(small, ANGLES, out_dir=mine)
    assert (mine / "frame-0000.png").read_bytes() == b"my picture"
    # A frame swapped for another of the same size is rendered again, not mixed in.
    out = tmp_path / "out"
    whole = opalray.sweep(small, ANGLES, out_dir=out)
    (out / "frame-0000.png").write_bytes((out / "frame-0001.png").read_bytes())
    again = opalray.sweep(small, ANGLES, out_dir=out)
    assert again.rendered == [0]
    assert all((a == b).all() for a, b in zip(whole.frames, again.frames))
    # Under a damaged manifest every frame is rendered again.
    (out / "sweep.json").write_text('{"angles_deg": [0.0')
    assert opalray.sweep(small, ANGLES, out_dir=out).rendered == list(range(len(ANGLES)))


def _listing(root):
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


@pytest.mark.parametrize(
    "kwargs, argument",
    [
        ({"out_dir": "{tmp}/afile"}, "out_dir"),
        ({"out_dir": "{tmp}/out", "sheet": "frame-0000.png"}, "sheet"),
        ({"out_dir": "{tmp}/out", "animation": "{tmp}/out/frame-0001.png"}, "animation"),
        ({"out_dir": "{tmp}/out", "sheet": "x.jpg"}, "sheet"),
        ({"sheet": "{tmp}/a.png", "animation": "{tmp}/a.png"}, "animation"),
        ({"sheet": "{tmp}/nodir/s.png"}, "sheet"),
        ({"sheet": "{tmp}/adir.png"}, "sheet"),
        ({"out_dir": "{tmp}/out.png", "sheet": "{tmp}/out.png"}, "sheet"),
    ],
)
def test_out_dir_and_outputs_are_checked_before_any_work(tmp_path, kwargs, argument):
    # As the CLI's --frames-dir with --sheet and --animation: every output checked before a
    # file is written or a frame rendered, the one at fault named by its argument.
    (tmp_path / "afile").write_bytes(b"mine")
    (tmp_path / "adir.png").mkdir()
    before = _listing(tmp_path)
    kwargs = {k: v.replace("{tmp}", str(tmp_path)) for k, v in kwargs.items()}
    bad = kwargs[argument]
    with pytest.raises(ValueError) as err:
        opalray.sweep(small_scene(), ANGLES[:2], **kwargs)
    message = str(err.value)
    assert message.startswith(f"{argument} {bad}"), message
    assert "\n" not in message and "--" not in message, message
    assert _listing(tmp_path) == before
    assert (tmp_path / "afile").read_bytes() == b"mine"


def _gem(**changes):
    """The default gem at a size that renders in a moment."""
    return opalray.Scene.preset("black-opal").replace(
        render={"width": 24, "height": 18}, integrator={"spp": 2}, **changes
    )


def test_a_gem_swept_over_its_tilt_gives_the_clis_frames_that_differ(tmp_path, cli):
    gem = _gem()
    result = opalray.sweep(gem, tilt_deg=[-20.0, 0.0, 20.0], out_dir=tmp_path / "py")
    assert result.moves == "tilt" and result.angles_deg == [-20.0, 0.0, 20.0]
    a, b, c = result.frames
    assert (a != b).any() and (b != c).any() and (a != c).any()
    # The CLI's frames, named alike.
    gem.save(tmp_path / "gem.toml")
    subprocess.run(
        [cli, "sweep", str(tmp_path / "gem.toml"), "--tilt-from", "-20", "--tilt-to", "20",
         "--frames", "3", "--width", "24", "--height", "18", "--frames-dir", str(tmp_path / "cli"),
         "--sheet", str(tmp_path / "cli.png")],
        check=True, capture_output=True,
    )
    for k in range(3):
        name = f"frame-{k:04d}.png"
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    # A turned frame is the render of the turned scene.
    turned = opalray.sweep(gem, turn_deg=[30.0])
    np.testing.assert_array_equal(turned.frames[0], opalray.render(gem, camera={"turn_deg": 30.0}).srgb8)


def test_a_sweep_that_moves_nothing_is_refused_naming_what_would():
    with pytest.raises(ValueError, match="no light.*tilt_deg"):
        opalray.sweep(_gem(), [-45.0, 45.0])
    with pytest.raises(ValueError, match="no environment.*light_angles"):
        opalray.sweep(small_scene(), env_rotation_deg=[0.0, 90.0])
    # A method that sees no environment is refused for that, as `opalray sweep` refuses it.
    stored = opalray.Scene.preset("paper-stone")
    with pytest.raises(ValueError, match='sees no environment \\(integrator.method = "stored"\\)'):
        opalray.sweep(stored, env_rotation_deg=[0.0, 90.0])
    with pytest.raises(ValueError, match="one thing"):
        opalray.sweep(_gem(), tilt_deg=[0.0], turn_deg=[0.0])
    with pytest.raises(ValueError, match="tilt_deg 100.0"):
        opalray.sweep(_gem(), tilt_deg=[100.0])


def test_a_time_limit_bounds_the_sweep_and_keeps_the_finished_frames(tmp_path, small):
    import os
    import time

    # Orientations correlated over 0.35 mm: some 50 000 parent grains, seconds to grow.
    slow = opalray.Scene.preset("black-opal").replace(
        render={"width": 8, "height": 6}, domains={"orientation": "correlated", "correlation_mm": 0.35}
    )
    start = time.monotonic()
    with pytest.raises(TimeoutError) as err:
        opalray.sweep(slow, tilt_deg=[-10.0, 10.0], time_limit=0.2, out_dir=tmp_path / "slow")
    message = str(err.value)
    assert message.startswith("time_limit 0.2: the limit passed during the stone's preparation"), message
    assert "\n" not in message and "--" not in message, message
    assert time.monotonic() - start < 1.5
    assert sorted(os.listdir(tmp_path / "slow")) == ["scene.toml", "sweep.json"]
    # Path-traced frames of about a second each, so that four of them outlast the limit on a
    # fast machine too: the limit passes during one of them (or, on a machine too busy to
    # prepare the stone in time, before the first).
    gem = opalray.Scene.preset("black-opal").replace(
        render={"width": 8, "height": 6}, integrator={"method": "path", "spp": 64}
    )
    tilts = [-30.0, -10.0, 10.0, 30.0]
    with pytest.raises(TimeoutError, match=r"^time_limit 1\.0: the limit passed during (frame|the stone)"):
        opalray.sweep(gem, tilt_deg=tilts, time_limit=1.0, out_dir=tmp_path / "gem")
    kept = sorted(os.listdir(tmp_path / "gem"))
    assert "sweep.png" not in kept and len(kept) < 2 + len(tilts), kept
    # The same call again renders only the rest, and the frames of a sweep never stopped.
    resumed = opalray.sweep(gem, tilt_deg=tilts, out_dir=tmp_path / "gem")
    assert len(resumed.rendered) == 2 + len(tilts) - len(kept)
    whole = opalray.sweep(gem, tilt_deg=tilts)
    for a, b in zip(resumed.frames, whole.frames):
        np.testing.assert_array_equal(a, b)
    for bad in (0, -1, float("nan"), 1e9, True):
        with pytest.raises(ValueError, match="time_limit"):
            opalray.sweep(small, ANGLES, time_limit=bad, out_dir=tmp_path / "never")
    assert not (tmp_path / "never").exists()


def test_a_time_limit_bounds_a_dask_sweep_and_keeps_the_finished_frames(tmp_path, dask_client):
    import os
    import time

    # Path-traced frames of a fraction of a second each, on two single-threaded workers: the
    # limit passes while some are rendering (or, on a busy machine, in the preparation).
    gem = opalray.Scene.preset("black-opal").replace(
        render={"width": 8, "height": 6}, integrator={"method": "path", "spp": 16}
    )
    tilts = [-40.0 + 7.0 * k for k in range(12)]
    start = time.monotonic()
    with pytest.raises(TimeoutError, match=r"^time_limit 2\.0: the limit passed during (frame|the stone)") as err:
        opalray.sweep(gem, tilt_deg=tilts, time_limit=2.0, client=dask_client, out_dir=tmp_path / "gem")
    assert time.monotonic() - start < 3.5, err.value
    assert "\n" not in str(err.value) and "--" not in str(err.value), err.value
    kept = sorted(os.listdir(tmp_path / "gem"))
    assert "sweep.png" not in kept and len(kept) < 2 + len(tilts), kept
    # The workers' tasks were given the time left: nothing runs on after the limit.
    time.sleep(0.3)
    before = time.process_time()
    time.sleep(1.0)
    assert time.process_time() - before < 0.3
    # The frames kept are whole: the same call renders only the rest, and gives the frames
    # of a local sweep never stopped.
    resumed = opalray.sweep(gem, tilt_deg=tilts, client=dask_client, out_dir=tmp_path / "gem")
    assert len(resumed.rendered) == 2 + len(tilts) - len(kept)
    whole = opalray.sweep(gem, tilt_deg=tilts)
    for a, b in zip(resumed.frames, whole.frames):
        np.testing.assert_array_equal(a, b)


def test_the_sheet_labels_half_degrees_as_swept(tmp_path):
    # One frame labelled 2.5°, 2° and 3°: three different sheets (not 2.5 rounded to 2).
    frame = bytes(24 * 18 * 3)
    sheets = []
    for angle in (2.5, 2.0, 3.0):
        path = tmp_path / f"{angle}.png"
        _opalray.write_sheet(str(path), [frame], [angle], 24, 18, 1)
        sheets.append(path.read_bytes())
    assert sheets[0] != sheets[1] and sheets[0] != sheets[2]
