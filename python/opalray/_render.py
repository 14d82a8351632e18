"""Rendering: ``render`` for one image, ``prepare`` for the stages as arrays and many renders
of one structure. The work runs in the Rust core with the GIL released."""

from __future__ import annotations

import json
import os
import tempfile
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from . import _opalray
from ._light import StoredLight
from ._scene import Scene, as_scene
from ._stone import Stone

__all__ = ["Image", "Stages", "Structure", "Optics", "light_pass", "prepare", "render"]

Progress = Callable[[str, int, int], None]

# The most samples per pixel (`integrator.spp`), which a time-limited render aims at.
_MAX_SPP = _opalray.MAX_SPP


def _progress_of(progress: Progress | bool | None, total: int, desc: str) -> tuple[Progress | None, Callable[[], None]]:
    """A callback ``(stage, done, total)`` for ``progress``: a callable is used as it is;
    ``True`` draws a tqdm bar (if tqdm is installed). Returns the callback and a closer."""
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError as e:
            raise ImportError("progress=True draws a tqdm bar: pip install tqdm, or pass a callable") from e
        bar = tqdm(total=total, desc=desc)

        def update(stage: str, done: int, total: int) -> None:
            if bar.total != total:  # the lobe integrator's rows, after its stages
                bar.total = total
            bar.set_postfix_str(stage)
            bar.update(done - bar.n)

        return update, bar.close
    return (progress or None), (lambda: None)


class Image:
    """A rendered image. Arrays are computed on first access and cached.

    Attributes: ``rgb`` (H × W × 3 float32, linear, scene-referred), ``srgb8`` (H × W × 3
    uint8, the display codes), ``spectral`` (H × W × bins float32), ``wavelengths_nm`` (bins,
    float64, bin centres), ``stats`` (dict: the fields of ``opalray render --stats``),
    ``scene``.
    """

    def __init__(self, frame: Any, scene: Scene):
        self._frame = frame
        self.scene = scene
        self._cache: dict[str, Any] = {}

    def _get(self, name: str) -> Any:
        if name not in self._cache:
            value = getattr(self._frame, name)()
            if isinstance(value, np.ndarray):
                value.setflags(write=False)
            self._cache[name] = value
        return self._cache[name]

    @property
    def rgb(self) -> np.ndarray:
        return self._get("rgb")

    @property
    def srgb8(self) -> np.ndarray:
        return self._get("srgb8")

    @property
    def spectral(self) -> np.ndarray:
        return self._get("spectral")

    @property
    def wavelengths_nm(self) -> np.ndarray:
        return self._get("wavelengths_nm")

    @property
    def stats(self) -> dict:
        return json.loads(self._frame.stats_json())

    @property
    def width(self) -> int:
        return self.scene["render"]["width"]

    @property
    def height(self) -> int:
        return self.scene["render"]["height"]

    def save(self, path: str | os.PathLike, *, spectral: bool = False) -> None:
        """Write the image as the CLI does: ``.png`` (sRGB, ``color.bit_depth`` bits) or
        ``.exr`` (linear RGB); with ``spectral=True``, the spectral image as OpenEXR with one
        channel per bin (``S0.<λ>nm``). Files are written atomically."""
        path = os.fspath(path)
        ext = os.path.splitext(path)[1].lower()
        if spectral:
            if ext != ".exr":
                raise ValueError(f"{path}: unsupported file type; use a name ending in .exr")
            self._frame.write_spectral_exr(path)
        elif ext == ".png":
            self._frame.write_png(path)
        elif ext == ".exr":
            self._frame.write_exr(path)
        else:
            raise ValueError(f"{path}: unsupported file type; use a name ending in .png or .exr")

    def _repr_png_(self) -> bytes:
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "image.png")
            self.save(path)
            with open(path, "rb") as f:
                return f.read()

    def __repr__(self) -> str:
        return f"<opalray.Image {self.width}×{self.height}, {len(self.wavelengths_nm)} bins>"

    def __reduce__(self):
        # Pickled as its arrays (for Dask and multiprocessing).
        return (
            _image_from_state,
            (np.asarray(self.spectral), np.asarray(self.rgb), self.scene, self._frame.stats_json()),
        )


