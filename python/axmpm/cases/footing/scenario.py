"""The rigid footing on weightless Tresca soil: scenario builder, load–settlement curve and the
bearing capacity factor N_c of a run (docs/physics.md §8).

Problem: a rigid footing of width (diameter) B = 1 m resting on the surface of a weightless
(g = 0) Tresca layer, s_u = 10 kPa, E = 3 MPa, ν = 0.49, ρ = 1800 kg/m³, pushed down at a
prescribed velocity. Strip footing in plane strain, modelled as its half against the symmetry
roller at x = 0; circular footing in axisymmetry (radius B/2 on the axis). The soil is 5B wide
(the half model 2.5B from the symmetry line or axis, rollers on the far side) and 3B deep (fixed
base): the Prandtl mechanism reaches 1.5B from the centre line and 0.7B deep (strip), so the
boundaries do not cut it. N_c = q/s_u with q = footing force / footing area (B/2 per metre for
the half strip, π B²/4 for the circle), averaged over the settlements 0.04B–0.06B.

Exact (Prandtl; Shield 1955, Eason & Shield 1960, Cox, Eason & Hopkins 1961; docs/physics.md §8):
strip 2 + π = 5.14 smooth and rough, circle 5.69 smooth and 6.05 rough.

Numerics and why:

* ``volumetric_averaging = "cell"``: ν = 0.49 and isochoric plastic flow lock a one-point MPM
  kinematics; the cell's mean dilatation (F-bar) removes it (docs/physics.md §1).
* cpGIMP, 2 × 2 particles per cell, MUSL, FLIP 0.999 (``flip_fraction``), CFL 0.4.
  Scheme: the original MPM (``linear``) is 2–3× cheaper and within 2 % at B/h = 10 and 20
  (strip, smooth, FLIP 0.99: 5.19, 5.12), but at B/h = 40 the averaging window is 2.4 cells of
  travel and the cell-crossing noise of the hat functions makes the load decay after its peak
  (4.48, −13 %; one run lost a particle above the grid); uGIMP and cpGIMP stay smooth (5.33 and
  5.32 at B/h = 40 with FLIP 0.99). FLIP: the PIC part of the blend damps a fixed fraction of the
  velocity field per step, and the nearly incompressible soil needs ~13,000 steps at B/h = 40,
  so even 1 % of PIC acts as a viscosity: with FLIP 0.99, N_c fell by 1.4 % when the footing
  moved half as fast (circle, B/h = 20), and pure FLIP gave N_c 2–3 % below FLIP 0.99 (strip and
  circle, B/h = 20 and 40); more PIC is far worse (FLIP 0.5: +18 %, PIC: +25 %, linear, B/h =
  20). Pure FLIP, however, let the particle noise at the circular footing's edge grow until a
  particle was thrown off the grid (smooth, B/h = 40, twice, at settlements 0.056B and 0.063B);
  FLIP 0.999 keeps a tenth of the default PIC share, which damps that noise (the run completes)
  at a tenth of the 0.99 viscosity (N_c within 0.7 % of pure FLIP on the strip). These choices
  are made for the numerics (no noise, no numerical viscosity), not tuned to the exact values.
* Loading rate. The footing accelerates linearly to V = 0.1 m/s over t_r = 0.1 s (a settlement of
  0.005B) and then moves at V. Inertia: in steady motion the dynamic pressure ρV² = 18 Pa is
  0.04 % of the collapse pressure N_c s_u ≈ 51 kPa; a sudden start would send a pressure pulse
  ρ V c_p = 30 kPa (c_p = 169 m/s), hence the ramp, whose acceleration V/t_r = 1 m/s² asks for
  about ρ (V/t_r) B/2 ≈ 0.9 kPa (2 %) while it lasts — over 0.35 s before the averaging window
  (0.04B, t = 0.45 s). The loading to 0.06B takes 0.65 s, about six shear-wave transits
  (c_s = 24 m/s) of the 2.5 m half width. Checked: V = 0.05, 0.1 and 0.2 m/s gave N_c within
  0.6 % of each other (strip, smooth, B/h = 20); 0.4 m/s gave 9 % more.
* Headroom: the grid reaches 0.5 m above the soil surface (the heave, and room for the footing).
* Cost: the P-wave of the nearly incompressible soil sets Δt = 0.4 h/c_p (5.9e-5 s at B/h = 40),
  so the finest run is 48,000 particles × 12,700 steps ≈ 6e8 particle-steps (2–4 min of one
  core with cpGIMP; the whole case 10–20 min on one core, 5–10 min with two jobs).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ...scenario import Scenario

__all__ = ["WIDTH", "UNDRAINED_STRENGTH", "EXACT", "SETTLEMENT_WINDOW", "footing_scenario", "load_settlement",
           "bearing_capacity_factor", "footing_area", "MESHES", "loaded_footing_scenario", "footing_mass"]

WIDTH = 1.0  # B, m: strip width or circle diameter
UNDRAINED_STRENGTH = 10.0e3  # s_u, Pa
YOUNGS_MODULUS = 3.0e6  # Pa
POISSON_RATIO = 0.49
DENSITY = 1800.0  # kg/m³
SOIL_HALF_WIDTH = 2.5  # m: 5B of soil in all (the half model's width from the symmetry line / axis)
SOIL_DEPTH = 3.0  # m: 3B
FOOTING_THICKNESS = 0.2  # m (rigid: only its base and sides matter)
HEADROOM = 0.5  # m of grid above the soil surface (the heave; and see the module doc)
VELOCITY = 0.1  # m/s
RAMP_TIME = 0.1  # s
FINAL_SETTLEMENT = 0.07  # × B: the run goes a little past the averaging window
SETTLEMENT_WINDOW = (0.04, 0.06)  # × B: N_c is the mean of q/s_u over these settlements
HISTORY_SETTLEMENT_STEP = 0.001  # × B between history rows

#: (formulation, roughness) → exact N_c.
EXACT: dict[tuple[str, str], float] = {
    ("plane_strain", "smooth"): 2.0 + math.pi,
    ("plane_strain", "rough"): 2.0 + math.pi,
    ("axisymmetric", "smooth"): 5.69,
    ("axisymmetric", "rough"): 6.05,
}

#: Cells per footing width B of the verification (coarse to fine).
MESHES: tuple[int, ...] = (10, 20, 40)


def settlement_at(time: float) -> float:
    """Footing settlement (m) at ``time`` for the ramped motion (the integral of the velocity)."""
    if time <= RAMP_TIME:
        return 0.5 * VELOCITY * time * time / RAMP_TIME
    return VELOCITY * (time - 0.5 * RAMP_TIME)


def time_of_settlement(settlement: float) -> float:
    ramp = 0.5 * VELOCITY * RAMP_TIME
    if settlement <= ramp:
        return math.sqrt(2.0 * settlement * RAMP_TIME / VELOCITY)
    return settlement / VELOCITY + 0.5 * RAMP_TIME


def footing_area(formulation: str) -> float:
    """The area q is taken over: the half strip (B/2 per metre) or the circle (π B²/4)."""
    return 0.5 * WIDTH if formulation == "plane_strain" else math.pi * WIDTH * WIDTH / 4.0


def footing_scenario(formulation: str = "plane_strain", roughness: str = "smooth", cells_per_width: int = 20,
                     shape_function: str = "cpgimp", contact: str = "nodes", grid: str = "fixed") -> Scenario:
    """The footing scenario (module doc) at B/h = ``cells_per_width``, the footing's contact
    enforced by ``contact`` (``"nodes"``, or the experimental ``"penalty"``), on a ``grid`` that
    is ``"fixed"`` or ``"follow"``s the footing (``grid.follow``)."""
    if grid not in ("fixed", "follow"):
        raise ValueError(f"grid must be fixed or follow (got {grid!r})")
    if formulation not in ("plane_strain", "axisymmetric"):
        raise ValueError(f"formulation must be plane_strain or axisymmetric (got {formulation!r})")
    if roughness not in ("smooth", "rough"):
        raise ValueError(f"roughness must be smooth or rough (got {roughness!r})")
    h = WIDTH / cells_per_width
    end_time = time_of_settlement(FINAL_SETTLEMENT * WIDTH)
    top = SOIL_DEPTH + FOOTING_THICKNESS
    grid_top = SOIL_DEPTH + HEADROOM
    data: dict[str, Any] = {
        "simulation": {
            "formulation": formulation,
            "shape_function": shape_function,
            "end_time": end_time,
            "output_interval": end_time / 2.0,
            "history_interval": HISTORY_SETTLEMENT_STEP * WIDTH / VELOCITY,
            "gravity": [0.0, 0.0],
            "volumetric_averaging": "cell",
            "flip_fraction": 0.999,
        },
        "grid": {"origin": [0.0, 0.0], "extent": [SOIL_HALF_WIDTH, grid_top], "cell_size": h,
                 "follow": "footing" if grid == "follow" else None, "experimental": grid == "follow"},
        "materials": {
            "clay": {"model": "mohr_coulomb", "density": DENSITY, "youngs_modulus": YOUNGS_MODULUS,
                     "poisson_ratio": POISSON_RATIO, "friction_angle": 0.0, "cohesion": UNDRAINED_STRENGTH},
        },
        "bodies": [{"name": "soil", "material": "clay", "min": [0.0, 0.0], "max": [SOIL_HALF_WIDTH, SOIL_DEPTH],
                    "particles_per_cell": 2}],
        "rigid_bodies": [{
            "name": "footing", "shape": "rectangle", "min": [0.0, SOIL_DEPTH], "max": [0.5 * WIDTH, top],
            "motion": [[0.0, 0.0, 0.0], [RAMP_TIME, 0.0, -VELOCITY]],
            "friction": "rough" if roughness == "rough" else 0.0,
            "contact": contact,
            "experimental": contact == "penalty",
        }],
        "boundaries": {"left": "roller", "right": "roller", "bottom": "fixed", "top": "free"},
    }
    return Scenario.from_dict(data, source=f"footing {formulation} {roughness} B/h={cells_per_width}")


def footing_mass(formulation: str) -> float:
    """Mass of the loaded footing, kg (per metre of the half strip, or the whole disc): a
    concrete footing of the scenario's thickness, ρ = 2400 kg/m³."""
    return 2400.0 * FOOTING_THICKNESS * footing_area(formulation)


