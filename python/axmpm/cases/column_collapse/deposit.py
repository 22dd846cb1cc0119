"""Granular column collapse: the deposit analysis (profiles, runout, final height).

The set-up (docs/physics.md §6, docs/validation-sources.md): a cylinder of sand of radius R_i
and height H_i = a R_i stands on a rough base inside a rigid cylinder wall; the wall is
removed and the column collapses into a deposit of runout radius R∞ and central height
H∞. Experiments (Lube et al. 2004, Lajeunesse et al. 2004) find the deposit depends on
a = H_i/R_i alone.

Analysis rules (documented in docs/validation.md):

* **Profile** h(r): the particles are binned radially in bins of one cell; the height of
  a bin is its *solid thickness*: the particles' initial volumes (mass / initial density)
  in the bin divided by the bin's area (annulus area per radian in axisymmetric runs,
  width in plane strain). Exact for a block, insensitive to a single particle sticking
  out, and not inflated by the volume the Mohr–Coulomb apex return lets flowing material
  gain (docs/validation.md). ``method="max"``: highest particle + half a spacing per bin.
* **Runout R∞**: bins, from the axis outwards, are *occupied* when their solid thickness
  is at least a quarter of a particle layer (0.25 s, s = cell / particles_per_cell: about
  one particle in a one-cell bin at 2×2 particles per cell). The continuous deposit is the
  run of occupied bins that starts at the axis; R∞ is its outermost particle plus half a
  spacing. Particles beyond the first empty bin (strays, thrown grains) are ignored. The
  radius that encloses 99 % of the mass is reported alongside (``runout_radius_99``).
  This edge follows the thinnest layer the mesh can carry, so it moves out with every
  refinement (docs/validation.md, mesh convergence).
* **Runout at one grain, R∞(d)**: where the solid-thickness profile, in bins of fixed width
  ``EDGE_BIN_WIDTH`` (2 mm, or one cell if coarser), first falls below one grain diameter
  d (``GRAIN_DIAMETER``, 1.15 mm: the glass beads of Lajeunesse et al. 2004 as tabulated by
  KK, docs/validation-sources.md §2, medium confidence), interpolated linearly between bin
  centres. A layer thinner than one grain is not a deposit an experimenter could see, and
  this rule has a physical length scale, so it converges with the mesh where the particle
  edge does not.
* **Tail** (reported beside the headline, never used to score it): R∞(3d), where the
  thickness profile first falls below ``TAIL_GRAINS`` = 3 grain diameters (same bins), and
  the share of the deposit's mass beyond a law's R∞ (:func:`mass_fraction_beyond`). How far
  the runout depends on the thickness an observer would call the edge, and how much material
  the excess over a law holds: the experiments do not state their edge criterion.
* **Final height H∞**: the deposit surface at the axis: a robust (Theil–Sen) line through
  the solid-thickness profile within r < max(R_i/4, 5 cells), evaluated at r = 0. A flat
  top gives its height, a cone its apex; thin spikes and cell-scale striations (seen at
  the axis for a = 5.4) carry little volume and average out. The mass-weighted 95th
  percentile of heights in r < R_i/4 is reported alongside (``final_height_p95``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...run.output import load_run

__all__ = [
    "ColumnGeometry",
    "geometry_from_scenario",
    "surface_profile",
    "runout_radius",
    "runout_radius_at_thickness",
    "final_height",
    "column_tops",
    "height_percentile",
    "mass_radius",
    "mass_fraction_beyond",
    "particle_metrics",
    "deposit_metrics",
    "profiles",
    "profile_difference",
]

#: Fraction of a particle layer a bin must hold to count as occupied (runout rule).
OCCUPIED_LAYERS = 0.25
#: Grain diameter (m) for the one-grain runout: the Lajeunesse et al. (2004) glass beads,
#: 1.15 mm (docs/validation-sources.md §2; medium confidence).
GRAIN_DIAMETER = 1.15e-3
#: Thickness, in grain diameters, of the tail runout R∞(3d) reported beside the headline.
TAIL_GRAINS = 3.0
#: Bin width (m) of the thickness profile for the one-grain runout (one cell if coarser).
EDGE_BIN_WIDTH = 2e-3
#: Central region for H∞, as a fraction of R_i.
CENTRAL_FRACTION = 0.25
#: Mass-weighted percentile of particle heights used for H∞.
HEIGHT_PERCENTILE = 95.0


@dataclass(frozen=True)
class ColumnGeometry:
    """The initial column and how it was discretised."""

    radius: float  # R_i, m (half-width in plane strain)
    height: float  # H_i, m
    axis: float  # r (x) of the axis / symmetry plane, m
    base: float  # z (y) of the base, m
    cell_size: float  # m
    particles_per_cell: int
    formulation: str

    @property
    def aspect_ratio(self) -> float:
        return self.height / self.radius

    @property
    def spacing(self) -> float:
        """Initial particle spacing s."""
        return self.cell_size / self.particles_per_cell

    @property
    def cells_per_radius(self) -> float:
        return self.radius / self.cell_size


def geometry_from_scenario(scenario: Any) -> ColumnGeometry:
    """The column of a scenario: its first body, standing on the axis / symmetry plane."""
    body = scenario.bodies[0]
    return ColumnGeometry(
        radius=float(body.max[0] - body.min[0]),
        height=float(body.max[1] - body.min[1]),
        axis=float(body.min[0]),
        base=float(body.min[1]),
        cell_size=float(scenario.grid.cell_size),
        particles_per_cell=int(body.particles_per_cell),
        formulation=str(scenario.simulation.formulation),
    )


# --------------------------------------------------------------------------- particle analysis


def _bins(geom: ColumnGeometry, r_max: float, width: float | None = None) -> NDArray[np.float64]:
    w = geom.cell_size if width is None else width
    n = max(1, int(math.ceil(r_max / w - 1e-9)))
    return np.arange(n + 1) * w


def _bin_area(edges: NDArray[np.float64], formulation: str) -> NDArray[np.float64]:
    """Bin area in the units of particle volumes: per radian (axisymmetric) or width."""
    if formulation == "axisymmetric":
        return 0.5 * (edges[1:] ** 2 - edges[:-1] ** 2)
    return np.diff(edges)


def surface_profile(
    x: NDArray[np.float64],
    volume0: NDArray[np.float64] | None,
    geom: ColumnGeometry,
    r_max: float | None = None,
    method: str = "volume",
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Free-surface profile: (bin centres r, heights h) relative to axis and base.

    ``method="volume"``: solid thickness, the particles' *initial* volume (mass / initial
    density) in the bin divided by the bin area — the height the material in the bin
    would have at its initial density. Current volumes are not used: near the axis of
    axisymmetric collapses J = V/V0 reaches 1.5–4.6 although ψ = 0 (docs/validation.md).
    ``method="max"``: highest particle in the bin plus half a particle spacing (0 if empty).
    """
    r = x[:, 0] - geom.axis
    z = x[:, 1] - geom.base
    if r_max is None:
        r_max = max(float(r.max(initial=0.0)) + geom.cell_size, geom.radius)
    edges = _bins(geom, r_max)
    idx = np.clip(np.searchsorted(edges, r, side="right") - 1, 0, len(edges) - 2)
    centres = 0.5 * (edges[1:] + edges[:-1])
    if method == "volume":
        if volume0 is None:
            raise ValueError("method='volume' needs the particles' initial volumes")
        vol = np.bincount(idx, weights=volume0, minlength=len(centres))
        return centres, vol / _bin_area(edges, geom.formulation)
    if method == "max":
        h = np.full(len(centres), -np.inf)
        np.maximum.at(h, idx, z + 0.5 * geom.spacing)
        h[~np.isfinite(h)] = 0.0
        return centres, np.maximum(h, 0.0)
    raise ValueError(f"unknown profile method {method!r} (volume or max)")


