"""Sweeps of the light angle (the paper's fig. 11), of the stone rocked (tilt) or turned, or of
the environment turned, and parameter studies, locally or on a Dask cluster, one task per frame
or per scene."""

from __future__ import annotations

import hashlib
import json
import os
import re
import threading
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Sequence

import numpy as np

from . import _opalray
from ._notebook import animation_html
from ._render import Progress, Stages, _progress_of
from ._scene import Scene, as_scene

__all__ = ["Sweep", "sweep", "map", "sweep_angles"]

_MANIFEST = "sweep.json"
_SCENE_FILE = "scene.toml"

# Prepared scenes of this process, by their TOML text: a Dask worker grows a structure and
# builds its optics once for all the frames of a sweep it is given.
_prepared: dict[str, Stages] = {}
_prepared_lock = threading.Lock()
_PREPARED_KEPT = 4


def _stages_for(scene: Scene, time_left: float | None = None) -> Stages:
    """The prepared ``scene`` of this process, prepared now (within ``time_left`` seconds,
    ``TimeoutError`` past them) if it is not kept."""
    key = scene.to_toml()
    with _prepared_lock:
        stages = _prepared.get(key)
    if stages is None:
        stages = Stages(_opalray.prepare(scene.to_dict(), time_left), scene)
        with _prepared_lock:
            while len(_prepared) >= _PREPARED_KEPT:
                _prepared.pop(next(iter(_prepared)))
            _prepared[key] = stages
    return stages


def _worker_threads() -> int | None:
    """The threads of the Dask worker running this task (None outside a worker)."""
    try:
        from distributed import get_worker

        return get_worker().state.nthreads
    except (ImportError, ValueError, AttributeError):
        return None


# What a sweep moves: its keyword of `sweep`, its default range and its valid range, degrees
# (as `opalray sweep --light-from`, `--tilt-from`, `--turn-from`, `--env-from`).
_MOVES = {
    "light": ("light_angles", (-60.0, 60.0), (-89.0, 89.0)),
    "tilt": ("tilt_deg", (-30.0, 30.0), (-89.0, 89.0)),
    "turn": ("turn_deg", (-45.0, 45.0), (-360.0, 360.0)),
    "environment": ("env_rotation_deg", (-90.0, 90.0), (-360.0, 360.0)),
}


def _why_still(scene: Scene, moves: str) -> str | None:
    """Why moving ``moves`` changes nothing in ``scene`` (None where it moves something): the
    rule of ``opalray sweep``."""
    if moves == "light" and scene["light"]["kind"] == "none":
        return 'the scene has no light (light.kind = "none")'
    if moves == "environment":
        method = scene["integrator"]["method"]
        if not _opalray.integrator_reads(method)["sees_environment"]:
            return f'its renderer sees no environment (integrator.method = "{method}")'
        if scene["environment"]["kind"] in ("none", "uniform"):
            return (
                "the scene's environment is the same in every direction about the stone's normal "
                '(environment.kind = "none" or "uniform")'
            )
    return None


def _choose_moves(scene: Scene, given: dict[str, Sequence[float] | None]) -> tuple[str, list[float]]:
    """What moves and its values: the one keyword given, else the light where the scene has
    one, else the tilt; a keyword that moves nothing in ``scene`` is refused."""
    named = [m for m, (kw, _, _) in _MOVES.items() if given[kw] is not None]
    if len(named) > 1:
        raise ValueError(
            f"{_MOVES[named[0]][0]} and {_MOVES[named[1]][0]}: a sweep moves one thing; give one of them"
        )
    moves = named[0] if named else ("light" if _why_still(scene, "light") is None else "tilt")
    keyword, default, (lo, hi) = _MOVES[moves]
    why = _why_still(scene, moves)
    if why is not None:
        movable = ", ".join(kw for m, (kw, _, _) in _MOVES.items() if _why_still(scene, m) is None)
        raise ValueError(f"{keyword}: {why}, so it moves nothing; what moves in this scene: {movable}")
    values = given[keyword]
    values = [float(v) for v in (sweep_angles(9, *default) if values is None else values)]
    if not 1 <= len(values) <= 1000:
        raise ValueError(f"{keyword}: {len(values)} values, must be 1 to 1000; try 9")
    for v in values:
        if not (np.isfinite(v) and lo <= v <= hi):
            what = "light angle" if moves == "light" else moves
            raise ValueError(f"{keyword} {v}: the {what} must be within {lo}° … {hi}°; try {default[0]:g} and {default[1]:g}")
    return moves, values


