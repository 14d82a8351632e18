"""Jupyter: a sweep shows itself as an inline animation; short reprs of the results."""

import base64
import re
import struct

import numpy as np
import pytest

import opalray
from opalray import _opalray
from conftest import small_scene

_SHORT = 240  # characters: a repr is one line, not a dump of arrays


def _data_png(html: str) -> bytes:
    match = re.search(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', html)
    assert match, html[:200]
    return base64.b64decode(match.group(1))


def _chunks(png: bytes) -> dict[bytes, bytes]:
    """The first chunk of each type of a PNG, by type."""
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    chunks, at = {}, 8
    while at < len(png):
        (length,) = struct.unpack(">I", png[at : at + 4])
        kind = png[at + 4 : at + 8]
        chunks.setdefault(kind, png[at + 8 : at + 8 + length])
        at += 12 + length
    return chunks


def _first_frame(png: bytes, tmp_path) -> np.ndarray:
    path = tmp_path / "inline.png"
    path.write_bytes(png)
    width, height, codes = _opalray.read_png_rgb8(str(path))
    return np.frombuffer(codes, np.uint8).reshape(height, width, 3)


@pytest.fixture(scope="module")
def tilted():
    """A black-opal sweep over tilt, 3 frames of 64 × 48."""
    scene = opalray.Scene.preset("black-opal").replace(render={"width": 64, "height": 48})
    return opalray.sweep(scene, tilt_deg=[-20.0, -10.0, 0.0])


def test_sweep_repr_is_one_short_line(tilted):
    text = repr(tilted)
    assert len(text) < _SHORT and "\n" not in text, text
    assert "3 frames" in text and "tilt -20° … 0°" in text and "64×48" in text


def test_sweep_shows_itself_as_an_animation_there_and_back(tilted, tmp_path):
    png = _data_png(tilted._repr_html_())
    chunks = _chunks(png)
    width, height = struct.unpack(">II", chunks[b"IHDR"][:8])
    assert (width, height) == (64, 48)
    # acTL: the frame count; 3 frames forth and the middle one back.
    (frames,) = struct.unpack(">I", chunks[b"acTL"][:4])
    assert frames == 4
    np.testing.assert_array_equal(_first_frame(png, tmp_path), tilted.frames[0])


def test_inline_animation_of_large_frames_is_reduced(tmp_path):
    # A 640 × 480 checkerboard of 0 and 200 reduces by 2 to a flat 100.
    checker = ((np.indices((480, 640)).sum(axis=0) % 2) * 200).astype(np.uint8)
    frame = np.repeat(checker[:, :, None], 3, axis=2)
    sweep = opalray.Sweep(angles_deg=[0.0, 1.0], frames=[frame, frame], rendered=[0, 1], moves="tilt")
    png = _data_png(sweep._repr_html_())
    assert len(png) < 20_000
    shown = _first_frame(png, tmp_path)
    assert shown.shape == (240, 320, 3)
    assert np.all(shown == 100)


def test_preview_frame_is_the_block_mean():
    from opalray._notebook import preview_frame

    rng = np.random.default_rng(1)
    frame = rng.integers(0, 256, size=(97, 701, 3), dtype=np.uint8)
    small = preview_frame(frame)
    # 701 px: the smallest whole factor to ≤ 320 is 3; 97 // 3 = 32 rows, 701 // 3 = 233 columns.
    assert small.shape == (32, 233, 3)
    for y, x in [(0, 0), (31, 232), (17, 100)]:
        block = frame[3 * y : 3 * y + 3, 3 * x : 3 * x + 3].astype(float)
        np.testing.assert_array_equal(small[y, x], np.floor(block.mean(axis=(0, 1)) + 0.5))
    np.testing.assert_array_equal(preview_frame(frame[:48, :64]), frame[:48, :64])


def test_stages_optics_and_structure_reprs_are_short():
    stages = opalray.prepare(small_scene())
    for value, words in [
        (stages, ["two-pass", "64×48"]),
        (stages.optics, ["181 angles", "40 bins", "n_eff"]),
        (stages.structure, ["100×75×25 cells"]),
    ]:
        text = repr(value)
        assert len(text) < _SHORT and "\n" not in text, text
        assert all(w in text for w in words), text


def test_scene_repr_names_the_fields_its_method_reads():
    paper = repr(opalray.Scene.preset("paper"))
    assert "method=two-pass" in paper and "grid=[100, 75, 25]" in paper and "light_angle_deg=30" in paper
    assert "cut=" not in paper and "environment=" not in paper
    gem = repr(opalray.Scene.preset("black-opal"))
    for word in ["method=lobe", "cut=cabochon", "domains=grains", "body_tone=1", "environment=studio"]:
        assert word in gem, gem
    # No light in the gem preset, and the paper's cell grid is not what the lobe method reads.
    assert "light" not in gem and "grid=" not in gem
    assert "light=directional at 30°" in repr(opalray.Scene.preset("paper-path"))
    assert all(len(repr(opalray.Scene.preset(p))) < _SHORT for p in opalray.presets())