def _image_from_state(spectral: np.ndarray, rgb: np.ndarray, scene: Scene, stats_json: str) -> Image:
    frame = _opalray.Frame.from_arrays(
        np.ascontiguousarray(spectral, np.float32),
        np.ascontiguousarray(rgb, np.float32),
        scene.to_dict(),
        stats_json,
    )
    return Image(frame, scene)


@dataclass(frozen=True)
class Structure:
    """The stone as the paper's cells (paper §2.4, fig. 9): the grown structure where the
    domains are the paper's growth, any other stone (grains) read at the cell centres of
    ``[structure]``'s grid laid over the stone's box. Arrays are indexed ``[z, y, x]``.

    ``cells`` (uint8): ``OUTSIDE`` 0, ``VOID`` 1, ``CLUSTER`` 2. ``orientations`` (float32,
    … × 4): the lattice → stone rotation of each cell as a unit quaternion ``(x, y, z, w)``
    (scalar last, as ``scipy.spatial.transform.Rotation.from_quat``), identity where no
    cluster. ``normals`` (float32, … × 3): the (111) plane normal in the stone frame.
    ``grid`` = (nx, ny, nz); lengths in mm; ``stats``: void ratio, counts, growth steps
    (none for a stone read at the centres).
    """

    OUTSIDE = 0
    VOID = 1
    CLUSTER = 2
    cells: np.ndarray
    orientations: np.ndarray
    normals: np.ndarray
    grid: tuple[int, int, int]
    semi_axes_mm: tuple[float, float, float]
    cell_size_mm: tuple[float, float, float]
    stats: dict = field(default_factory=dict)

    def __repr__(self) -> str:
        nx, ny, nz = self.grid
        a, b, c = self.semi_axes_mm
        clusters = int(np.count_nonzero(self.cells == self.CLUSTER))
        return (
            f"<opalray.Structure {nx}×{ny}×{nz} cells, semi-axes {a:g} × {b:g} × {c:g} mm, "
            f"{clusters} cluster cells>"
        )


@dataclass(frozen=True)
class Optics:
    """One cluster's optics tables (paper §3.1): rows are angles inside the stone between a ray
    and the (111) normal, uniform in cos θ from 1 (normal) to 0 (grazing); columns are
    wavelength bins. ``reflectance`` R (specular, Bragg), ``transmittance`` T, ``diffuse``
    D, each ``angles × bins`` float32 with R + T + D = 1."""

    reflectance: np.ndarray
    transmittance: np.ndarray
    diffuse: np.ndarray
    cos_theta: np.ndarray
    theta_deg: np.ndarray
    wavelengths_nm: np.ndarray
    n_eff: float
    d111_nm: float

    def __repr__(self) -> str:
        angles, bins = self.reflectance.shape
        lo, hi = self.wavelengths_nm[0], self.wavelengths_nm[-1]
        # The Bragg peak at normal incidence (row 0: cos θ = 1).
        peak = int(np.argmax(self.reflectance[0]))
        return (
            f"<opalray.Optics {angles} angles × {bins} bins ({lo:.0f}–{hi:.0f} nm), "
            f"n_eff {self.n_eff:.4f}, d111 {self.d111_nm:.1f} nm, "
            f"R {self.reflectance[0, peak]:.3f} at {self.wavelengths_nm[peak]:.0f} nm at normal incidence>"
        )


