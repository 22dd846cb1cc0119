"""Point probes: the history columns of the ``[[probes]]`` of a scenario.

At each history row, a probe's values are a weighted linear least-squares fit through the
particles near its point (a moving least-squares estimate with a linear basis, Lancaster &
Salkauskas 1981): q(x) ≈ a + b·(x − x₀)/h + c·(y − y₀)/h with weights V_p w(x_p − x₀),
w(d) = (1 − |d_x|/h)(1 − |d_y|/h) on the 2h × 2h square around the point (h the cell size),
and the probe's value is a. The fit reproduces a linear field exactly, also next to a free
surface or a boundary where the particles lie on one side only. Where the particles near the
point do not span a plane (fewer than three, or all on one line) the value is their weighted
mean; with no particle within the square, NaN. The point is fixed in space: the values are those
of the material at the point at that time (the current positions are used). The sums run in the
particles' id order with numpy, so a run gives the same columns every time.

Columns, per probe NAME: ``NAME.pore_pressure`` (Pa, compression positive; saturated runs only,
from the saturated particles), ``NAME.stress_xx``, ... (the four stress components under the
names of :func:`axmpm.run.output.stress_names`, Pa, tension positive; effective stress in a
saturated body) and ``NAME.displacement_x``, ``NAME.displacement_y`` (m).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .output import stress_names

__all__ = ["interpolate", "probe_columns"]

#: A fit whose normal matrix is this ill-conditioned (in units of h) falls back to the mean.
_CONDITION_LIMIT = 1e10


def interpolate(point: Sequence[float], positions: NDArray[np.float64], volumes: NDArray[np.float64],
                values: NDArray[np.float64], cell_size: float) -> NDArray[np.float64]:
    """The moving least-squares estimate (module doc) at ``point`` of each column of ``values``
    ((N,) or (N, k)) carried by particles at ``positions`` (N, 2) with ``volumes`` (N,)."""
    values = np.asarray(values, dtype=float)
    flat = values.ndim == 1
    table = values[:, None] if flat else values
    d = (np.asarray(positions, dtype=float) - np.asarray(point, dtype=float)) / cell_size
    tent = np.clip(1.0 - np.abs(d), 0.0, None)
    weight = np.asarray(volumes, dtype=float) * tent[:, 0] * tent[:, 1]
    near = weight > 0.0
    if not near.any():
        out = np.full(table.shape[1], np.nan)
        return out[0] if flat else out
    w, d, q = weight[near], d[near], table[near]
    basis = np.column_stack([np.ones(len(w)), d[:, 0], d[:, 1]])
    normal = basis.T @ (w[:, None] * basis)
    if np.linalg.cond(normal) < _CONDITION_LIMIT:
        out = np.linalg.solve(normal, basis.T @ (w[:, None] * q))[0]
    else:
        out = (w @ q) / w.sum()
    return out[0] if flat else out


def probe_columns(probes: Sequence[Any], frame: Any, formulation: str, cell_size: float) -> dict[str, float]:
    """The history columns of ``probes`` (module doc) for one state of the particles: ``frame``
    has ``x`` (N, 2), ``X0``, ``volume``, ``stress`` (N, 4) and ``pore_pressure``/``porosity``
    (empty in a dry run), as :class:`axmpm.run.output.FrameData`."""
    columns: dict[str, float] = {}
    if not probes:
        return columns
    x, volume = frame.x, frame.volume
    mechanical = np.column_stack([frame.stress, frame.x - frame.X0])
    names = [*stress_names(formulation), "displacement_x", "displacement_y"]
    saturated = len(frame.pore_pressure) > 0
    wet = frame.porosity > 0.0 if saturated else None
    for probe in probes:
        if saturated:
            p = interpolate(probe.point, x[wet], volume[wet], frame.pore_pressure[wet], cell_size)
            columns[f"{probe.name}.pore_pressure"] = float(p)
        values = interpolate(probe.point, x, volume, mechanical, cell_size)
        columns.update({f"{probe.name}.{n}": float(v) for n, v in zip(names, values)})
    return columns
