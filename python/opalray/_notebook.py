"""How results show themselves in Jupyter: a sweep as an inline animation (an APNG in an
``<img>``, small), and one-line summaries of scenes for their method."""

from __future__ import annotations

import base64
import html
import os
import tempfile
from collections.abc import Mapping, Sequence

import numpy as np

from . import _opalray

__all__ = ["animation_html", "preview_frame", "scene_summary"]

# The longest side of an inline animation's frames, pixels: a 640 × 480 sweep of 9 frames
# shows at 320 × 240, some hundreds of kB in the notebook instead of megabytes.
INLINE_MAX_PX = 320


def preview_frame(frame: np.ndarray, max_px: int = INLINE_MAX_PX) -> np.ndarray:
    """``frame`` (H × W × 3 uint8 display codes) reduced by the smallest whole factor that
    brings its longest side to ``max_px`` or less: the mean of each factor × factor block
    (the last rows and columns that fill no block are dropped). A frame that fits is returned
    as it is."""
    height, width = frame.shape[:2]
    factor = -(-max(height, width) // max_px)
    if factor <= 1:
        return frame
    h, w = height // factor, width // factor
    blocks = frame[: h * factor, : w * factor].reshape(h, factor, w, factor, 3)
    return np.rint(blocks.mean(axis=(1, 3), dtype=np.float64)).astype(np.uint8)


def animation_html(frames: Sequence[np.ndarray], delay_ms: int, caption: str) -> str:
    """An ``<img>`` of the frames as a looping APNG, there and back again (a stone rocked to
    and fro, a light swung and returned), each frame reduced by :func:`preview_frame`, with
    ``caption`` under it."""
    small = [np.ascontiguousarray(preview_frame(f)) for f in frames]
    loop = small + small[-2:0:-1]
    height, width = small[0].shape[:2]
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "sweep.png")
        _opalray.write_animation(path, [f.tobytes() for f in loop], width, height, delay_ms)
        with open(path, "rb") as f:
            data = base64.b64encode(f.read()).decode("ascii")
    text = html.escape(caption)
    return (
        f'<figure style="margin:0"><img src="data:image/png;base64,{data}" width="{width}" '
        f'height="{height}" alt="{text}"><figcaption>{text}</figcaption></figure>'
    )


def _light(s: Mapping) -> str | None:
    light = s["light"]
    if light["kind"] == "none":
        return None
    return f"light={light['kind']} at {light['angle_deg']:g}°"


def _stone(s: Mapping) -> list[str]:
    """The stone model's fields that shape what the stone methods render."""
    domains, body = s["domains"], s["body"]
    parts = [f"cut={body['cut']}", f"domains={domains['pattern']}"]
    if domains["pattern"] == "grains":
        parts.append(f"grain_size_mm={domains['grain_size_mm']:g}")
    parts += [f"orientation={domains['orientation']}", f"body_tone={s['render']['body_tone']}"]
    return parts


def scene_summary(s: Mapping) -> list[str]:
    """``field=value`` strings of the fields that the scene's method reads and that set what
    it shows: the paper's cell grid and light for a method that renders the grid (``two-pass``);
    the stone model (cut, domains, body tone), the lights and the samples for one that renders
    the stone (``path``, ``stored``, ``lobe``), and the environment where it sees one."""
    method = s["integrator"]["method"]
    reads = _opalray.integrator_reads(method) or {"renders_stone": True, "sees_environment": True}
    parts = [f"method={method}", f"sphere_diameter_nm={s['crystal']['sphere_diameter_nm']:g}"]
    if not reads["renders_stone"]:
        parts += [f"grid={s['structure']['grid']}", f"light_angle_deg={s['light']['angle_deg']:g}"]
    else:
        parts += _stone(s)
        light = _light(s)
        if light is not None:
            parts.append(light)
        environment = s["environment"]
        if reads["sees_environment"] and environment["kind"] != "none":
            kind = environment["kind"]
            parts.append(f"environment={os.path.basename(environment['path']) if kind == 'file' else kind}")
        camera = s["camera"]
        if camera["tilt_deg"] or camera["turn_deg"]:
            parts.append(f"tilt/turn={camera['tilt_deg']:g}°/{camera['turn_deg']:g}°")
        parts.append(f"spp={s['integrator']['spp']}")
    parts += [f"size={s['render']['width']}x{s['render']['height']}", f"bins={s['spectrum']['bins']}"]
    return parts