def runout_radius(
    x: NDArray[np.float64], volume0: NDArray[np.float64], geom: ColumnGeometry
) -> float:
    """R∞: outer edge of the continuous deposit (see the module docstring)."""
    r = x[:, 0] - geom.axis
    centres, h = surface_profile(x, volume0, geom)
    occupied = h >= OCCUPIED_LAYERS * geom.spacing
    empty = np.flatnonzero(~occupied)
    n_cont = int(empty[0]) if empty.size else len(occupied)
    if n_cont == 0:
        return 0.0
    edge = n_cont * geom.cell_size
    inside = r < edge
    return float(r[inside].max() + 0.5 * geom.spacing)


def runout_radius_at_thickness(
    x: NDArray[np.float64], volume0: NDArray[np.float64], geom: ColumnGeometry,
    thickness: float = GRAIN_DIAMETER, bin_width: float = EDGE_BIN_WIDTH,
) -> float:
    """R∞(d): the radius where the solid thickness first falls below ``thickness``.

    Thickness profile as in :func:`surface_profile`, in bins of ``max(bin_width, cell)``
    from the axis; the crossing is interpolated linearly between the centres of the last
    bin at or above ``thickness`` and the first bin below it (0 if the bin at the axis is
    already thinner).
    """
    w = max(bin_width, geom.cell_size)
    r = x[:, 0] - geom.axis
    n = max(1, int(math.ceil(float(r.max(initial=0.0)) / w)) + 2)
    edges = np.arange(n + 1) * w
    idx = np.clip(np.searchsorted(edges, r, side="right") - 1, 0, n - 1)
    h = np.bincount(idx, weights=volume0, minlength=n) / _bin_area(edges, geom.formulation)
    centres = 0.5 * (edges[1:] + edges[:-1])
    thin = np.flatnonzero(h < thickness)
    k = int(thin[0]) if thin.size else n - 1
    if k == 0:
        return 0.0
    h0, h1 = h[k - 1], h[k]
    return float(centres[k - 1] + (h0 - thickness) / (h0 - h1) * w)


