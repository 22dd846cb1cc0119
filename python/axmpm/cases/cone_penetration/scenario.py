"""The cone penetration test in undrained clay: scenario builder, the cone's resistance against
depth and the steady cone factor N_c of a run (docs/physics.md §8).

Problem (after the numgeo-pfem "CPT_Tresca" specification): a standard cone, radius
R = 17.85 mm (10 cm²), 60° apex, with a shaft of the same radius behind it, pushed axially into
weightless Tresca clay, s_u = 18 kPa, ν = 0.49, G = I_r s_u, at the isotropic in-situ stress
σ_v0 = σ_h0 = 66 kPa (Δ = (σ_v0 − σ_h0)/(2 s_u) = 0), which a 66 kPa surcharge on the soil's top
holds. Axisymmetric, the cone on the axis. The cone starts wished in place with its tip
``EMBEDMENT`` below the surface (a smooth cone in isotropically stressed soil is in equilibrium
there at t = 0) and is pushed ``PUSH`` further. q_c = tip force / πR² (the tip: the cone below
its shoulder, the rigid body's part ``tip``); N_c = (q_c − σ_v0)/s_u. The steady N_c is the mean
over the last ``WINDOW`` of the push, and its drift the slope of a straight line fitted over that
window per diameter of travel, relative to the mean.

The 150 cm² friction sleeve (length 150 cm²/(2πR) = 133.7 mm directly above the shoulder) is the
part ``sleeve``; its force is reported, not checked.

Domain: the plastic zone around the shaft reaches about R √I_r (the cylindrical cavity in Tresca
soil) and the soil's lateral confinement matters up to a few times that, so the soil's radius is
``WIDTH_FACTOR`` √I_r R (at least ``MIN_WIDTH`` R) and its depth below the final tip position half
of that (at least ``MIN_BELOW`` R). Rollers on the far side and the base. The case's domain check
doubles both.

Numerics and why:

* ``volumetric_averaging = "cell"``: ν = 0.49 and isochoric plastic flow lock a one-point MPM
  kinematics; the cell's mean dilatation (F-bar) removes it (docs/physics.md §1).
* cpGIMP, 2 × 2 particles per cell, MUSL, the default FLIP share 0.99, no local damping
  (docs/physics.md §8, "Cone penetration": what local damping and FLIP 0.999 do to the cone).
* Rate: the cone accelerates linearly to ``VELOCITY`` over ``RAMP`` of travel (a sudden start sends
  a pressure pulse ρ V c_p through the soil); ρ V² = 1.8 kPa is 0.1 s_u. The quasi-static
  check reports the kinetic energy over the plastic work at the end. N_c still falls with the
  speed, a numerical effect (half the speed: 11 % less at R/h = 4; docs/physics.md §8, "Rate");
  ``velocity`` sets the speed.
* The shaft reaches the top of the grid and the grid reaches ``PUSH`` + ``HEADROOM`` above the
  soil, so the shaft stays out of the soil's top until the end.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ...scenario import Scenario

__all__ = ["RADIUS", "UNDRAINED_STRENGTH", "IN_SITU_STRESS", "SHOULDER", "SLEEVE_LENGTH", "cone_scenario",
           "penetration_curve", "steady_cone_factor", "teh_houlsby", "lu_et_al", "domain"]

RADIUS = 0.01785  # R, m: the standard 10 cm² cone
DIAMETER = 2.0 * RADIUS
SHOULDER = RADIUS * math.sqrt(3.0)  # m: the height of a 60° cone
SLEEVE_AREA = 0.015  # m²: the standard 150 cm² friction sleeve
SLEEVE_LENGTH = SLEEVE_AREA / (2.0 * math.pi * RADIUS)  # m
UNDRAINED_STRENGTH = 18.0e3  # s_u, Pa
IN_SITU_STRESS = 66.0e3  # σ_v0 = σ_h0, Pa (compression)
POISSON_RATIO = 0.49
DENSITY = 1800.0  # kg/m³
VELOCITY = 1.0  # m/s
RAMP = 0.25  # × R of travel to reach VELOCITY
EMBEDMENT = 4.0  # × R: the tip's initial depth below the surface
PUSH = 20.0  # × R of travel (10 diameters)
WINDOW = 6.0  # × R: N_c is the mean over the last 3 diameters of the push
HEADROOM = 4.0  # × R of grid above the soil's heave, on top of the push
WIDTH_FACTOR = 3.0  # soil radius = WIDTH_FACTOR √I_r R ...
MIN_WIDTH = 20.0  # ... at least this many R
MIN_BELOW = 10.0  # × R of soil below the final tip position, at least
HISTORY_STEP = 0.05  # × R of travel between history rows

#: Rigidity indices I_r = G/s_u of the case.
RIGIDITY_INDICES: tuple[int, ...] = (50, 100, 300, 500)
#: Cells per cone radius R/h of the case (coarse to fine).
MESHES: tuple[int, ...] = (4, 8)
#: Interface adhesion over s_u by roughness (α: 0 smooth, 1 rough).
ROUGHNESS: dict[str, float] = {"smooth": 0.0, "rough": 1.0}


def teh_houlsby(rigidity_index: float, alpha: float = 0.0, shaft_alpha: float | None = None,
                anisotropy: float = 0.0) -> float:
    """Teh & Houlsby (1991): N_c = (4/3)(1 + ln I_r)(1.25 + I_r/2000) + 2.4 α_f − 0.2 α_s − 1.8 Δ
    (α_f on the cone face, α_s on the shaft; the shaft's α is the face's unless given)."""
    shaft = alpha if shaft_alpha is None else shaft_alpha
    return (4.0 / 3.0) * (1.0 + math.log(rigidity_index)) * (1.25 + rigidity_index / 2000.0) \
        + 2.4 * alpha - 0.2 * shaft - 1.8 * anisotropy


def lu_et_al(rigidity_index: float, alpha: float = 0.0, anisotropy: float = 0.0) -> float:
    """Lu, Randolph, Hu & Bugarski (2004): N_c = 3.4 + 1.6 ln I_r − 1.9 Δ + 1.3 α."""
    return 3.4 + 1.6 * math.log(rigidity_index) - 1.9 * anisotropy + 1.3 * alpha


def domain(rigidity_index: float, scale: float = 1.0, push: float = PUSH) -> tuple[float, float]:
    """(soil radius, soil depth below the final tip) in units of R (module doc), × ``scale``."""
    width = max(MIN_WIDTH, WIDTH_FACTOR * math.sqrt(rigidity_index))
    return scale * width, scale * max(MIN_BELOW, 0.5 * width)


def cone_scenario(rigidity_index: float = 100.0, roughness: str = "smooth", cells_per_radius: int = 4,
                  push: float = PUSH, domain_scale: float = 1.0, embedment: float = EMBEDMENT,
                  width: float | None = None, below: float | None = None,
                  velocity: float = VELOCITY) -> Scenario:
    """The cone penetration scenario (module doc): I_r = ``rigidity_index``, ``roughness``
    smooth or rough, R/h = ``cells_per_radius``, pushed ``push`` R at ``velocity`` m/s from
    ``embedment`` R below the surface, in a soil of the module's radius and depth ×
    ``domain_scale`` (or ``width`` and ``below`` R given)."""
    if roughness not in ROUGHNESS:
        raise ValueError(f"roughness must be one of {', '.join(ROUGHNESS)} (got {roughness!r})")
    if not rigidity_index > 0:
        raise ValueError(f"rigidity_index must be > 0 (got {rigidity_index})")
    if not velocity > 0:
        raise ValueError(f"velocity must be > 0 m/s (got {velocity})")
    R = RADIUS
    h = R / cells_per_radius
    default_width, default_below = domain(rigidity_index, domain_scale, push)
    width = default_width if width is None else width
    below = default_below if below is None else below
    cells = lambda length: max(1, math.ceil(length * cells_per_radius - 1e-9))  # noqa: E731 - whole cells of R
    soil_radius = cells(width) * h
    soil_depth = cells(embedment + push + below) * h
    grid_top = soil_depth + cells(push + HEADROOM) * h
    tip = soil_depth - embedment * R
    shear = rigidity_index * UNDRAINED_STRENGTH
    ramp_time = 2.0 * RAMP * R / velocity  # travel V t_r / 2 = RAMP R during the ramp
    end_time = ramp_time + (push * R - RAMP * R) / velocity
    data: dict[str, Any] = {
        "simulation": {
            "formulation": "axisymmetric",
            "shape_function": "cpgimp",
            "end_time": end_time,
            "output_interval": end_time / 4.0,
            "history_interval": HISTORY_STEP * R / velocity,
            "gravity": [0.0, 0.0],
            "volumetric_averaging": "cell",
        },
        "grid": {"origin": [0.0, 0.0], "extent": [soil_radius, grid_top], "cell_size": h},
        "materials": {
            "clay": {"model": "mohr_coulomb", "density": DENSITY, "youngs_modulus": 2.0 * shear * (1.0 + POISSON_RATIO),
                     "poisson_ratio": POISSON_RATIO, "friction_angle": 0.0, "cohesion": UNDRAINED_STRENGTH},
        },
        "bodies": [{"name": "soil", "material": "clay", "min": [0.0, 0.0], "max": [soil_radius, soil_depth],
                    "particles_per_cell": 2,
                    "initial_stress": {"vertical": -IN_SITU_STRESS, "horizontal": -IN_SITU_STRESS}}],
        "surcharges": [{"name": "overburden", "pressure": IN_SITU_STRESS, "level": soil_depth}],
        "rigid_bodies": [{
            "name": "cone", "shape": "polygon",
            "vertices": [[0.0, tip], [R, tip + SHOULDER], [R, grid_top], [0.0, grid_top]],
            "motion": [[0.0, 0.0, 0.0], [ramp_time, 0.0, -velocity]],
            "friction": 0.0,
            "adhesion": ROUGHNESS[roughness] * UNDRAINED_STRENGTH,
            "parts": [{"name": "tip", "below": SHOULDER}, {"name": "sleeve", "below": SHOULDER + SLEEVE_LENGTH}],
        }],
        "boundaries": {"left": "roller", "right": "roller", "bottom": "roller", "top": "free"},
    }
    name = f"cone I_r={rigidity_index:g} {roughness} R/h={cells_per_radius}"
    return Scenario.from_dict(data, source=name)


def penetration_curve(run_dir: str | Path, embedment: float = EMBEDMENT) -> dict[str, np.ndarray]:
    """The cone's resistance against depth at every history row after the first: ``depth`` of
    the tip below the surface in diameters (at the row interval's mid-travel), ``travel`` in
    diameters, ``cone_factor`` (q_c − σ_v0)/s_u from the tip part, ``tip``, ``sleeve``, ``total``
    axial forces (N) and the parts' sum ``parts_sum`` (tip + sleeve + rest)."""
    from ...run.output import load_run

    body = load_run(run_dir).rigid_bodies["cone"]
    travel = -body["displacement"][:, 1] / DIAMETER
    mid = 0.5 * (travel[1:] + travel[:-1])
    tip = body["tip_force"][1:, 1]
    q_c = tip / (math.pi * RADIUS**2)
    parts = body["tip_force"][1:, 1] + body["sleeve_force"][1:, 1] + body["rest_force"][1:, 1]
    return {"travel": mid, "depth": mid + embedment * RADIUS / DIAMETER,
            "cone_factor": (q_c - IN_SITU_STRESS) / UNDRAINED_STRENGTH, "tip": tip,
            "sleeve": body["sleeve_force"][1:, 1], "total": body["force"][1:, 1], "parts_sum": parts}


def steady_cone_factor(travel: np.ndarray, cone_factor: np.ndarray, push: float = PUSH,
                       window: float = WINDOW) -> tuple[float | None, float | None]:
    """(mean N_c, drift per diameter relative to the mean) over the last ``window`` R of a push of
    ``push`` R (travel in diameters); (None, None) when the run did not get there."""
    end = push * RADIUS / DIAMETER
    start = end - window * RADIUS / DIAMETER
    if len(travel) < 3 or travel.max() < end - HISTORY_STEP * RADIUS / DIAMETER - 1e-9:
        return None, None
    inside = travel >= start - 1e-9
    if inside.sum() < 3:
        return None, None
    mean = float(np.mean(cone_factor[inside]))
    slope = float(np.polyfit(travel[inside], cone_factor[inside], 1)[0])
    return mean, slope / mean