def loaded_footing_scenario(formulation: str, roughness: str, cells_per_width: int, load_fraction: float,
                            duration: float, ramp_time: float = 0.2, shape_function: str = "cpgimp") -> Scenario:
    """The footing of :func:`footing_scenario` driven by a load instead of a velocity: a
    force-driven rigid body of mass :func:`footing_mass` under the pressure ``load_fraction`` ×
    q_ult on its area (q_ult = N_c s_u with the exact N_c of ``EXACT``; the force per metre of
    the half strip, or of the whole disc), ramped in linearly over ``ramp_time`` and then held,
    run for ``duration`` seconds (weightless soil, as the original)."""
    scenario = footing_scenario(formulation, roughness, cells_per_width, shape_function)
    data = scenario.model_dump(mode="json", exclude_none=True)
    load = load_fraction * EXACT[(formulation, roughness)] * UNDRAINED_STRENGTH * footing_area(formulation)
    body = data["rigid_bodies"][0]
    body.pop("motion", None)
    body.pop("velocity", None)
    body.update(mass=footing_mass(formulation), force=[[0.0, 0.0, 0.0], [ramp_time, 0.0, -load]])
    data["simulation"].update(end_time=duration, output_interval=duration,
                              history_interval=duration / 200.0)
    source = f"loaded footing {formulation} {roughness} B/h={cells_per_width} {load_fraction} q_ult"
    return Scenario.from_dict(data, source=source)


def load_settlement(run_dir: str | Path, formulation: str) -> tuple[np.ndarray, np.ndarray]:
    """(δ/B, q/s_u) at every history row after the first of a footing run: settlement from the
    footing's displacement, q from its force (the mean over the row's interval, plotted at the
    interval's mid-settlement)."""
    from ...run.output import load_run

    body = load_run(run_dir).rigid_bodies["footing"]
    settlement = -body["displacement"][:, 1] / WIDTH
    force = body["force"][:, 1]
    mid = 0.5 * (settlement[1:] + settlement[:-1])
    return mid, force[1:] / footing_area(formulation) / UNDRAINED_STRENGTH


def bearing_capacity_factor(settlement: np.ndarray, nc: np.ndarray) -> float | None:
    """Mean of q/s_u over the settlement window 0.04B–0.06B (None when the run did not get there)."""
    lo, hi = SETTLEMENT_WINDOW
    inside = (settlement >= lo - 1e-9) & (settlement <= hi + 1e-9)
    if not inside.any() or settlement.max() < hi - 1e-9:
        return None
    return float(np.mean(nc[inside]))
