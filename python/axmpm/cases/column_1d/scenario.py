"""The 1D column under self-weight (docs/physics.md §4) as an axmpm scenario, and its errors.

:func:`column_scenario` builds a column of width w = cells_across·h and height H on rollers
(uniaxial strain), in plane strain or axisymmetric (optionally with its inner face at
r = offset, away from the axis), loaded by gravity ramped in over a whole number of
fundamental periods and brought to rest by Cundall local damping. The fundamental period
of a fixed–free column is T = 4H/c with c = √(M/ρ0), M the P-wave modulus (E for ν = 0);
ramping over n·T leaves (almost) no residual vibration of the odd modes (periods T/(2k+1))
in the linear regime. The defaults (ramp 2 T, then 4 T of settling with local damping 0.3)
reach the static state within a fraction of a percent for ρ0 g H/E from 0.01 to 0.5; with
damping 0.1 and 2 T of settling, large-deformation columns still ring by several percent.
Note: output times that are multiples of T/2 sample the ringing at its turning points,
where the kinetic energy is zero, so a small final kinetic energy alone proves little.

:func:`column_errors` compares a frame with the exact static solution in
:mod:`axmpm.cases.column_1d.exact`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from . import exact
from ...scenario import Scenario

__all__ = ["column_scenario", "column_errors", "ColumnErrors", "column_geometry", "stress_difference"]


def column_scenario(
    formulation: Literal["plane_strain", "axisymmetric"] = "axisymmetric",
    shape_function: Literal["linear", "ugimp", "cpgimp", "cpdi2"] = "linear",
    mode: exact.Mode = "compression",
    *,
    cells_along: int = 16,
    cells_across: int = 2,
    offset: float = 0.0,
    height: float = 1.0,
    density: float = 1000.0,
    gravity: float = 10.0,
    load_ratio: float | None = 0.01,
    youngs_modulus: float | None = None,
    particles_per_cell: int = 2,
    material_model: Literal["neo_hookean", "linear_elastic"] = "neo_hookean",
    poisson_ratio: float = 0.0,
    ramp_periods: float = 2.0,
    settle_periods: float = 4.0,
    damping: float = 0.3,
    outputs: int = 10,
    cfl: float = 0.4,
    flip_fraction: float = 0.99,
    update_scheme: Literal["musl", "usl"] = "musl",
) -> Scenario:
    """A 1D column scenario.

    ``youngs_modulus`` defaults to ρ0 g H / ``load_ratio`` (s0 = load_ratio). ``poisson_ratio``
    > 0 (with rollers on the lateral faces: uniaxial strain, lateral stress ν/(1 − ν) times the
    vertical one) makes the axisymmetric hoop stress, and so the hoop force, non-zero. ``offset`` is
    the x (r) position of the column's inner face; it must be a whole number of cells.
    Compression: base fixed on the bottom face, 2 cells of room above. Tension: top fixed
    on the top face, room below for twice the exact elongation plus 2 cells.
    """
    if mode not in ("compression", "tension"):
        raise ValueError(f"mode must be 'compression' or 'tension' (got {mode!r})")
    H = float(height)
    h = H / cells_along
    w = cells_across * h
    if youngs_modulus is None:
        if not load_ratio:
            raise ValueError("give youngs_modulus or a positive load_ratio")
        youngs_modulus = density * gravity * H / load_ratio
    E = float(youngs_modulus)
    n_offset = offset / h
    if abs(n_offset - round(n_offset)) > 1e-9 or offset < 0:
        raise ValueError(f"offset must be a non-negative whole number of cells of {h:g} m (got {offset:g})")
    x0 = round(n_offset) * h

    nu = float(poisson_ratio)
    modulus = E if nu == 0.0 else E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))  # P-wave modulus
    wave_speed = math.sqrt(modulus / density)
    period = 4.0 * H / wave_speed
    ramp = ramp_periods * period
    end_time = ramp + settle_periods * period

    walls: list[dict[str, Any]] = []
    if formulation == "plane_strain":
        origin_x, extent_x = x0, w
        left = right = "roller"
    elif formulation == "axisymmetric":
        origin_x, extent_x = 0.0, x0 + w
        left = right = "roller"
        if x0 > 0:
            walls.append({"axis": "x", "position": x0, "material_side": "positive", "condition": "roller"})
    else:
        raise ValueError(f"unknown formulation {formulation!r}")

    if mode == "compression":
        base = 0.0
        extent_y = H + 2 * h
        bottom, top = "fixed", "free"
    else:
        elongation = -float(exact.vertical_displacement(0.0, H, density, gravity, E, "tension"))
        if material_model == "linear_elastic":
            elongation = -float(exact.small_strain_displacement(0.0, H, density, gravity, E, "tension"))
        base = math.ceil((2.0 * elongation) / h + 2) * h
        extent_y = base + H
        bottom, top = "free", "fixed"

    data = {
        "simulation": {
            "formulation": formulation,
            "shape_function": shape_function,
            "end_time": end_time,
            "output_interval": end_time / outputs,
            "gravity": [0.0, -gravity],
            "gravity_ramp_time": ramp,
            "cfl": cfl,
            "update_scheme": update_scheme,
            "flip_fraction": flip_fraction,
            "damping": damping,
        },
        "grid": {"origin": [origin_x, 0.0], "extent": [extent_x, extent_y], "cell_size": h},
        "materials": {
            "column": {"model": material_model, "density": density, "youngs_modulus": E, "poisson_ratio": nu}
        },
        "bodies": [
            {
                "name": "column",
                "material": "column",
                "min": [x0, base],
                "max": [x0 + w, base + H],
                "particles_per_cell": particles_per_cell,
            }
        ],
        "boundaries": {"left": left, "right": right, "bottom": bottom, "top": top},
        "walls": walls,
    }
    return Scenario.from_dict(data)


@dataclass(frozen=True)
class ColumnGeometry:
    """What the exact solution needs, read from a column scenario."""

    base: float  # m, initial height of the column's bottom
    inner: float  # m, x (r) of the column's inner face
    height: float  # m
    density: float  # kg/m³
    gravity: float  # m/s², magnitude
    youngs_modulus: float  # Pa
    mode: exact.Mode
    small_strain: bool  # linear_elastic material: compare with the small-strain displacement


def column_geometry(scenario: Scenario, mode: exact.Mode | None = None) -> ColumnGeometry:
    """Read the column (the first body) from a scenario; infer the mode from the fixed face."""
    body = scenario.bodies[0]
    mat = scenario.materials[body.material]
    if mode is None:
        fixed_top = scenario.boundaries.top.condition == "fixed" or any(
            w.axis == "y" and w.condition == "fixed" and w.material_side == "negative" for w in scenario.walls
        )
        mode = "tension" if fixed_top else "compression"
    return ColumnGeometry(
        base=body.min[1],
        inner=body.min[0],
        height=body.max[1] - body.min[1],
        density=mat.density,
        gravity=-scenario.simulation.gravity[1],
        youngs_modulus=mat.youngs_modulus,
        mode=mode,
        small_strain=mat.model == "linear_elastic",
    )


@dataclass(frozen=True)
class ColumnErrors:
    """Errors of a column frame against the exact static solution (dimensionless)."""

    stress_l2: float  # ||σ_v − σ_exact||₂ / ||σ_exact||₂ over particles
    displacement_l2: float  # ||u_v − u_exact||₂ / ||u_exact||₂
    stress_max: float  # max |σ_v − σ_exact| / max |σ_exact|

    def __str__(self) -> str:
        return (f"stress L2 {100 * self.stress_l2:.3f} %, displacement L2 {100 * self.displacement_l2:.3f} %, "
                f"stress max {100 * self.stress_max:.3f} %")


def _frame_and_scenario(run_or_frame: Any, scenario: Scenario | None) -> tuple[Any, Scenario]:
    if hasattr(run_or_frame, "frames"):
        frame = run_or_frame.frames[-1]
        scenario = scenario or run_or_frame.scenario
    else:
        frame = run_or_frame
    if scenario is None:
        raise ValueError("a frame needs its scenario: column_errors(frame, scenario)")
    return frame, scenario


def column_errors(run_or_frame: Any, scenario: Scenario | None = None, mode: exact.Mode | None = None) -> ColumnErrors:
    """Relative errors of the vertical stress (stress column 1) and vertical displacement of
    each particle against the exact solution at its initial height (last frame of a run)."""
    frame, scenario = _frame_and_scenario(run_or_frame, scenario)
    geo = column_geometry(scenario, mode)
    X = np.asarray(frame.X0)[:, 1] - geo.base
    args = (geo.height, geo.density, geo.gravity, geo.youngs_modulus, geo.mode)
    sigma_exact = exact.vertical_stress(X, *args)
    u_exact = (exact.small_strain_displacement if geo.small_strain else exact.vertical_displacement)(X, *args)
    sigma = np.asarray(frame.stress)[:, 1]
    u = np.asarray(frame.x)[:, 1] - np.asarray(frame.X0)[:, 1]
    return ColumnErrors(
        stress_l2=_relative_l2(sigma, sigma_exact),
        displacement_l2=_relative_l2(u, u_exact),
        stress_max=float(np.max(np.abs(sigma - sigma_exact)) / np.max(np.abs(sigma_exact))),
    )


def _relative_l2(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def _column_order(frame: Any, geo: ColumnGeometry) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    rel = np.asarray(frame.X0) - np.array([geo.inner, geo.base])
    rel = np.round(rel / geo.height, 9)
    return rel, np.lexsort((rel[:, 0], rel[:, 1]))


def stress_difference(run_a: Any, run_b: Any, component: int = 1) -> float:
    """Relative L2 difference ||σ_a − σ_b|| / ||σ_b|| of one stress component between two
    column runs (e.g. axisymmetric vs plane strain), matching particles by their initial
    position relative to the column's inner bottom corner."""
    fa, sa = _frame_and_scenario(run_a, None)
    fb, sb = _frame_and_scenario(run_b, None)
    rel_a, ia = _column_order(fa, column_geometry(sa))
    rel_b, ib = _column_order(fb, column_geometry(sb))
    if rel_a.shape != rel_b.shape or not np.allclose(rel_a[ia], rel_b[ib], atol=1e-7):
        raise ValueError("the two runs do not have the same particle lattice")
    a = np.asarray(fa.stress)[ia, component]
    b = np.asarray(fb.stress)[ib, component]
    return _relative_l2(a, b)