def _render_posed(
    stages: Stages, moves: str, value: float, threads: int | None = None, time_limit: float | None = None
) -> bytes:
    """One sweep frame's display codes: ``value`` degrees of what ``moves`` moves;
    ``TimeoutError`` past ``time_limit`` seconds."""
    if moves == "light":
        return stages._stages.render_rgb8(float(value), threads, time_limit)
    scene = stages.scene
    pose = [scene["camera"]["tilt_deg"], scene["camera"]["turn_deg"], scene["environment"]["rotation_deg"]]
    pose[["tilt", "turn", "environment"].index(moves)] = value
    return stages._stages.render_posed_rgb8(*pose, threads, time_limit)


# Longest ``time_limit``, seconds (a week, as the command's ``--time-limit``).
_MAX_TIME_LIMIT_S = 7 * 24 * 3600.0


class _Deadline:
    """``sweep``'s ``time_limit``: the time left for each stage, counted from the call, and
    the error naming the stage it passed in."""

    def __init__(self, time_limit: float | None, start: float, out_dir: str | None):
        if time_limit is not None:
            ok = isinstance(time_limit, (int, float)) and not isinstance(time_limit, bool)
            if not (ok and 0 < time_limit <= _MAX_TIME_LIMIT_S):
                raise ValueError(
                    f"time_limit {time_limit!r}: must be a number of seconds above 0 and at most "
                    f"{_MAX_TIME_LIMIT_S}; try 60"
                )
        self.time_limit, self.start, self.out_dir = time_limit, start, out_dir

    def left(self, stage: str) -> float | None:
        """Seconds left for ``stage`` (None without a limit); raises if none are."""
        if self.time_limit is None:
            return None
        left = self.start + self.time_limit - time.perf_counter()
        if left <= 0:
            raise self.passed(stage)
        return left

    def passed(self, stage: str) -> TimeoutError:
        kept = (
            "no sheet or animation was written (the frames finished in out_dir stay: the same "
            "call renders only the rest)"
            if self.out_dir is not None
            else "nothing was written"
        )
        return TimeoutError(
            f"time_limit {self.time_limit}: the limit passed during {stage} (it counts from the "
            f"call, the stone's preparation included); {kept}; raise time_limit, or sweep fewer "
            "angles or a smaller image (render.width, render.height)"
        )

    def run(self, stage: str, work: Callable[[float | None], Any]) -> Any:
        """``work(seconds_left)``, its ``TimeoutError`` named as the sweep's ``stage``."""
        try:
            return work(self.left(stage))
        except TimeoutError:
            raise self.passed(stage) from None


@dataclass(frozen=True)
class _Stopped:
    """A Dask task's answer when the sweep's limit passed before or during it (an answer, not
    an error, so that the workers log nothing); ``in_preparation``: it passed while the task
    prepared the stone."""

    in_preparation: bool


def _time_left(deadline_s: float | None) -> float | None:
    """Seconds left to ``deadline_s`` (``time.time()`` seconds; None: no limit); raises
    ``TimeoutError`` if none are."""
    if deadline_s is None:
        return None
    left = deadline_s - time.time()
    if left <= 0:
        raise TimeoutError("the limit passed before the stage began")
    return left


def _render_frame(
    scene: Scene, moves: str, value: float, threads: int | None = None, deadline_s: float | None = None
) -> bytes | _Stopped:
    """One sweep frame's display codes: a Dask task. It renders on ``threads`` threads, by
    default as many as its worker has, so that single-threaded workers run one frame per
    core instead of each spreading its frame over every core of the machine. Under a
    ``time_limit`` the task is given the time left to the sweep's ``deadline_s`` (wall-clock
    seconds, ``time.time()``) for its preparation and for its frame: past it, its stage stops
    (freeing the worker's cores) and it answers ``_Stopped``."""
    try:
        stages = _stages_for(scene, _time_left(deadline_s))
    except TimeoutError:
        return _Stopped(in_preparation=True)
    try:
        return _render_posed(stages, moves, value, threads or _worker_threads(), _time_left(deadline_s))
    except TimeoutError:
        return _Stopped(in_preparation=False)