class Stages:
    """A prepared scene: the structure and optics computed once (``opalray.prepare``), as
    arrays, and renders at any light angle that reuse them."""

    def __init__(self, stages: Any, scene: Scene):
        self._stages = stages
        self.scene = scene
        self._structure: Structure | None = None
        self._optics: Optics | None = None
        self._stone: Stone | None = None

    def __repr__(self) -> str:
        times = self.times
        return (
            f"<opalray.Stages {self.scene['integrator']['method']}, "
            f"{self.scene['render']['width']}×{self.scene['render']['height']}, prepared in "
            f"{times['structure']:.2f} s (structure) + {times['optics']:.2f} s (optics)>"
        )

    @property
    def times(self) -> dict:
        """Seconds of the structure and optics stages."""
        t = json.loads(self._stages.times_json())
        return {"structure": t["structure"], "optics": t["optics"]}

    @property
    def structure(self) -> Structure:
        if self._structure is None:
            nx, ny, nz, semi, size, stats = self._stages.structure_info()
            shape = (nz, ny, nx)
            self._structure = Structure(
                cells=self._stages.cell_kinds().reshape(shape),
                orientations=self._stages.orientations().reshape(shape + (4,)),
                normals=self._stages.normals().reshape(shape + (3,)),
                grid=(nx, ny, nz),
                semi_axes_mm=tuple(semi),
                cell_size_mm=tuple(size),
                stats=json.loads(stats),
            )
        return self._structure

    @property
    def optics(self) -> Optics:
        if self._optics is None:
            n_eff, d111 = self._stages.optics_info()
            cos_theta = self._stages.optics_cos_theta()
            self._optics = Optics(
                reflectance=self._stages.optics_table("R"),
                transmittance=self._stages.optics_table("T"),
                diffuse=self._stages.optics_table("D"),
                cos_theta=cos_theta,
                theta_deg=np.degrees(np.arccos(np.clip(cos_theta, -1.0, 1.0))),
                wavelengths_nm=self._stages.wavelengths_nm(),
                n_eff=n_eff,
                d111_nm=d111,
            )
        return self._optics

    @property
    def stone(self) -> Stone:
        """The stone model (the path integrator's: domains as geometry, each with its
        orientation and sphere diameter), built on first use for a two-pass scene."""
        if self._stone is None:
            self._stone = Stone(self._stages.stone())
        return self._stone

    def light_pass(self, light_angle_deg: float | None = None, *, threads: int | None = None) -> StoredLight:
        """The light pass alone at ``light_angle_deg`` (default: the scene's): the light
        stored in every inside cell, as the view pass of :meth:`render` at that angle reads
        it (the same on any number of threads). The two-pass method's; for a scene of the
        path integrator it is the light pass its two passes would run."""
        angle = self.scene["light"]["angle_deg"] if light_angle_deg is None else light_angle_deg
        stored = self._stages.light_pass(float(angle), threads)
        return StoredLight._of(stored, self.structure, angle)

    def render(self, light_angle_deg: float | None = None, *, threads: int | None = None) -> Image:
        """Render one frame at ``light_angle_deg`` (default: the scene's ``light.angle_deg``),
        on ``threads`` threads (default: every core); the same bytes as a fresh ``render`` of
        the scene at that angle, on any number of threads."""
        angle = self.scene["light"]["angle_deg"] if light_angle_deg is None else light_angle_deg
        scene = self.scene if angle == self.scene["light"]["angle_deg"] else self.scene.replace(light={"angle_deg": angle})
        return Image(self._stages.render(float(angle), threads), scene)

    def render_rgb8(self, light_angle_deg: float, *, threads: int | None = None) -> bytes:
        """One frame's display codes only (H × W × 3 bytes, row-major): a sweep's frame."""
        return self._stages.render_rgb8(float(light_angle_deg), threads)


def prepare(scene: Scene | dict | str | os.PathLike | None = None, **overrides: Any) -> Stages:
    """Grow the structure and build the optics of ``scene`` (see :func:`render` for what
    ``scene`` and ``overrides`` may be)."""
    scene = as_scene(scene, **overrides)
    return Stages(_opalray.prepare(scene.to_dict()), scene)