def mass_radius(x: NDArray[np.float64], mass: NDArray[np.float64], geom: ColumnGeometry,
                fraction: float = 0.99) -> float:
    """Radius enclosing ``fraction`` of the mass (plus half a particle spacing)."""
    r = x[:, 0] - geom.axis
    order = np.argsort(r)
    cum = np.cumsum(mass[order])
    k = int(np.searchsorted(cum, fraction * cum[-1]))
    return float(r[order][min(k, len(r) - 1)] + 0.5 * geom.spacing)


def mass_fraction_beyond(x: NDArray[np.float64], mass: NDArray[np.float64], geom: ColumnGeometry,
                         radius: float) -> float:
    """Share of the mass whose particle centres lie farther than ``radius`` from the axis."""
    r = x[:, 0] - geom.axis
    total = float(mass.sum())
    return float(mass[r > radius].sum()) / total if total > 0.0 else 0.0


def column_tops(x: NDArray[np.float64], geom: ColumnGeometry,
                r_limit: float | None = None) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Top of the particle column in radial bins one particle spacing wide: (bin centre r,
    highest particle z + half a spacing), non-empty bins with r < ``r_limit`` only."""
    r = x[:, 0] - geom.axis
    z = x[:, 1] - geom.base
    r_limit = CENTRAL_FRACTION * geom.radius if r_limit is None else r_limit
    s = geom.spacing
    n = max(1, int(math.ceil(r_limit / s - 1e-9)))
    sel = r < n * s
    idx = np.clip((r[sel] / s).astype(int), 0, n - 1)
    top = np.full(n, -np.inf)
    np.maximum.at(top, idx, z[sel])
    ok = np.isfinite(top)
    centres = (np.arange(n) + 0.5) * s
    return centres[ok], top[ok] + 0.5 * s


def _theil_sen(x: NDArray[np.float64], y: NDArray[np.float64]) -> tuple[float, float]:
    """Median-of-slopes line (robust to ~29 % outliers): (intercept, slope)."""
    i, j = np.triu_indices(len(x), k=1)
    slope = float(np.median((y[j] - y[i]) / (x[j] - x[i])))
    return float(np.median(y - slope * x)), slope


def final_height(x: NDArray[np.float64], volume0: NDArray[np.float64],
                 geom: ColumnGeometry) -> float:
    """H∞: the deposit surface at the axis.

    The solid-thickness profile (:func:`surface_profile`, bins of one cell) within
    r < max(R_i/4, 3 cells) is fitted with a robust Theil–Sen line against each bin's
    area centroid (so that a linear surface is fitted exactly in axisymmetric bins) and
    evaluated at r = 0. A flat top gives its height, a cone its apex; a thin spike at the
    axis carries little volume, and cell-scale striations average out.
    """
    w = geom.cell_size
    r_lim = max(CENTRAL_FRACTION * geom.radius, 5 * w)
    n = int(math.ceil(r_lim / w - 1e-9))
    edges = np.arange(n + 1) * w
    r = x[:, 0] - geom.axis
    idx = np.searchsorted(edges, r, side="right") - 1
    ok = (idx >= 0) & (idx < n)
    vol = np.bincount(idx[ok], weights=volume0[ok], minlength=n)
    thick = vol / _bin_area(edges, geom.formulation)
    if geom.formulation == "axisymmetric":
        rc = (2.0 / 3.0) * (edges[1:] ** 3 - edges[:-1] ** 3) / (edges[1:] ** 2 - edges[:-1] ** 2)
    else:
        rc = 0.5 * (edges[1:] + edges[:-1])
    intercept, _ = _theil_sen(rc, thick)
    return float(intercept)


def height_percentile(x: NDArray[np.float64], mass: NDArray[np.float64], geom: ColumnGeometry,
                      percentile: float = HEIGHT_PERCENTILE) -> float:
    """Mass-weighted percentile of particle heights within r < R_i/4, + half a spacing
    (reported alongside H∞; biased low by up to one spacing when the top layer holds
    less than 100 − percentile % of the central mass)."""
    r = x[:, 0] - geom.axis
    z = x[:, 1] - geom.base
    sel = r < CENTRAL_FRACTION * geom.radius
    if not np.any(sel):
        return 0.0
    zs, ms = z[sel], mass[sel]
    order = np.argsort(zs)
    cum = np.cumsum(ms[order])
    k = int(np.searchsorted(cum, percentile / 100.0 * cum[-1]))
    return float(zs[order][min(k, len(zs) - 1)] + 0.5 * geom.spacing)


def particle_metrics(
    x: NDArray[np.float64],
    volume0: NDArray[np.float64],
    mass: NDArray[np.float64],
    geom: ColumnGeometry,
) -> dict[str, float]:
    """Deposit metrics of one particle set (see :func:`deposit_metrics`); ``volume0`` are
    the particles' initial volumes (mass / initial density)."""
    R_i, H_i = geom.radius, geom.height
    R_inf = runout_radius(x, volume0, geom)
    R_grain = runout_radius_at_thickness(x, volume0, geom)
    R_tail = runout_radius_at_thickness(x, volume0, geom, TAIL_GRAINS * GRAIN_DIAMETER)
    H_inf = final_height(x, volume0, geom)
    return {
        "initial_radius": R_i,
        "initial_height": H_i,
        "aspect_ratio": H_i / R_i,
        # The deposit edge is where it becomes thinner than one grain (the headline runout);
        # the outermost particle of the continuous deposit follows the mesh (module doc).
        "runout_radius": R_grain,
        "final_height": H_inf,
        "runout_normalised": (R_grain - R_i) / R_i,
        "final_height_normalised": H_inf / R_i,
        "runout_radius_particle_edge": R_inf,
        "runout_normalised_particle_edge": (R_inf - R_i) / R_i,
        "runout_radius_3_grains": R_tail,
        "runout_normalised_3_grains": (R_tail - R_i) / R_i,
        "runout_radius_99": mass_radius(x, mass, geom, 0.99),
        "final_height_p95": height_percentile(x, mass, geom),
        "max_particle_radius": float((x[:, 0] - geom.axis).max() + 0.5 * geom.spacing),
        "max_particle_height": float((x[:, 1] - geom.base).max() + 0.5 * geom.spacing),
        "cell_size": geom.cell_size,
        "cells_per_radius": geom.cells_per_radius,
    }