def _sweep_on_dask(
    client: Any, scene: Scene, moves: str, angles: list[float], missing: list[int],
    deadline: _Deadline, finish: Callable[[int, bytes], None],
) -> None:
    """Render the ``missing`` frames on ``client``'s cluster, one task per frame, each handed
    to ``finish`` as it completes. Under ``deadline``'s limit each task gets the time left, and
    past it the frames not finished are cancelled and ``TimeoutError`` names the stage
    (the stone's preparation where the first task to stop stopped in it, else the first
    frame not finished)."""
    from dask.distributed import as_completed
    from distributed import TimeoutError as DaskTimeoutError

    n = len(angles)
    left = deadline.left("the stone's preparation")
    deadline_s = None if left is None else time.time() + left
    # A key of its own (hash=False): a content-hashed key can name data that the last
    # sweep's release is still deleting ("lost dependencies").
    scene_future = client.scatter(scene, broadcast=True, hash=False)
    tail, tail_threads = _tail_split(client, len(missing))
    body = missing[: len(missing) - tail]
    futures = {
        client.submit(_render_frame, scene_future, moves, angles[k], None, deadline_s, pure=False): k
        for k in body
    }
    # The tail after the rest (a lower priority), each frame on more threads.
    futures.update({
        client.submit(_render_frame, scene_future, moves, angles[k], tail_threads, deadline_s, pure=False,
                      priority=-1): k
        for k in missing[len(body):]
    })
    pending = set(futures.values())
    stopped: str | None = None  # the stage the limit passed in
    try:
        for future in as_completed(futures, timeout=None if left is None else left + _DASK_GRACE_S):
            k = futures[future]
            codes = future.result()
            if isinstance(codes, _Stopped):
                first = f"frame {min(pending) + 1} of {n}"
                stopped = "the stone's preparation" if codes.in_preparation else first
                break
            pending.discard(k)
            finish(k, codes)
    except DaskTimeoutError:  # no task answered in time
        stopped = f"frame {min(pending) + 1} of {n}"
    finally:
        client.cancel([f for f, k in futures.items() if k in pending])
    if stopped is not None:
        raise deadline.passed(stopped)


# How long past the limit a Dask sweep waits for its tasks' own TimeoutError (which names the
# stage) before it names the first unfinished frame itself.
_DASK_GRACE_S = 0.5