def light_pass(
    scene: Scene | dict | str | os.PathLike | None = None,
    light_angle_deg: float | None = None,
    *,
    threads: int | None = None,
    **overrides: Any,
) -> StoredLight:
    """The light pass of ``scene`` alone at ``light_angle_deg`` (default: the scene's):
    ``prepare(scene, **overrides).light_pass(light_angle_deg, threads=threads)``."""
    return prepare(scene, **overrides).light_pass(light_angle_deg, threads=threads)


def render(
    scene: Scene | dict | str | os.PathLike | None = None,
    *,
    progress: Progress | bool | None = None,
    time_limit: float | None = None,
    **overrides: Any,
) -> Image:
    """Render ``scene`` end to end, exactly as ``opalray render`` does.

    ``scene``: a :class:`Scene`, a dict, a TOML file's path, or None for the default preset
    (``black-opal``, as ``opalray render``; :data:`opalray.DEFAULT_PRESET`). ``overrides``
    change it first, as :meth:`Scene.replace` (``render(scene, camera={"tilt_deg": -20})``).
    ``progress``: a callable ``(stage, done, total)``, or ``True`` for a tqdm bar; the path
    integrator calls it after every pass (``stage`` says the samples per pixel and the noise
    so far, ``done``/``total`` count samples per pixel), the other methods as their stages
    finish, and the lobe integrator (the gem presets') as its view pass goes, a few times a
    second (``stage`` says the rows done, the time so far and the time left,
    ``done``/``total`` count rows from then on). ``time_limit``: seconds, counted from the call, bounding every stage, the stone's
    preparation included (as ``opalray render --time-limit``): a stage not done in time raises
    ``TimeoutError`` naming it, except the path integrator's passes after the first, which stop
    after the pass in which the time has passed; the path integrator then renders up to 65536
    samples per pixel unless ``overrides`` set ``integrator={"spp": N}``, and
    ``image.stats["path"]`` says how many it reached. An overrun stage is stopped within a
    fraction of a second (its cores freed) and dropped. The GIL is released while the core
    works; Ctrl-C interrupts the wait and stops the work the same way.
    """
    scene = as_scene(scene, **overrides)
    path = scene["integrator"]["method"] == "path"
    if time_limit is not None and path and "spp" not in overrides.get("integrator", {}):
        scene = scene.replace(integrator={"spp": _MAX_SPP})
    if path:
        total = scene["integrator"]["spp"]
        report, close = _progress_of(progress, total, "render")

        def on_pass(passes: int, spp: int, target: int, elapsed: float, noise: float | None) -> None:
            if report is not None:
                told = "" if noise is None else f", noise {100 * noise:.1f} %"
                report(f"{spp} spp{told}, {elapsed:.1f} s", min(spp, total), total)

        try:
            return Image(_opalray.render(scene.to_dict(), time_limit, on_pass), scene)
        finally:
            close()
    report, close = _progress_of(progress, 2, "render")
    try:
        if report is None:
            return Image(_opalray.render(scene.to_dict(), time_limit), scene)
        total = 2

        def on_rows(rows: int, total_rows: int, elapsed: float) -> None:
            # The lobe integrator's view pass: from here on `done`/`total` count its rows.
            nonlocal total
            total = total_rows
            if rows >= total_rows:
                left = "done"
            elif elapsed < 1.0:  # the first rows' pace says little
                left = "time left unknown"
            else:
                left = f"about {elapsed * (total_rows - rows) / rows:.1f} s left"
            report(f"view pass: {rows} of {total_rows} rows, {elapsed:.1f} s elapsed, {left}", rows, total_rows)

        report("structure, optics", 0, 2)
        image = Image(
            _opalray.render(
                scene.to_dict(), time_limit, None, lambda _: report("light, view, colour", 1, 2), on_rows
            ),
            scene,
        )
        report("done", total, total)
        return image
    finally:
        close()