def deposit_metrics(run_dir: str | Path) -> dict[str, Any]:
    """Deposit metrics from the last frame of a column-collapse run.

    Keys: ``initial_radius``, ``initial_height``, ``aspect_ratio``, ``runout_radius`` (R∞
    where the deposit is one grain diameter thick), ``final_height`` (m),
    ``runout_normalised`` = (R∞ − R_i)/R_i, ``final_height_normalised`` = H∞/R_i, ``time``
    (of the frame used), plus ``runout_radius_particle_edge`` and
    ``runout_normalised_particle_edge`` (outermost particle of the continuous deposit),
    ``runout_radius_3_grains`` and ``runout_normalised_3_grains`` (where the deposit is
    three grains thick), ``runout_radius_99``, ``max_particle_radius``, ``max_particle_height``, ``cell_size``,
    ``cells_per_radius``, ``frame``, ``status``. Geometry comes from the scenario's first body.
    """
    run = load_run(run_dir)
    if not run.frames:
        raise ValueError(f"{run_dir}: the run has no frames")
    geom = geometry_from_scenario(run.scenario)
    last = run.frames[-1]
    out: dict[str, Any] = particle_metrics(last.x, last.volume0, last.mass, geom)
    out["time"] = float(last.time)
    out["frame"] = len(run.frames) - 1
    out["status"] = run.summary.get("status")
    out["formulation"] = geom.formulation
    return out