def _tail_split(client: Any, frames: int) -> tuple[int, int | None]:
    """``(tail, threads)``: the last ``tail`` frames of a sweep render on ``threads`` threads
    each, after the others. With one frame per worker thread, the frames beyond a multiple
    of the cluster's threads would leave most of them idle at the end (9 frames on two
    single-threaded workers: 5 frame-times instead of 4.5); spread over the threads left,
    they keep every core busy. ``threads`` is at most what the workers on one host have
    between them, so a tail frame asks for no more cores than its host's workers hold;
    ``(0, None)`` where nothing is gained."""
    try:
        info = client.scheduler_info(n_workers=-1)  # every worker, not the first few
    except TypeError:
        info = client.scheduler_info()
    workers = list(info.get("workers", {}).values())
    per_host: dict[str, int] = {}
    for w in workers:
        per_host[w.get("host", "")] = per_host.get(w.get("host", ""), 0) + int(w.get("nthreads", 1))
    total = sum(per_host.values())
    if total < 2:
        return 0, None
    tail = frames % total
    threads = min(-(-total // tail), min(per_host.values())) if tail else 1
    if threads <= max(int(w.get("nthreads", 1)) for w in workers):
        return 0, None
    return tail, threads


def sweep_angles(frames: int = 9, start_deg: float = -60.0, stop_deg: float = 60.0) -> list[float]:
    """``frames`` light angles evenly spaced from ``start_deg`` to ``stop_deg``, computed as
    ``opalray sweep --from --to --frames`` computes them."""
    if not 1 <= frames <= 1000:
        raise ValueError(f"frames {frames}: must be 1 to 1000; try 9")
    if frames == 1:
        return [float(start_deg)]
    return [start_deg + (stop_deg - start_deg) * k / (frames - 1) for k in range(frames)]


@dataclass(repr=False)
class Sweep:
    """The result of :func:`sweep`: ``moves`` (``"light"``, ``"tilt"``, ``"turn"`` or
    ``"environment"``) and ``angles_deg``, its values, degrees; ``frames``, one H × W × 3
    uint8 array per value (display codes); ``rendered``, the indices rendered by this call
    (the others were read back from ``out_dir``); the paths written; ``seconds``, the wall
    time; ``delay_ms``, each frame's time in its animations. In Jupyter it shows itself as
    an animation, there and back again, at most 320 pixels wide or high."""

    angles_deg: list[float]
    frames: list[np.ndarray]
    rendered: list[int]
    moves: str = "light"
    sheet: str | None = None
    animation: str | None = None
    frame_paths: list[str] = field(default_factory=list)
    seconds: float = 0.0
    delay_ms: int = 120

    def _caption(self) -> str:
        if not self.angles_deg:
            return "no frames"
        first, last = self.angles_deg[0], self.angles_deg[-1]
        what = "light angle" if self.moves == "light" else self.moves
        return f"{len(self.frames)} frames, {what} {first:g}° … {last:g}°"

    def _repr_html_(self) -> str | None:
        if not self.frames:
            return None
        return animation_html(self.frames, self.delay_ms, self._caption())

    def __repr__(self) -> str:
        height, width = self.frames[0].shape[:2] if self.frames else (0, 0)
        return (
            f"<opalray.Sweep {self._caption()}, {width}×{height}, "
            f"{len(self.rendered)} rendered in {self.seconds:.1f} s>"
        )


def _read_manifest(out_dir: str, manifest: dict, n: int) -> list[str | None]:
    """The checksums of the frames ``out_dir`` holds of the sweep ``manifest`` (None where
    none is trusted). A folder with files but no manifest, or a manifest that is not one of
    ours, is refused; a manifest that cannot be read trusts no frame (all are rendered again);
    one of another sweep is refused."""
    path = os.path.join(out_dir, _MANIFEST)
    if not os.path.lexists(path):
        if any(not name.startswith(".opalray-") for name in os.listdir(out_dir)):
            raise ValueError(
                f"out_dir {out_dir}: holds files but no {_MANIFEST} of opalray, so it is not a "
                "sweep's folder; use a new or empty folder"
            )
        return [None] * n
    if not os.path.isfile(path):
        raise ValueError(f"out_dir {out_dir}: its {_MANIFEST} is not a regular file; use a new or empty folder")
    try:
        with open(path, encoding="utf-8") as f:
            found = json.load(f)
    except (OSError, ValueError):
        return [None] * n
    if not (isinstance(found, dict) and all(k in found for k in manifest)):
        raise ValueError(
            f"out_dir {out_dir}: its {_MANIFEST} was not written by opalray; use a new or empty folder"
        )
    if {k: found[k] for k in manifest} != manifest:
        raise ValueError(
            f"out_dir {out_dir}: holds a sweep of another scene or other angles; "
            "use a new folder or empty this one"
        )
    checksums = found.get("checksums")
    if not (isinstance(checksums, list) and len(checksums) == n):
        return [None] * n
    return [c if isinstance(c, str) else None for c in checksums]


def _write_manifest(out_dir: str, manifest: dict) -> None:
    """Write ``sweep.json`` whole or not at all (a temporary file, then a rename)."""
    path = os.path.join(out_dir, _MANIFEST)
    temp = os.path.join(out_dir, f".opalray-{_MANIFEST}.{os.getpid()}.tmp")
    with open(temp, "w", encoding="utf-8") as f:
        json.dump(manifest, f, indent=1)
    os.replace(temp, path)


def _checksum(path: str) -> str:
    """SHA-256 of a file's bytes, hex."""
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def _check_out(path: str, allowed: tuple[str, ...], what: str) -> None:
    if os.path.splitext(path)[1].lower() not in allowed:
        raise ValueError(f"{what} {path}: unsupported file type; use a name ending in {' or '.join(allowed)}")


# The names a frames folder holds of its own.
_FOLDER_NAME = re.compile(r"frame-\d{4}\.png|sweep\.json|scene\.toml")


def _check_outputs(
    out_dir: str | None, sheet: str | None, animation: str | None
) -> tuple[str | None, str | None]:
    """Check ``out_dir`` and the outputs before any file is written, as ``opalray sweep``
    checks ``--frames-dir``, ``--sheet`` and ``--animation``: a ``ValueError`` naming the
    argument at fault. Returns the sheet's and the animation's paths (relative ones under
    ``out_dir``)."""
    if out_dir is not None and os.path.lexists(out_dir) and not os.path.isdir(out_dir):
        raise ValueError(f"out_dir {out_dir}: exists and is not a folder; use a new or empty folder")
    paths: list[str | None] = []
    for given, allowed, what in ((sheet, (".png",), "sheet"), (animation, (".gif", ".png"), "animation")):
        if given is None:
            paths.append(None)
            continue
        _check_out(given, allowed, what)
        path = given
        if out_dir is not None and not os.path.isabs(path):
            path = os.path.join(out_dir, path)
        folder = os.path.dirname(os.path.abspath(path))
        if out_dir is not None and os.path.abspath(path) == os.path.abspath(out_dir):
            raise ValueError(f"{what} {given}: is out_dir; give the {what} a name of its own")
        if os.path.isdir(path):
            raise ValueError(f"{what} {given}: is a folder; give a file name")
        if out_dir is not None and folder == os.path.abspath(out_dir):
            if _FOLDER_NAME.fullmatch(os.path.basename(path)):
                raise ValueError(
                    f"{what} {given}: would overwrite a file of out_dir's own (frames, "
                    f"{_MANIFEST}, {_SCENE_FILE}); give another name"
                )
        elif not os.path.isdir(folder):
            raise ValueError(f"{what} {given}: its folder {folder} does not exist; create it first")
        if path in paths or (paths and paths[0] and os.path.abspath(path) == os.path.abspath(paths[0])):
            raise ValueError(f"{what} {given}: the same file as sheet; give each output its own name")
        paths.append(path)
    return paths[0], paths[1]


def sweep(
    scene: Scene | dict | str | os.PathLike | None = None,
    light_angles: Sequence[float] | None = None,
    *,
    tilt_deg: Sequence[float] | None = None,
    turn_deg: Sequence[float] | None = None,
    env_rotation_deg: Sequence[float] | None = None,
    client: Any = None,
    out_dir: str | os.PathLike | None = None,
    sheet: str | os.PathLike | None = None,
    animation: str | os.PathLike | None = None,
    columns: int | None = None,
    delay_ms: int = 120,
    progress: Progress | bool | None = None,
    time_limit: float | None = None,
    **overrides: Any,
) -> Sweep:
    """Render ``scene`` (default: the preset of ``opalray render``) at every light angle of
    ``light_angles``, or rocked to every tilt of ``tilt_deg`` (``camera.tilt_deg``), turned
    to every ``turn_deg`` (``camera.turn_deg``), or with the environment at every rotation of
    ``env_rotation_deg`` (``environment.rotation_deg``), degrees; one of them. Given none,
    as ``opalray sweep``: 9 light angles from −60° to 60° where the scene has a light, else 9
    tilts from −30° to 30°. One that moves nothing in the scene (the light of a scene without
    one, the environment of the paper's two passes) is refused with a ``ValueError`` naming
    what would move. Frames are at the scene's image size.

    ``client``: a ``dask.distributed.Client``: one task per frame on its cluster (each worker
    prepares the structure and optics once); None renders here, one frame at a time, each on
    every core. ``out_dir``: write ``frame-NNNN.png`` per frame there (named as by ``opalray
    sweep --frames-dir``) (with ``scene.toml`` and
    ``sweep.json``), and the sheet (default ``sweep.png``) and animation; a run into a folder
    that already holds some frames of the same scene and angles renders only the missing ones.
    ``sheet``/``animation`` (relative paths go under ``out_dir``): the contact sheet (PNG) and
    an animation (``.gif``, or ``.png`` for APNG), byte for byte those of ``opalray sweep``.
    ``progress``: a callable ``(stage, done, total)`` per frame, or ``True`` for a tqdm bar.
    ``time_limit``: seconds, counted from the call, bounding the stone's preparation and every
    frame (as ``opalray sweep --time-limit``; with ``client`` each task is given the time
    left, and the frames not finished when it is spent are cancelled): past it
    ``TimeoutError`` names the stage, no sheet or animation is written, and the frames
    finished in ``out_dir`` stay there for the same call to reuse.
    """
    start = time.perf_counter()
    scene = as_scene(scene, **overrides)
    moves, angles = _choose_moves(
        scene,
        {"light_angles": light_angles, "tilt_deg": tilt_deg, "turn_deg": turn_deg, "env_rotation_deg": env_rotation_deg},
    )
    width, height = scene["render"]["width"], scene["render"]["height"]
    n = len(angles)
    deadline = _Deadline(time_limit, start, None if out_dir is None else os.fspath(out_dir))

    # Where the files go, and which frames are already there.
    frame_paths: list[str] = []
    frames: list[bytes | None] = [None] * n
    if out_dir is not None:
        out_dir = os.fspath(out_dir)
        if sheet is None:
            sheet = "sweep.png"
    sheet_path, animation_path = _check_outputs(
        out_dir,
        None if sheet is None else os.fspath(sheet),
        None if animation is None else os.fspath(animation),
    )
    if out_dir is not None:
        os.makedirs(out_dir, exist_ok=True)
        manifest = {"moves": moves, "angles_deg": angles, "scene": scene.to_toml()}
        checksums = _read_manifest(out_dir, manifest, n)
        manifest["checksums"] = checksums
        scene.save(os.path.join(out_dir, _SCENE_FILE))
        _write_manifest(out_dir, manifest)
        frame_paths = [os.path.join(out_dir, f"frame-{k:04d}.png") for k in range(n)]
        for k, path in enumerate(frame_paths):
            # Only a regular file whose bytes match the manifest's checksum is reused.
            if checksums[k] is not None and os.path.isfile(path) and _checksum(path) == checksums[k]:
                w, h, codes = _opalray.read_png_rgb8(path)
                if (w, h) == (width, height):
                    frames[k] = codes
    missing = [k for k in range(n) if frames[k] is None]
    report, close = _progress_of(progress, n, "sweep")
    done = n - len(missing)

    def finish(k: int, codes: bytes) -> None:
        nonlocal done
        frames[k] = codes
        if frame_paths:
            _opalray.write_png_rgb8(frame_paths[k], width, height, codes)
            manifest["checksums"][k] = _checksum(frame_paths[k])
            _write_manifest(out_dir, manifest)
        done += 1
        if report:
            report(f"{round(angles[k], 1):g}°", done, n)

    try:
        if client is None:
            if missing:
                stages = deadline.run(
                    "the stone's preparation", lambda left: Stages(_opalray.prepare(scene.to_dict(), left), scene)
                )
                for k in missing:
                    codes = deadline.run(
                        f"frame {k + 1} of {n}", lambda left: _render_posed(stages, moves, angles[k], None, left)
                    )
                    finish(k, codes)
        elif missing:
            _sweep_on_dask(client, scene, moves, angles, missing, deadline, finish)
    finally:
        close()

    if sheet_path is not None:
        _opalray.write_sheet(sheet_path, frames, angles, width, height, columns or min(n, 9))
    if animation_path is not None:
        _opalray.write_animation(animation_path, frames, width, height, delay_ms)
    return Sweep(
        moves=moves,
        angles_deg=angles,
        frames=[np.frombuffer(f, np.uint8).reshape(height, width, 3) for f in frames],
        rendered=missing,
        sheet=sheet_path,
        animation=animation_path,
        frame_paths=frame_paths,
        seconds=time.perf_counter() - start,
        delay_ms=delay_ms,
    )


def map(fn: Callable[[Any], Any], items: Iterable[Any], client: Any = None, **submit: Any) -> list:
    """``[fn(x) for x in items]``, locally or, given a Dask ``client``, one task per item on
    its cluster (results in the order of ``items``). ``fn`` is typically ``opalray.render``
    or a function of a scene that returns a few numbers; ``Image`` results travel as arrays.
    ``submit``: extra keyword arguments of ``client.map`` (``resources=``, ``retries=`` …)."""
    items = list(items)
    if client is None:
        return [fn(x) for x in items]
    submit.setdefault("pure", False)
    return client.gather(client.map(fn, items, **submit))
