"""The light pass's stored light (paper §3.2) as arrays: what the two-pass method's view pass
reads back at every cluster."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["StoredLight"]


@dataclass(frozen=True)
class StoredLight:
    """The light stored by one light pass in every inside cell (a *slot*: a cluster or a
    void), in three lobes (``LOBES``): the direct light (refracted once, since only filtered),
    and the light reflected inside at least once, travelling down (−z) and up (+z).

    ``cells`` (int64, slots): the flat index of each slot's cell into the structure's
    ``nz × ny × nx`` cells; ``cell_zyx`` (slots × 3) the same as ``(z, y, x)``; ``kinds``
    (uint8, slots): ``Structure.VOID`` or ``Structure.CLUSTER``. ``fluence`` (float32,
    slots × 3 × bins): the fluence spectrum, power per mm² per nm (a density: it converges
    as rays are added and does not scale with their number); ``directions`` (float32,
    slots × 3 × 3): each lobe's power-weighted mean direction of travel in the stone frame,
    unit or zero where none arrived; ``concentration`` (float32, slots × 3): the mean
    resultant length of those directions, 1 for light from one direction. ``wavelengths_nm``:
    the bin centres; ``light_spectrum`` (float32, bins): the light's irradiance per nm across
    the beam before the stone; ``ledger``: where the energy went (``emitted = reflected +
    escaped + stored + absorbed + truncated``, the fields of ``stats["energy"]``).
    """

    LOBES = ("direct", "down", "up")
    cells: np.ndarray
    cell_zyx: np.ndarray
    kinds: np.ndarray
    fluence: np.ndarray
    directions: np.ndarray
    concentration: np.ndarray
    wavelengths_nm: np.ndarray
    light_spectrum: np.ndarray
    light_angle_deg: float
    grid: tuple[int, int, int]
    ledger: dict = field(default_factory=dict)

    @classmethod
    def _of(cls, stored: Any, structure: Any, light_angle_deg: float) -> StoredLight:
        nx, ny, nz = structure.grid
        cells = stored.cells()
        z, rest = np.divmod(cells, nx * ny)
        y, x = np.divmod(rest, nx)
        arrays = dict(
            cells=cells,
            cell_zyx=np.stack([z, y, x], axis=1),
            kinds=structure.cells.reshape(-1)[cells],
            fluence=stored.fluence(),
            directions=stored.directions(),
            concentration=stored.concentration(),
            wavelengths_nm=stored.wavelengths_nm(),
            light_spectrum=stored.light_spectrum(),
        )
        for a in arrays.values():
            a.setflags(write=False)
        return cls(**arrays, light_angle_deg=float(light_angle_deg), grid=(nx, ny, nz),
                   ledger=json.loads(stored.ledger_json()))

    def on_grid(self, lobe: int | str | None = None) -> np.ndarray:
        """The fluence as an ``nz × ny × nx × bins`` float32 array (zero outside the stone):
        one lobe (its index or name), or the sum of the three (``None``)."""
        if lobe is None:
            values = self.fluence.sum(axis=1)
        else:
            k = self.LOBES.index(lobe) if isinstance(lobe, str) else int(lobe)
            values = self.fluence[:, k]
        nx, ny, nz = self.grid
        out = np.zeros((nz * ny * nx, values.shape[-1]), np.float32)
        out[self.cells] = values
        return out.reshape(nz, ny, nx, -1)
