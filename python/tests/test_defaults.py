"""What a new user meets first: one default scene in Python and in every command, the list of
presets, progress per pass and a time limit."""

import _thread
import subprocess
import signal
import threading
import time

import numpy as np
import pytest

import opalray


def test_python_and_every_command_default_to_the_same_scene(cli):
    assert opalray.DEFAULT_PRESET == "black-opal"
    assert opalray.DEFAULT_PRESET in opalray.presets() and "paper" in opalray.presets()
    default = opalray.Scene.preset(opalray.DEFAULT_PRESET)
    # A Scene made with nothing given is that scene too, as the preset named by nobody.
    assert opalray.Scene() == default
    assert opalray.Scene.preset() == default

    def shown(*args):
        out = subprocess.run([cli, *args], check=True, capture_output=True, text=True)
        return opalray.Scene(__import__("tomllib").loads(out.stdout))

    assert shown("scene") == default
    for command in ("render", "bench", "structure"):
        assert shown(command, "--show-scene") == default, command
    assert shown("sweep", "--show-scene", "--width", "640", "--height", "480") == default
    # Python's render and sweep start from it too (small sizes given, as overrides).
    small = {"render": {"width": 16, "height": 12}, "integrator": {"spp": 1}}
    image = opalray.render(**small)
    assert image.scene == default.replace(**small)
    # The preset is tilted by -10 degrees: its own tilt is the default render.
    swept = opalray.sweep(tilt_deg=[default["camera"]["tilt_deg"]], **small)
    np.testing.assert_array_equal(swept.frames[0], image.srgb8)


def test_a_path_traced_render_reports_every_pass():
    gem = opalray.Scene.preset("black-opal").replace(
        render={"width": 16, "height": 12}, integrator={"method": "path", "spp": 4}
    )
    seen = []
    image = opalray.render(gem, progress=lambda stage, done, total: seen.append((stage, done, total)))
    # Passes of doubling samples: 2, then 4 samples per pixel, each with its noise.
    assert [(d, t) for _, d, t in seen] == [(2, 4), (4, 4)]
    assert all("spp, noise" in stage for stage, _, _ in seen), seen
    np.testing.assert_array_equal(image.srgb8, opalray.render(gem).srgb8)


def test_the_default_methods_view_pass_reports_its_rows():
    gem = opalray.Scene.preset("black-opal").replace(render={"width": 24, "height": 18}, integrator={"spp": 2})
    seen = []
    image = opalray.render(gem, progress=lambda stage, done, total: seen.append((stage, done, total)))
    rows = [(stage, done, total) for stage, done, total in seen if stage.startswith("view pass")]
    # The centres' sweep of 18 rows, then the edges': 36 rows in all, the last reported.
    assert rows and rows[-1][1:] == (36, 36), seen
    assert all(" rows, " in stage and "elapsed" in stage for stage, _, _ in rows), rows
    assert [d for _, d, _ in rows] == sorted(d for _, d, _ in rows), rows
    assert seen[-1][1] == seen[-1][2], seen
    # Reporting changes no byte.
    np.testing.assert_array_equal(image.srgb8, opalray.render(gem).srgb8)


def test_a_scene_without_a_light_reports_no_light_angle_nor_light_rays():
    small = {"render": {"width": 16, "height": 12}, "integrator": {"spp": 1}}
    stats = opalray.render(**small).stats
    assert stats["light_angle_deg"] is None and stats["light_rays"] is None, stats
    paper = opalray.render(opalray.Scene.preset("paper"), render={"width": 16, "height": 12},
                           light={"rays": 1024}).stats
    assert paper["light_angle_deg"] == 30 and paper["light_rays"] >= 1024, paper


def test_a_time_limit_stops_after_the_pass_it_falls_in():
    gem = opalray.Scene.preset("black-opal").replace(
        render={"width": 8, "height": 6}, integrator={"method": "path"}
    )
    # Long enough for the stone (a few hundred grains) and the first pass, on a busy machine.
    image = opalray.render(gem, time_limit=2.0)
    path = image.stats["path"]
    assert path["stopped_by_time_limit"] and path["spp"] < path["target_spp"] == 65536
    assert path["time_limit_s"] == 2.0
    # The image is the one of the samples reached.
    again = opalray.render(gem, integrator={"spp": path["spp"]})
    np.testing.assert_array_equal(image.srgb8, again.srgb8)
    with pytest.raises(ValueError, match="time_limit"):
        opalray.render(gem, time_limit=-1)
    with pytest.raises(ValueError, match="time_limit"):
        opalray.render(gem, time_limit=1e9)


def test_a_time_limit_bounds_every_method_and_the_stones_preparation():
    # Orientations correlated over 0.35 mm: some 50 000 parent grains, seconds to grow.
    slow = opalray.Scene.preset("black-opal").replace(
        render={"width": 8, "height": 6},
        domains={"orientation": "correlated", "correlation_mm": 0.35},
    )
    for method in ("path", "lobe"):
        start = time.monotonic()
        with pytest.raises(TimeoutError) as err:
            opalray.render(slow, integrator={"method": method}, time_limit=0.2)
        took = time.monotonic() - start
        message = str(err.value)
        assert message.startswith("time_limit 0.2: the limit passed during the stone's preparation"), message
        assert "\n" not in message and "--" not in message, message
        assert took < 1.5, f"{method}: {took:.2f} s"
    # A method that does not render in passes takes the limit too, and renders in time the
    # bytes it renders without it.
    paper = opalray.Scene.preset("paper").replace(render={"width": 16, "height": 12})
    np.testing.assert_array_equal(opalray.render(paper, time_limit=60).srgb8, opalray.render(paper).srgb8)


def test_a_stage_stopped_by_its_time_limit_frees_the_cores():
    # Orientations correlated over 0.25 mm: some 140 000 parent grains, many seconds of
    # growth on every core; the limit passes early in it.
    slow = opalray.Scene.preset("black-opal").replace(
        render={"width": 8, "height": 6},
        domains={"orientation": "correlated", "correlation_mm": 0.25},
    )
    with pytest.raises(TimeoutError):
        opalray.render(slow, integrator={"method": "lobe"}, time_limit=0.3)
    _assert_idle_after_the_stop()
    # Ctrl-C stops it the same way. Python's own SIGINT handler is put in place for it (as in
    # a session): `interrupt_main` does nothing where an earlier test or library left the
    # signal ignored or at its default.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        timer = threading.Timer(0.3, _thread.interrupt_main)
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            opalray.render(slow, integrator={"method": "lobe"})
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    _assert_idle_after_the_stop()


def _assert_idle_after_the_stop():
    """The stopped work returns within a fraction of a second; after that the process spends
    no more CPU time (a growth running on would spend about a second per core)."""
    time.sleep(0.3)
    before = time.process_time()
    time.sleep(1.0)
    used = time.process_time() - before
    assert used < 0.2, f"{used:.2f} s of CPU time in the second after the stop"
