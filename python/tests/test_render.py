"""Rendering from Python: the CLI's bytes, arrays' shapes and dtypes, the stages, the GIL."""

import json
import pickle
import subprocess
import threading
import time

import numpy as np
import pytest

import opalray
from conftest import small_scene


def test_render_is_byte_identical_to_the_cli(tmp_path, cli, small):
    scene_path = tmp_path / "small.toml"
    small.save(scene_path)
    subprocess.run(
        [cli, "render", str(scene_path), "--output", str(tmp_path / "cli.png"),
         "--stats", str(tmp_path / "cli.json")],
        check=True, capture_output=True,
    )
    image = opalray.render(small)
    image.save(tmp_path / "py.png")
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    # The same fields as --stats, the same energy figures.
    cli_stats = json.loads((tmp_path / "cli.json").read_text())
    assert set(image.stats) == set(cli_stats)
    assert image.stats["energy"] == cli_stats["energy"]
    assert image.stats["void_ratio"] == cli_stats["void_ratio"]
    assert image.stats["image"] == cli_stats["image"]
    # And the CLI's EXR outputs.
    subprocess.run(
        [cli, "render", str(scene_path), "--output", str(tmp_path / "cli.exr"),
         "--spectral", str(tmp_path / "cli-cube.exr")],
        check=True, capture_output=True,
    )
    image.save(tmp_path / "py.exr")
    image.save(tmp_path / "py-cube.exr", spectral=True)
    assert (tmp_path / "py.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    assert (tmp_path / "py-cube.exr").read_bytes() == (tmp_path / "cli-cube.exr").read_bytes()


def test_a_denoised_render_is_the_clis_and_smoother(tmp_path, cli):
    # The harlequin at 48 x 36, 4 spp: denoised from Python and by `--denoise`, the same bytes;
    # the noise left (the filtered halves' estimate) below the raw render's.
    scene = opalray.Scene.preset("harlequin").replace(
        render={"width": 48, "height": 36},
        integrator={"method": "path", "spp": 4, "denoise": True},
    )
    scene_path = tmp_path / "h.toml"
    scene.replace(integrator={"denoise": False}).save(scene_path)
    subprocess.run(
        [cli, "render", str(scene_path), "--denoise", "--output", str(tmp_path / "cli.png")],
        check=True, capture_output=True,
    )
    image = opalray.render(scene)
    image.save(tmp_path / "py.png")
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    path = image.stats["path"]
    left = path["denoised"]["noise_estimate"]["relative_rms"]
    assert 0 < left < path["noise"]["relative_rms"]


def test_arrays_have_their_shapes_dtypes_and_axis(small):
    image = opalray.render(small, light={"angle_deg": -20})
    h, w, bins = 48, 64, small["spectrum"]["bins"]
    assert image.rgb.shape == (h, w, 3) and image.rgb.dtype == np.float32
    assert image.srgb8.shape == (h, w, 3) and image.srgb8.dtype == np.uint8
    assert image.spectral.shape == (h, w, bins) and image.spectral.dtype == np.float32
    wl = image.wavelengths_nm
    lo, hi = small["spectrum"]["min_nm"], small["spectrum"]["max_nm"]
    step = (hi - lo) / bins
    assert wl.shape == (bins,) and wl.dtype == np.float64
    np.testing.assert_allclose(wl, lo + step * (np.arange(bins) + 0.5))
    assert np.isfinite(image.spectral).all() and (image.spectral >= 0).all()
    assert image.spectral.max() > 0 and image.srgb8.max() > 0
    assert image.stats["light_angle_deg"] == -20
    assert image.scene["light"]["angle_deg"] == -20
    assert not image.rgb.flags.writeable
    png = image._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"


def test_save_refuses_unknown_types(tmp_path, small):
    image = opalray.render(small)
    for bad, kw in [("x.jpg", {}), ("x.png", {"spectral": True})]:
        with pytest.raises(ValueError, match="unsupported file type"):
            image.save(tmp_path / bad, **kw)
    with pytest.raises(OSError, match="does not exist"):
        image.save(tmp_path / "no" / "x.png")


def test_save_into_a_missing_folder_speaks_of_the_path_not_a_flag(tmp_path, small):
    image = opalray.render(small)
    for name in ["nodir/a.png", "nodir/a.exr"]:
        with pytest.raises(OSError) as err:
            image.save(tmp_path / name)
        message = str(err.value)
        assert "does not exist" in message and "--output" not in message, message
    assert list(tmp_path.iterdir()) == []


def test_images_pickle_as_their_arrays(small):
    image = opalray.render(small)
    back = pickle.loads(pickle.dumps(image))
    np.testing.assert_array_equal(back.rgb, image.rgb)
    np.testing.assert_array_equal(back.srgb8, image.srgb8)
    np.testing.assert_array_equal(back.spectral, image.spectral)
    assert back.stats == image.stats and back.scene == image.scene
    assert back._repr_png_() == image._repr_png_()


def test_stages_are_arrays_and_render_the_same_bytes(small):
    stages = opalray.prepare(small)
    s = stages.structure
    nx, ny, nz = small["structure"]["grid"]
    assert s.grid == (nx, ny, nz)
    assert s.cells.shape == (nz, ny, nx) and s.cells.dtype == np.uint8
    assert s.orientations.shape == (nz, ny, nx, 4) and s.orientations.dtype == np.float32
    assert s.normals.shape == (nz, ny, nx, 3)
    clusters = s.cells == s.CLUSTER
    inside = s.cells != s.OUTSIDE
    assert clusters.sum() == s.stats["clusters"] and inside.sum() == s.stats["inside_cells"]
    assert abs((inside & ~clusters).sum() / inside.sum() - s.stats["void_ratio"]) < 1e-12
    np.testing.assert_allclose(np.linalg.norm(s.orientations[clusters], axis=-1), 1, atol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(s.normals[clusters], axis=-1), 1, atol=1e-5)
    o = stages.optics
    bins = small["spectrum"]["bins"]
    assert o.reflectance.shape == (len(o.cos_theta), bins) == o.transmittance.shape
    assert o.cos_theta[0] == 1.0 and o.theta_deg[-1] == pytest.approx(90)
    np.testing.assert_allclose(o.reflectance + o.transmittance + o.diffuse, 1, atol=1e-5)
    # The Bragg peak at normal incidence: λ = 2·d111·n_eff (DESIGN.md, Bragg–Snell).
    peak = o.wavelengths_nm[np.argmax(o.reflectance[0])]
    assert abs(peak - 2 * o.d111_nm * o.n_eff) < 15
    # A prepared scene renders the bytes of a fresh render, at any angle.
    for angle in (30.0, -40.0):
        fresh = opalray.render(small, light={"angle_deg": angle})
        np.testing.assert_array_equal(stages.render(angle).srgb8, fresh.srgb8)
        assert stages.render_rgb8(angle) == fresh.srgb8.tobytes()


def test_progress_callback_reports_the_stages(small):
    seen = []
    image = opalray.render(small, progress=lambda stage, done, total: seen.append((done, total)))
    assert seen == [(0, 2), (1, 2), (2, 2)]
    np.testing.assert_array_equal(image.srgb8, opalray.render(small).srgb8)


def test_the_gil_is_released_while_rendering():
    # Big enough that the render takes a while (about 0.3 s on two cores; 160 × 120 took
    # under 0.1 s on an idle machine); a second Python thread keeps counting.
    scene = small_scene(render={"width": 960, "height": 720}, light={"rays": 65536})
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    thread = threading.Thread(target=count)
    thread.start()
    try:
        time.sleep(0.05)
        start = time.perf_counter()
        opalray.render(scene)
        end = time.perf_counter()
    finally:
        stop.set()
        thread.join()
    during = [t for t in ticks if start <= t <= end]
    assert end - start > 0.1, "the render should take long enough to measure"
    # Ticks kept coming every few ms throughout the render: no gap near its length.
    gaps = np.diff([start] + during + [end])
    assert len(during) >= 5 and gaps.max() < 0.5 * (end - start), (len(during), gaps.max(), end - start)


def test_ctrl_c_interrupts_a_render_at_once():
    # A render of over a second (1.6 s on two cores); Ctrl-C (SIGINT's flag, as the terminal
    # sets it) 0.2 s in. Python turns SIGINT into KeyboardInterrupt only with its own handler,
    # which it leaves out when started with SIGINT ignored (a script's background job), and
    # `interrupt_main` then does nothing: the handler is put in for the test.
    import _thread
    import signal

    scene = small_scene(render={"width": 1280, "height": 960}, light={"rays": 1048576})
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        timer = threading.Timer(0.2, _thread.interrupt_main)
        start = time.perf_counter()
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            opalray.render(scene)
        waited = time.perf_counter() - start
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert waited < 1.0, waited
    # The package still works afterwards.
    assert opalray.render(small_scene()).srgb8.shape == (48, 64, 3)


def test_progress_true_draws_a_tqdm_bar_to_its_end(small, monkeypatch):
    # tqdm writes to sys.stderr unless told otherwise: a StringIO there holds the bar.
    pytest.importorskip("tqdm")
    import io
    import sys

    for run, total in [(lambda: opalray.render(small, progress=True), 2),
                       (lambda: opalray.sweep(small, [-30.0, 0.0, 30.0], progress=True), 3)]:
        out = io.StringIO()
        monkeypatch.setattr(sys, "stderr", out)
        run()
        monkeypatch.undo()
        text = out.getvalue()
        # The last state of the bar: every step of its total done.
        assert f"{total}/{total}" in text.split("\r")[-1], text
        assert "100%" in text and f"0/{total}" in text, text
    # The lobe integrator's bar counts its view pass's rows once they begin: 2 × 12 here.
    out = io.StringIO()
    monkeypatch.setattr(sys, "stderr", out)
    opalray.render(render={"width": 16, "height": 12}, integrator={"spp": 2}, progress=True)
    monkeypatch.undo()
    assert "24/24" in out.getvalue().split("\r")[-1], out.getvalue()


def test_prepared_renders_are_the_same_on_one_thread_and_scenes_hash(small):
    stages = opalray.prepare(small)
    assert stages.render(10.0, threads=1).srgb8.tobytes() == stages.render_rgb8(10.0)
    assert hash(small) == hash(opalray.Scene(small.to_dict()))
    assert len({small, opalray.Scene(small.to_dict()), small.replace(light={"rays": 8192})}) == 2


def test_a_saved_image_gives_back_its_scene(tmp_path, small):
    scene = small.replace(light={"angle_deg": -35.0}, structure={"seed": 9})
    image = opalray.render(scene)
    for name in ("a.png", "a.exr"):
        image.save(tmp_path / name)
        back = opalray.Scene.from_image(tmp_path / name)
        assert back == scene, name
        opalray.render(back).save(tmp_path / f"b-{name}")
        assert (tmp_path / name).read_bytes() == (tmp_path / f"b-{name}").read_bytes(), name
    (tmp_path / "plain.png").write_bytes((tmp_path / "a.png").read_bytes()[:8])
    with pytest.raises(ValueError, match="plain.png"):
        opalray.Scene.from_image(tmp_path / "plain.png")