def profile_difference(run_dir: str | Path, reference_dir: str | Path,
                       bin_width: float = EDGE_BIN_WIDTH) -> float:
    """How differently two runs of the same column deposit their material: the final
    solid-thickness profiles h and h_ref (last frames, common bins of
    ``max(bin_width, coarser cell)``) give ∫|h − h_ref| dA / ∫ h_ref dA, with dA the bin
    area (annulus per radian in axisymmetry). 0 = the same deposit; it is the fraction of
    the deposit volume that lies elsewhere (counted at both places), so a mesh sequence
    converges when it shrinks, whatever rule then reads a runout off the profile."""
    from dataclasses import replace

    runs = [load_run(run_dir), load_run(reference_dir)]
    geoms = [geometry_from_scenario(r.scenario) for r in runs]
    a, b = (g.aspect_ratio for g in geoms)
    if abs(a - b) > 1e-9 * max(a, b) or geoms[0].formulation != geoms[1].formulation:
        raise ValueError(f"not the same column: a = {a:.6g} vs {b:.6g}")
    w = max(bin_width, geoms[0].cell_size, geoms[1].cell_size)
    r_max = max(float((r.frames[-1].x[:, 0] - g.axis).max()) for r, g in zip(runs, geoms)) + w
    heights = []
    for run, g in zip(runs, geoms):
        last = run.frames[-1]
        _, h = surface_profile(last.x, last.volume0, replace(g, cell_size=w), r_max=r_max)
        heights.append(h)
    n = min(len(h) for h in heights)
    area = _bin_area(np.arange(n + 1) * w, geoms[0].formulation)
    h, h_ref = heights[0][:n], heights[1][:n]
    return float(np.sum(np.abs(h - h_ref) * area) / np.sum(h_ref * area))


def profiles(run_dir: str | Path, interval: float | None = None,
             method: str = "volume") -> list[dict[str, Any]]:
    """Free-surface profiles of every frame (or frames ~``interval`` apart):
    ``[{"time", "r", "h"}]`` in metres, relative to the axis and the base."""
    run = load_run(run_dir)
    geom = geometry_from_scenario(run.scenario)
    r_max = max(float(np.max(f.x[:, 0])) for f in (run.frames[0], run.frames[-1])) - geom.axis
    r_max = max(r_max + geom.cell_size, geom.radius)
    out = []
    next_t = -math.inf
    for f in run.frames:
        if interval is not None and f.time < next_t - 1e-9:
            continue
        r_max_f = max(r_max, float(f.x[:, 0].max()) - geom.axis + geom.cell_size)
        r, h = surface_profile(f.x, f.volume0, geom, r_max=r_max_f, method=method)
        out.append({"time": float(f.time), "r": r, "h": h})
        if interval is not None:
            next_t = f.time + interval
    return out
