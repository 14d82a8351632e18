"""The stone model of the path integrator as arrays: domains as geometry (balls of the
paper's growth or grains), each with its lattice orientation and sphere diameter."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["Stone"]

_AXES = "xyz"


class Stone:
    """The stone model of a scene (``opalray.prepare(scene).stone``).

    ``orientations`` (float32, domains × 4): each domain's lattice → stone rotation as a
    unit quaternion ``(x, y, z, w)`` (scalar last, as ``scipy.spatial.transform.Rotation``);
    ``normals`` (float32, domains × 3): one (111) plane normal per domain, the orientation
    applied to (1, 1, 1)/√3; ``sphere_diameters_nm`` (float32, domains). ``semi_axes_mm``:
    the ellipsoid's; ``n_eff``: the effective index. ``domain_at`` and ``slice`` give the
    domain at points: its index, ``POTCH`` (−1) in potch, ``OUTSIDE`` (−2) outside.
    """

    POTCH = -1
    OUTSIDE = -2

    def __init__(self, model: Any):
        self._model = model
        semi, self.n_eff = model.info()
        self.semi_axes_mm = tuple(float(v) for v in semi)
        self.orientations = model.orientations()
        self.normals = model.normals()
        self.sphere_diameters_nm = model.sphere_diameters_nm()
        for a in (self.orientations, self.normals, self.sphere_diameters_nm):
            a.setflags(write=False)

    def __len__(self) -> int:
        return len(self.sphere_diameters_nm)

    def domain_at(self, points_mm: Any) -> np.ndarray:
        """The domain id (int32) of every point of ``points_mm`` (… × 3, mm in the stone
        frame, centred on the stone); the result has the points' shape less the last axis."""
        points = np.asarray(points_mm, dtype=np.float32)
        if points.ndim == 0 or points.shape[-1] != 3:
            raise ValueError(f"points_mm: shape {points.shape}, expected … × 3 (x, y, z in mm)")
        flat = np.ascontiguousarray(points.reshape(-1, 3))
        return self._model.domain_ids(flat).reshape(points.shape[:-1])

    def slice(self, axis: str = "z", at_mm: float = 0.0, pixels: tuple[int, int] = (300, 400)
              ) -> tuple[np.ndarray, tuple[float, float, float, float]]:
        """The domain ids on the plane ``axis = at_mm`` across the whole stone, sampled at
        pixel centres: ``(ids, extent)``, ``ids`` of shape ``pixels`` (rows, columns) and
        ``extent`` = (left, right, bottom, top) in mm, for
        ``plt.imshow(…, extent=extent, origin="lower")``. Rows run along the second of the
        other two axes, columns along the first (``z``: rows y, columns x)."""
        if axis not in _AXES:
            raise ValueError(f"axis {axis!r}: choose 'x', 'y' or 'z'")
        rows, cols = (int(v) for v in pixels)
        if rows < 1 or cols < 1 or rows * cols > 50_000_000:
            raise ValueError(f"pixels {pixels}: need 1 … 50 million pixels, e.g. (300, 400)")
        k = _AXES.index(axis)
        across, up = [a for a in range(3) if a != k]
        half_c, half_r = self.semi_axes_mm[across], self.semi_axes_mm[up]
        u = -half_c + (np.arange(cols) + 0.5) * (2 * half_c / cols)
        v = -half_r + (np.arange(rows) + 0.5) * (2 * half_r / rows)
        points = np.empty((rows, cols, 3), np.float32)
        points[..., across] = u[None, :]
        points[..., up] = v[:, None]
        points[..., k] = at_mm
        return self.domain_at(points), (-half_c, half_c, -half_r, half_r)

    def __repr__(self) -> str:
        a, b, c = self.semi_axes_mm
        return f"<opalray.Stone {len(self)} domains, semi-axes {a:g} × {b:g} × {c:g} mm>"
