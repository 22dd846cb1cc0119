"""``consolidation``: Terzaghi's one-dimensional consolidation of a saturated column, in plane
strain and in axisymmetry, against the series solution (:mod:`.exact`), Mandel's problem in
plane strain (:mod:`.mandel`, :func:`mandel_scenario`), and Cryer's sphere and de Leeuw's
cylinder in axisymmetry (:mod:`.radial`, :func:`radial_scenario`): the centre's pressure against
the closed forms, its rise above p₀ included (docs/verification.md "Consolidation").

Scenario (:func:`column_scenario`): a column H = 1 m high and one cell wide of a linear elastic
skeleton (E = 10 MPa, ν = 0, so E_oed = E; grains 2650 kg/m³) saturated with water (n = 0.4,
K_w = 2.2 GPa, ρ_w = 1000 kg/m³, k = 1e-4 m/s: the consolidation time is then ~4000 periods of the column's undrained ringing after the step load, whose extra early drainage stays below 1e-3 in U), no gravity, base fixed and impermeable, sides
rollers (impermeable), top free and drained under a surface load q = 10 kPa applied at t = 0.
Plane strain: the column spans x = 0 … h next to a roller face and a roller wall.
Axisymmetric: a ring r = 1 … 1 + h m between two roller walls, off the axis (the hoop terms are
present, the flow stays one-dimensional). Linear shape functions, 2 × 2 particles per cell,
MUSL, FLIP 0.99, the default time step (0.4 of the undrained wave's).

Runs: both formulations at H/h = 10 and 20 (``--quick``: 10 only, at k = 1e-3 m/s), to T_v = 0.85 with a frame
every ΔT_v = 0.0025; and ``undrained``: plane strain, H/h = 10, k = 1e-9 m/s and soft water
(K_w = 20 MPa, so that u₀ = 0.833 q differs from q), ten periods of the column's undrained
ringing, a frame every ten steps.

Metrics: U = 1 − ⟨p⟩/u₀ (⟨p⟩ the volume-weighted mean over the particles) at the T_v of
U = 0.2, 0.4, 0.5, 0.6, 0.8, 0.9 (linear interpolation between frames); the worst
|p/u₀ − u(z)/u₀| over the particles at T_v = 0.05, 0.2, 0.5 (the frame nearest, z the particle's
initial depth); for ``undrained``, the time average of ⟨p⟩ over the frames against u₀.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

from .. import RunSpec, register
from ...report import DASH, fmt
from . import exact

HEIGHT = 1.0
LOAD = 1.0e4
SKELETON = {"model": "linear_elastic", "density": 2650.0, "youngs_modulus": 1.0e7, "poisson_ratio": 0.0}
OEDOMETER_MODULUS = 1.0e7  # E (1 − ν)/((1 + ν)(1 − 2ν)) at ν = 0
POROSITY = 0.4
WATER_DENSITY = 1000.0
WATER_BULK_MODULUS = 2.2e9
CONDUCTIVITY = 1.0e-4
#: The quick runs' k: ten times fewer steps; U(0.0314) then runs about 0.003 ahead (the early
#: drainage of the ringing), well within the tolerance.
QUICK_CONDUCTIVITY = 1.0e-3
#: The undrained run: very low k and soft water.
UNDRAINED_CONDUCTIVITY = 1.0e-9
UNDRAINED_WATER_BULK_MODULUS = 2.0e7
UNDRAINED_PERIODS = 10
#: Inner radius of the axisymmetric ring, m.
RING_RADIUS = 1.0
MESHES = (10, 20)
QUICK_MESHES = (10,)
FORMULATIONS = ("plane_strain", "axisymmetric")
#: T_v of U = 0.2, 0.4, 0.5, 0.6, 0.8, 0.9 (exact.time_factor_of_degree, rounded).
DEGREE_TIME_FACTORS = (0.0314, 0.1257, 0.1967, 0.2864, 0.5672, 0.8481)
ISOCHRONE_TIME_FACTORS = (0.05, 0.2, 0.5)
FRAME_TIME_FACTOR = 0.0025
END_TIME_FACTOR = 0.85
#: Targets: U within 0.02 (absolute), isochrones within 0.03 u₀, the undrained share within 1 %.
DEGREE_TOLERANCE = 0.02
ISOCHRONE_TOLERANCE = 0.03
UNDRAINED_TOLERANCE = 0.01


#: Mandel's problem (:mod:`.mandel`): a quarter of the specimen, half-width a and half-height b,
#: a/h cells across; the plate's mean pressure is LOAD.
MANDEL_HALF_WIDTH = 1.0
MANDEL_HALF_HEIGHT = 0.5
MANDEL_MESHES = (10, 20)
QUICK_MANDEL_MESHES = (10,)
#: History rows every ΔT = 0.005 (T = c t/a²) up to T = 0.6 (0.15 in the quick run, past the peak).
MANDEL_ROW_TIME_FACTOR = 0.005
MANDEL_END_TIME_FACTOR = 0.6
QUICK_MANDEL_END_TIME_FACTOR = 0.15
#: k of the Mandel runs: the step load sets the nearly incompressible specimen ringing in shear
#: (period ≈ 0.04 s); at this k the consolidation time a²/c = 10 s is 250 such periods.
MANDEL_CONDUCTIVITY = 1.0e-4
#: Cundall local damping of the Mandel runs (a quasi-static problem): it settles the ringing by
#: T ≈ 0.05 (at T = 0.02 it is still 4 % of p₀), before the centre's pressure peaks (T ≈ 0.08).
MANDEL_DAMPING = 0.2
#: The centre's pressure within 5 % of p₀ at every row from T = 0.05 on (p is then already 1.14 p₀,
#: on its way up to the peak).
MANDEL_TOLERANCE = 0.05
MANDEL_FROM_TIME_FACTOR = 0.05
# Largest spread of the cell pressures down one column of cells (p₀), where the exact field is
# uniform: a checkerboard of the pressure would exceed it.
CHECKERBOARD_TOLERANCE = 0.01


#: Cryer's sphere and de Leeuw's cylinder (:mod:`.radial`), radius R, R/h cells across, set up as
#: the drained-surface perturbation of docs/physics.md §10: free, drained surface, initial pore
#: pressure p₀ and effective stress of the undrained-minus-drained state under LOAD, no load.
RADIAL_RADIUS = 1.0
RADIAL_SHAPES = ("sphere", "cylinder")
RADIAL_NAMES = {"sphere": "cryer", "cylinder": "deleeuw"}
RADIAL_TITLES = {"sphere": "Cryer's sphere", "cylinder": "de Leeuw's cylinder"}
RADIAL_MESHES = (10, 20)
QUICK_RADIAL_MESHES = (10,)
#: The cylinder is a slab of this many cells between its two roller plates.
CYLINDER_CELLS_HIGH = 2
#: Chords of the sphere's quarter circle (the polygon body; particles fill it by their centres).
SPHERE_CHORDS = 90
#: History rows every ΔT = 0.005 (T = c t/R²) up to T = 0.5 (0.15 in the quick run, past the peak
#: at T ≈ 0.06).
RADIAL_ROW_TIME_FACTOR = 0.005
RADIAL_END_TIME_FACTOR = 0.5
QUICK_RADIAL_END_TIME_FACTOR = 0.15
#: k of the radial runs, as Mandel's: R²/c = 9.8 s.
RADIAL_CONDUCTIVITY = 1.0e-4
#: The centre's pressure within 5 % of p₀ at every row from T = RADIAL_FROM_TIME_FACTOR on.
RADIAL_TOLERANCE = 0.05
RADIAL_FROM_TIME_FACTOR = 0.01


def _saturated_block(formulation: str, end_time: float, output_interval: float, h: float, extent: list[float],
                     name: str, lo: list[float], hi: list[float], conductivity: float,
                     water_bulk_modulus: float) -> dict[str, Any]:
    """What the case's scenarios share: no gravity, linear shape functions, MUSL with FLIP 0.99,
    the grid from the origin, one rectangular body of the skeleton, 2 × 2 particles per cell,
    saturated with the case's water under LOAD."""
    return {
        "simulation": {"formulation": formulation, "shape_function": "linear", "end_time": end_time,
                       "output_interval": output_interval, "gravity": [0.0, 0.0], "flip_fraction": 0.99,
                       "update_scheme": "musl"},
        "grid": {"origin": [0.0, 0.0], "extent": extent, "cell_size": h},
        "materials": {"skeleton": dict(SKELETON)},
        "bodies": [{"name": name, "material": "skeleton", "min": lo, "max": hi, "particles_per_cell": 2,
                    "saturated": {"porosity": POROSITY, "hydraulic_conductivity": conductivity,
                                  "water_bulk_modulus": water_bulk_modulus, "water_density": WATER_DENSITY,
                                  "surface_load": LOAD}}],
    }


def mandel_material(conductivity: float) -> Any:
    from .mandel import MandelMaterial

    return MandelMaterial(SKELETON["youngs_modulus"], SKELETON["poisson_ratio"], POROSITY, WATER_BULK_MODULUS,
                          WATER_DENSITY, conductivity)


def mandel_scenario(cells: int, conductivity: float, end_time_factor: float = MANDEL_END_TIME_FACTOR,
                    *, as_dict: bool = False) -> Any:
    """Mandel's specimen as its quarter 0 ≤ x ≤ a, 0 ≤ y ≤ b: rollers (impermeable) on the axes of
    symmetry x = 0 and y = 0, the side x = a free and drained, the top under LOAD through the
    rigid, frictionless, impermeable loading plate; no gravity; the probe ``centre`` at x = 0."""
    a, b = MANDEL_HALF_WIDTH, MANDEL_HALF_HEIGHT
    h = a / cells
    time_scale = a * a / mandel_material(conductivity).consolidation_coefficient
    data = _saturated_block("plane_strain", end_time_factor * time_scale, 0.1 * time_scale, h, [a + 2 * h, b + 2 * h],
                            "specimen", [0.0, 0.0], [a, b], conductivity, WATER_BULK_MODULUS)
    data["simulation"]["history_interval"] = MANDEL_ROW_TIME_FACTOR * time_scale
    data["simulation"]["damping"] = MANDEL_DAMPING
    data["bodies"][0]["saturated"]["loading_plate"] = True
    data["boundaries"] = {"left": "roller", "right": "free", "bottom": "roller", "top": "free"}
    data["probes"] = [{"name": "centre", "point": [0.0, 0.5 * b]}]
    if as_dict:
        return data
    from ...scenario import Scenario

    return Scenario.from_dict(data, source=f"consolidation mandel_n{cells:02d}")


def _centre_metrics(run_dir: Path, time_scale: float, p0: float, exact_centre: Any, from_time_factor: float,
                    error_key: str) -> dict[str, Any]:
    """The probe ``centre``'s pore pressure against a closed form ``exact_centre(T)`` (p/p₀ at
    T = t/``time_scale``) at every history row from ``from_time_factor`` on: the worst
    |p − p_exact|/p₀ (under ``error_key``), the peak p/p₀ of both and its T (over those rows)."""
    import numpy as np

    from ...run.output import load_run

    try:
        history = load_run(run_dir).history
        t = np.asarray(history["time"]) / time_scale
        p = np.asarray(history["centre.pore_pressure"]) / p0
    except Exception:  # noqa: BLE001 - a failed run without history
        return {error_key: None, "p0": p0}
    if len(t) < 3:
        return {error_key: None, "p0": p0}
    later = t >= from_time_factor
    t, p = t[later], p[later]
    exact_p = exact_centre(t)
    return {"p0": p0, error_key: float(np.max(np.abs(p - exact_p))),
            "peak": float(p.max()), "peak_exact": float(exact_p.max()),
            "peak_time_factor": float(t[int(np.argmax(p))])}


def mandel_metrics(run: RunSpec, run_dir: Path) -> dict[str, Any]:
    """The centre's pressure against Mandel's closed form at every history row from
    MANDEL_FROM_TIME_FACTOR on: the worst |p − p_exact|/p₀, the peak p/p₀ of both (over those rows)."""
    from . import mandel

    material = mandel_material(run.params["conductivity"])
    out = _centre_metrics(run_dir, MANDEL_HALF_WIDTH**2 / material.consolidation_coefficient,
                          material.initial_pressure(LOAD), lambda t: mandel.centre_pressure(t, material),
                          MANDEL_FROM_TIME_FACTOR, "mandel_error")
    if out["mandel_error"] is None:
        return out
    import numpy as np

    from ...run.output import load_run

    p0 = out["p0"]
    run_output = load_run(run_dir)
    h = MANDEL_HALF_WIDTH / run.params["cells"]
    field = [mandel.field_errors(frame.x, frame.pore_pressure, h, MANDEL_HALF_WIDTH, time_factor, material, p0)
             for time_factor, frame in zip(np.asarray(run_output.times) * material.consolidation_coefficient
                                           / MANDEL_HALF_WIDTH**2, run_output.frames)
             if time_factor >= MANDEL_FROM_TIME_FACTOR]
    out.update({"cell_size": h, "field_error": max((f[0] for f in field), default=None),
                "column_spread": max((f[1] for f in field), default=None)})
    return out


def radial_metrics(run: RunSpec, run_dir: Path) -> dict[str, Any]:
    """The centre's pressure of Cryer's sphere or de Leeuw's cylinder against its closed form at
    every history row from RADIAL_FROM_TIME_FACTOR on (:func:`_centre_metrics`)."""
    from . import radial

    shape = run.params["shape"]
    material = mandel_material(run.params["conductivity"])
    out = _centre_metrics(run_dir, RADIAL_RADIUS**2 / material.consolidation_coefficient,
                          radial.initial_pressure(shape, LOAD, material),
                          lambda t: radial.centre_pressure(shape, t, material), RADIAL_FROM_TIME_FACTOR,
                          "centre_error")
    if out["centre_error"] is not None:
        out["cell_size"] = RADIAL_RADIUS / run.params["cells"]
    return out


def radial_scenario(shape: str, cells: int, conductivity: float, end_time_factor: float = RADIAL_END_TIME_FACTOR,
                    *, as_dict: bool = False) -> Any:
    """Cryer's sphere (``shape = "sphere"``) or de Leeuw's cylinder (``"cylinder"``) in
    axisymmetry, as the perturbation of its drained final state (docs/physics.md §10): no load,
    the surface r = R free and drained, the initial pore pressure p₀ and effective stress of
    :func:`.radial.initial_effective_stress`; the axis a roller (impermeable). Sphere: the quarter
    disc r, z ≥ 0 (a polygon of SPHERE_CHORDS chords), the plane z = 0 a roller (impermeable, the
    plane of symmetry). Cylinder: a slab 0 ≤ z ≤ CYLINDER_CELLS_HIGH h between the roller faces
    z = 0 and the top of the grid (impermeable). The probe ``centre`` sits at the origin."""
    from . import radial

    r = RADIAL_RADIUS
    h = r / cells
    material = mandel_material(conductivity)
    time_scale = r * r / material.consolidation_coefficient
    height = r if shape == radial.SPHERE else CYLINDER_CELLS_HIGH * h
    grid_height = r + 2 * h if shape == radial.SPHERE else height
    data = _saturated_block("axisymmetric", end_time_factor * time_scale, 0.1 * time_scale, h,
                            [r + 2 * h, grid_height], shape, [0.0, 0.0], [r, height], conductivity,
                            WATER_BULK_MODULUS)
    data["simulation"]["history_interval"] = RADIAL_ROW_TIME_FACTOR * time_scale
    body = data["bodies"][0]
    saturated = body["saturated"]
    del saturated["surface_load"]
    saturated["pore_pressure"] = radial.initial_pressure(shape, LOAD, material)
    rr, zz, hoop = radial.initial_effective_stress(shape, LOAD, material)
    body["initial_stress"] = {"xx": rr, "yy": zz, "zz": hoop, "xy": 0.0}
    if shape == radial.SPHERE:
        del body["min"], body["max"]
        arc = [[r * math.cos(a), r * math.sin(a)]
               for a in (0.5 * math.pi * i / SPHERE_CHORDS for i in range(SPHERE_CHORDS + 1))]
        body.update({"shape": "polygon", "vertices": [[0.0, 0.0]] + arc})
        data["boundaries"] = {"left": "roller", "right": "free", "bottom": "roller", "top": "free"}
    else:
        data["boundaries"] = {"left": "roller", "right": "free", "bottom": "roller", "top": "roller"}
    data["probes"] = [{"name": "centre", "point": [0.0, 0.0]}]
    if as_dict:
        return data
    from ...scenario import Scenario

    return Scenario.from_dict(data, source=f"consolidation {shape}_n{cells:02d}")


def run_name(formulation: str, cells: int) -> str:
    return f"{formulation}_n{cells:02d}"


def radial_run_name(shape: str, cells: int) -> str:
    """``cryer_nNN`` (the sphere) or ``deleeuw_nNN`` (the cylinder)."""
    return f"{RADIAL_NAMES[shape]}_n{cells:02d}"


def run_specs(quick: bool = False) -> list[RunSpec]:
    meshes = QUICK_MESHES if quick else MESHES
    k = QUICK_CONDUCTIVITY if quick else CONDUCTIVITY
    runs = [RunSpec(run_name(f, n), {"formulation": f, "cells": n, "kind": "consolidation", "conductivity": k})
            for f in FORMULATIONS for n in meshes]
    runs.append(RunSpec("undrained", {"formulation": "plane_strain", "cells": 10, "kind": "undrained"}))
    runs += [RunSpec(f"mandel_n{n:02d}", {"formulation": "plane_strain", "cells": n, "kind": "mandel",
                                          "conductivity": MANDEL_CONDUCTIVITY, "quick": quick})
             for n in (QUICK_MANDEL_MESHES if quick else MANDEL_MESHES)]
    runs += [RunSpec(radial_run_name(shape, n), {"formulation": "axisymmetric", "cells": n, "kind": "radial",
                                                 "shape": shape, "conductivity": RADIAL_CONDUCTIVITY, "quick": quick})
             for shape in RADIAL_SHAPES for n in (QUICK_RADIAL_MESHES if quick else RADIAL_MESHES)]
    return runs


def water(kind: str, conductivity: float = CONDUCTIVITY) -> tuple[float, float]:
    """(k, K_w) of a run kind."""
    if kind == "undrained":
        return UNDRAINED_CONDUCTIVITY, UNDRAINED_WATER_BULK_MODULUS
    return conductivity, WATER_BULK_MODULUS


def consolidation_coefficient(kind: str, conductivity: float = CONDUCTIVITY) -> float:
    k, k_w = water(kind, conductivity)
    return exact.consolidation_coefficient(k, WATER_DENSITY, POROSITY, k_w, OEDOMETER_MODULUS)


def undrained_wave_speed(k_w: float) -> float:
    rho_sat = (1.0 - POROSITY) * SKELETON["density"] + POROSITY * WATER_DENSITY
    return math.sqrt((OEDOMETER_MODULUS + k_w / POROSITY) / rho_sat)


def column_scenario(formulation: str, cells: int, kind: str = "consolidation", conductivity: float = CONDUCTIVITY,
                    *, as_dict: bool = False) -> Any:
    """The scenario of one run (module doc)."""
    h = HEIGHT / cells
    k, k_w = water(kind, conductivity)
    axisymmetric = formulation == "axisymmetric"
    x0 = RING_RADIUS if axisymmetric else 0.0
    if kind == "undrained":
        period = 4.0 * HEIGHT / undrained_wave_speed(k_w)
        end_time = UNDRAINED_PERIODS * period
        dt = 0.4 * h / undrained_wave_speed(k_w)
        output_interval = end_time / round(end_time / (10 * dt))
    else:
        time_scale = HEIGHT**2 / consolidation_coefficient(kind, conductivity)
        end_time = END_TIME_FACTOR * time_scale
        output_interval = FRAME_TIME_FACTOR * time_scale
    walls = [{"axis": "x", "position": x0 + h, "material_side": "negative", "condition": "roller"}]
    if axisymmetric:
        walls.insert(0, {"axis": "x", "position": x0, "material_side": "positive", "condition": "roller"})
    data = _saturated_block(formulation, end_time, output_interval, h, [x0 + 3 * h, HEIGHT + 2 * h], "soil",
                            [x0, 0.0], [x0 + h, HEIGHT], k, k_w)
    # Base fixed and impermeable, sides rollers and impermeable, top free and drained (the
    # faces' defaults).
    data["boundaries"] = {"left": "roller", "right": "free", "bottom": "fixed", "top": "free"}
    data["walls"] = walls
    if as_dict:
        return data
    from ...scenario import Scenario

    return Scenario.from_dict(data, source=f"consolidation {run_name(formulation, cells)}")


def _mean_pressure(frame: Any) -> float:
    return float((frame.pore_pressure * frame.volume).sum() / frame.volume.sum())


def run_metrics(run: RunSpec, run_dir: Path) -> dict[str, Any]:
    """The metrics of a run folder (module doc; None values when it has no frame)."""
    import numpy as np

    from ...run.output import load_run

    kind = run.params["kind"]
    if kind == "mandel":
        return mandel_metrics(run, run_dir)
    if kind == "radial":
        return radial_metrics(run, run_dir)
    k_w = water(kind)[1]
    u0 = exact.undrained_pressure(LOAD, POROSITY, k_w, OEDOMETER_MODULUS)
    try:
        frames = load_run(run_dir).frames
        times = np.array([f.time for f in frames])
        means = np.array([_mean_pressure(f) for f in frames])
    except Exception:  # noqa: BLE001 - a failed run without frames
        frames, times, means = [], np.zeros(0), np.zeros(0)
    if kind == "undrained":
        if len(frames) < 2:
            return {"undrained_ratio": None}
        # Frames at t > 0: whole periods of the ringing.
        ratio = float(means[times > 0].mean() / u0)
        return {"undrained_ratio": ratio, "undrained_error": abs(ratio - 1.0), "u0": u0}
    cv = consolidation_coefficient(kind, run.params["conductivity"])
    tv = times * cv / HEIGHT**2
    out: dict[str, Any] = {"u0": u0}
    if len(frames) < 2 or tv[-1] < max(DEGREE_TIME_FACTORS):
        out.update({"degree_error": None, "isochrone_error": None})
        return out
    degree = 1.0 - means / u0
    errors = []
    for t in DEGREE_TIME_FACTORS:
        u = float(np.interp(t, tv, degree))
        out[f"U_{t:g}"] = u
        errors.append(abs(u - exact.degree(t)))
    out["degree_error"] = max(errors)
    worst = 0.0
    h = HEIGHT / run.params["cells"]
    for t in ISOCHRONE_TIME_FACTORS:
        frame = frames[int(np.argmin(abs(tv - t)))]
        t_frame = float(frame.time * cv / HEIGHT**2)
        # The pressure increment is averaged over each cell: the pressure is the cell's (as in a
        # constant-pressure element), compared with u at the centre of the particle's cell.
        centre = (np.floor(frame.x[:, 1] / h) + 0.5) * h
        depth = (HEIGHT - centre) / HEIGHT
        e = float(np.max(np.abs(frame.pore_pressure / u0 - exact.pressure(depth, t_frame))))
        out[f"isochrone_error_{t:g}"] = e
        worst = max(worst, e)
    out["isochrone_error"] = worst
    out["cell_size"] = HEIGHT / run.params["cells"]
    return out


def _centre_checks(r: dict[str, Any], what: str, error_key: str, tolerance: float) -> list[dict[str, Any]]:
    """The two checks of a centre-pressure run: ``what`` (within ``tolerance`` p₀ from a stated
    time on) and the rise above p₀."""
    e = r.get(error_key)
    peak = r.get("peak")
    return [{"name": f"{r['run']}: {what}", "passed": e is not None and e <= tolerance,
             "detail": f"max |Δp|/p₀ = {fmt(e, '.4f')}"},
            {"name": f"{r['run']}: the centre's pressure rises above p₀ (Mandel–Cryer effect)",
             "passed": peak is not None and peak > 1.0,
             "detail": f"peak p/p₀ = {fmt(peak, '.4f')} (closed form {fmt(r.get('peak_exact'), '.4f')})"}]


def _mesh_check(name: str, group: list[dict[str, Any]], error_key: str, size: str) -> list[dict[str, Any]]:
    """``name``: the error of the finest run of ``group`` below the coarsest's (none without two
    runs with errors)."""
    group = sorted(group, key=lambda r: r["cells"])
    errors = [r.get(error_key) for r in group]
    if len(group) < 2 or None in errors:
        return []
    return [{"name": name, "passed": errors[-1] < errors[0],
             "detail": ", ".join(f"{size} = {r['cells']}: {e:.4f}" for r, e in zip(group, errors))}]


def evaluate_checks(results: list[dict[str, Any]], quick: bool = False) -> list[dict[str, Any]]:
    checks: list[dict[str, Any]] = []
    for r in results:
        if r.get("kind") == "mandel":
            checks += _centre_checks(r, f"Mandel's centre pressure within {MANDEL_TOLERANCE} p₀ from c t/a² = "
                                        f"{MANDEL_FROM_TIME_FACTOR:g}", "mandel_error", MANDEL_TOLERANCE)
            e = r.get("field_error")
            checks.append({"name": f"{r['run']}: the pressure field within {MANDEL_TOLERANCE} p₀ in every cell "
                                   f"from c t/a² = {MANDEL_FROM_TIME_FACTOR:g} (each output frame)",
                           "passed": e is not None and e <= MANDEL_TOLERANCE,
                           "detail": f"max |⟨p⟩_cell − p_exact|/p₀ = {fmt(e, '.4f')}"})
            e = r.get("column_spread")
            checks.append({"name": f"{r['run']}: no checkerboard: the cell pressures down a column of cells "
                                   f"within {CHECKERBOARD_TOLERANCE} p₀ of each other",
                           "passed": e is not None and e <= CHECKERBOARD_TOLERANCE,
                           "detail": f"largest spread = {fmt(e, '.4f')} p₀"})
            continue
        if r.get("kind") == "radial":
            checks += _centre_checks(r, f"{RADIAL_TITLES.get(r.get('shape'), 'radial')}, centre pressure within "
                                        f"{RADIAL_TOLERANCE} p₀ from c t/R² = {RADIAL_FROM_TIME_FACTOR:g}",
                                     "centre_error", RADIAL_TOLERANCE)
            continue
        if r.get("kind") == "undrained":
            e = r.get("undrained_error")
            checks.append({"name": f"{r['run']}: time-averaged ⟨p⟩/u₀ within {UNDRAINED_TOLERANCE:.0%}",
                           "passed": e is not None and e <= UNDRAINED_TOLERANCE,
                           "detail": f"⟨p⟩/u₀ = {fmt(r.get('undrained_ratio'), '.4f')}"})
            continue
        e = r.get("degree_error")
        checks.append({"name": f"{r['run']}: U within {DEGREE_TOLERANCE} at every T_v",
                       "passed": e is not None and e <= DEGREE_TOLERANCE, "detail": f"max |ΔU| = {fmt(e, '.4f')}"})
        e = r.get("isochrone_error")
        checks.append({"name": f"{r['run']}: isochrones within {ISOCHRONE_TOLERANCE} u₀",
                       "passed": e is not None and e <= ISOCHRONE_TOLERANCE,
                       "detail": f"max |Δu|/u₀ = {fmt(e, '.4f')}"})
    if not quick:
        mandel_runs = [r for r in results if r.get("kind") == "mandel"]
        checks += _mesh_check("Mandel: the error shrinks with the mesh", mandel_runs, "mandel_error", "a/h")
        checks += _mesh_check("Mandel: the pressure field's error shrinks with the mesh", mandel_runs, "field_error",
                              "a/h")
        for shape in RADIAL_SHAPES:
            checks += _mesh_check(f"{RADIAL_TITLES[shape]}: the error shrinks with the mesh",
                                  [r for r in results if r.get("kind") == "radial" and r.get("shape") == shape],
                                  "centre_error", "R/h")
        for f in FORMULATIONS:
            checks += _mesh_check(f"{f}: the U error shrinks with the mesh",
                                  [r for r in results if r.get("formulation") == f and r.get("kind") == "consolidation"],
                                  "degree_error", "H/h")
    return checks


def results_table(results: list[dict[str, Any]]) -> str:
    head = "| run | H/h | " + " | ".join(f"U({t:g})" for t in DEGREE_TIME_FACTORS) + " | max ΔU | isochrones max Δu/u₀ |"
    rows = [head, "|" + "---|" * (len(DEGREE_TIME_FACTORS) + 4)]
    exact_row = "| Terzaghi | | " + " | ".join(f"{exact.degree(t):.4f}" for t in DEGREE_TIME_FACTORS) + " | | |"
    rows.append(exact_row)
    for r in results:
        if r.get("kind") != "consolidation":
            continue
        cells = " | ".join(fmt(r.get(f"U_{t:g}"), ".4f") for t in DEGREE_TIME_FACTORS)
        rows.append(f"| {r['run']} | {r['cells']} | {cells} | {fmt(r.get('degree_error'), '.4f')} | "
                    f"{fmt(r.get('isochrone_error'), '.4f')} |")
    mandel_rows = [r for r in results if r.get("kind") == "mandel"]
    if mandel_rows:
        rows += ["", "| Mandel run | a/h | max \\|Δp\\|/p₀ (c t/a² ≥ " + f"{MANDEL_FROM_TIME_FACTOR:g}) | peak p/p₀ | "
                 "closed-form peak | T at peak | field: max \\|Δ⟨p⟩_cell\\|/p₀ | column spread/p₀ |",
                 "|---|---|---|---|---|---|---|---|"]
        rows += [f"| {r['run']} | {r['cells']} | {fmt(r.get('mandel_error'), '.4f')} | {fmt(r.get('peak'), '.4f')} | "
                 f"{fmt(r.get('peak_exact'), '.4f')} | {fmt(r.get('peak_time_factor'), '.3f')} | "
                 f"{fmt(r.get('field_error'), '.4f')} | {fmt(r.get('column_spread'), '.4f')} |" for r in mandel_rows]
    radial_rows = [r for r in results if r.get("kind") == "radial"]
    if radial_rows:
        rows += ["", "| radial run | body | R/h | max \\|Δp\\|/p₀ (c t/R² ≥ " + f"{RADIAL_FROM_TIME_FACTOR:g}) | "
                 "peak p/p₀ | closed-form peak | T at peak |", "|---|---|---|---|---|---|---|"]
        rows += [f"| {r['run']} | {RADIAL_TITLES.get(r.get('shape'), DASH)} | {r['cells']} | "
                 f"{fmt(r.get('centre_error'), '.4f')} | {fmt(r.get('peak'), '.4f')} | "
                 f"{fmt(r.get('peak_exact'), '.4f')} | {fmt(r.get('peak_time_factor'), '.3f')} |" for r in radial_rows]
    for r in results:
        if r.get("kind") == "undrained":
            rows.append(f"\nUndrained (k = {UNDRAINED_CONDUCTIVITY:g} m/s, K_w = {UNDRAINED_WATER_BULK_MODULUS:g} Pa): "
                        f"time-averaged ⟨p⟩/u₀ = {fmt(r.get('undrained_ratio'), '.4f')}, "
                        f"u₀/q = {fmt((r.get('u0') or math.nan) / LOAD, '.4f')}")
    return "\n".join(rows)


def plot(results: list[dict[str, Any]], base: Path, path: Path) -> bool:
    """U against T_v and the isochrones of the finest runs against the closed form."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np

        from ...run.output import load_run
    except ImportError:  # pragma: no cover
        return False
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(15, 4))
    tv = np.linspace(1e-4, END_TIME_FACTOR, 400)
    a.plot(tv, [exact.degree(t) for t in tv], "k-", label="Terzaghi")
    z = np.linspace(0, 1, 200)
    for t in ISOCHRONE_TIME_FACTORS:
        b.plot(exact.pressure(z, t), z, "k-", lw=1)
    for r in results:
        if r.get("kind") != "consolidation" or r.get("status") != "completed":
            continue
        frames = load_run(base / r["run_dir"]).frames
        u0 = r["u0"]
        cv = consolidation_coefficient("consolidation", r["conductivity"])
        t = np.array([f.time for f in frames]) * cv / HEIGHT**2
        a.plot(t, [1 - _mean_pressure(f) / u0 for f in frames], "--", label=r["run"])
        for tt in ISOCHRONE_TIME_FACTORS:
            f = frames[int(np.argmin(abs(t - tt)))]
            b.plot(f.pore_pressure / u0, (HEIGHT - f.X0[:, 1]) / HEIGHT, ".", ms=2)
    a.set_xlabel("T_v")
    a.set_ylabel("U")
    a.legend(fontsize=7)
    b.set_xlabel("u/u₀")
    b.set_ylabel("z/H (depth below the drained top)")
    b.invert_yaxis()
    _plot_mandel(c, results, base)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return True


def _plot_mandel(ax: Any, results: list[dict[str, Any]], base: Path) -> None:
    """The centre's pressure of the Mandel runs against the closed form."""
    import numpy as np

    from ...run.output import load_run
    from . import mandel

    material = mandel_material(MANDEL_CONDUCTIVITY)
    t = np.linspace(1e-4, MANDEL_END_TIME_FACTOR, 400)
    ax.plot(t, mandel.centre_pressure(t, material), "k-", label="Mandel (closed form)")
    for r in results:
        if r.get("kind") != "mandel" or r.get("status") != "completed":
            continue
        history = load_run(base / r["run_dir"]).history
        tr = np.asarray(history["time"]) * material.consolidation_coefficient / MANDEL_HALF_WIDTH**2
        ax.plot(tr, np.asarray(history["centre.pore_pressure"]) / r["p0"], "--", label=r["run"])
    ax.axvline(MANDEL_FROM_TIME_FACTOR, color="0.7", lw=0.8)
    ax.set_xlabel("c t / a²")
    ax.set_ylabel("p(0, t) / p₀")
    ax.set_ylim(0.0, 1.4)
    ax.legend(fontsize=7)


def plot_radial(results: list[dict[str, Any]], base: Path, path: Path) -> bool:
    """The centre's pressure of the Cryer and de Leeuw runs against the closed forms, one panel
    each; False without matplotlib or without such runs."""
    runs = [r for r in results if r.get("kind") == "radial" and r.get("status") == "completed"]
    if not runs:
        return False
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np

        from ...run.output import load_run
        from . import radial
    except ImportError:  # pragma: no cover
        return False
    material = mandel_material(RADIAL_CONDUCTIVITY)
    fig, axes = plt.subplots(1, len(RADIAL_SHAPES), figsize=(10, 4))
    t = np.linspace(1e-4, RADIAL_END_TIME_FACTOR, 400)
    for ax, shape in zip(axes, RADIAL_SHAPES):
        ax.plot(t, radial.centre_pressure(shape, t, material), "k-", label="closed form")
        for r in runs:
            if r.get("shape") != shape:
                continue
            history = load_run(base / r["run_dir"]).history
            tr = np.asarray(history["time"]) * material.consolidation_coefficient / RADIAL_RADIUS**2
            ax.plot(tr, np.asarray(history["centre.pore_pressure"]) / r["p0"], "--", label=r["run"])
        ax.axvline(RADIAL_FROM_TIME_FACTOR, color="0.7", lw=0.8)
        ax.set_title(RADIAL_TITLES[shape])
        ax.set_xlabel("c t / R²")
        ax.set_ylabel("p(0, t) / p₀")
        ax.set_ylim(0.0, 1.7)
        ax.legend(fontsize=7)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return True


def _cell(text: str) -> str:
    """A Markdown table cell: the bars of "|Δp|" escaped, which would otherwise end the cell."""
    return str(text).replace("|", "\\|")


class Consolidation:
    """Consolidation of saturated soil (two-phase v–w): Terzaghi's column in plane strain and
    axisymmetric, Mandel's specimen, Cryer's sphere and de Leeuw's cylinder."""

    name = "consolidation"
    kind = "verification"
    title = "Consolidation of saturated soil: Terzaghi, Mandel, Cryer, de Leeuw (two-phase)"
    default = False

    def add_options(self, parser: argparse.ArgumentParser) -> None:
        pass

    def runs(self, options: argparse.Namespace) -> list[RunSpec]:
        return run_specs(bool(getattr(options, "quick", False)))

    def scenario(self, run: RunSpec) -> Any:
        p = run.params
        if p["kind"] == "mandel":
            end = QUICK_MANDEL_END_TIME_FACTOR if p.get("quick") else MANDEL_END_TIME_FACTOR
            return mandel_scenario(p["cells"], p["conductivity"], end)
        if p["kind"] == "radial":
            end = QUICK_RADIAL_END_TIME_FACTOR if p.get("quick") else RADIAL_END_TIME_FACTOR
            return radial_scenario(p["shape"], p["cells"], p["conductivity"], end)
        return column_scenario(p["formulation"], p["cells"], p["kind"], p.get("conductivity", CONDUCTIVITY))

    def reference(self, run: RunSpec) -> dict[str, Any]:
        if run.params["kind"] == "undrained":
            return {"undrained_ratio": 1.0}
        if run.params["kind"] in ("mandel", "radial"):
            return {}
        return {f"U_{t:g}": exact.degree(t) for t in DEGREE_TIME_FACTORS}

    def metrics(self, run: RunSpec, run_dir: Path) -> dict[str, Any]:
        return run_metrics(run, run_dir)

    def cost(self, run: RunSpec) -> float:
        p = run.params
        if p["kind"] == "mandel":
            return float(p["cells"] ** 3 / p["conductivity"])
        if p["kind"] == "radial":
            # Particles × steps: the sphere's quarter disc has ~π/4 (R/h)² cells, the slab 2 R/h.
            cells = p["cells"] ** 3 if p["shape"] == "sphere" else 2 * p["cells"] ** 2
            return float(cells / p["conductivity"])
        return float(p["cells"] ** 2 / p["conductivity"]) if p["kind"] == "consolidation" else 1.0

    def progress(self, record: dict[str, Any]) -> str:
        if record.get("status") != "completed":
            return f"{record.get('status')}: {record.get('message', '')}"
        if record.get("kind") == "undrained":
            return f"⟨p⟩/u₀ {fmt(record.get('undrained_ratio'), '.4f')}"
        if record.get("kind") == "radial":
            return (f"{RADIAL_TITLES.get(record.get('shape'), 'radial')}: max |Δp|/p₀ "
                    f"{fmt(record.get('centre_error'), '.4f')}, peak p/p₀ {fmt(record.get('peak'), '.4f')} "
                    f"(exact {fmt(record.get('peak_exact'), '.4f')})")
        if record.get("kind") == "mandel":
            return (f"Mandel: max |Δp|/p₀ {fmt(record.get('mandel_error'), '.4f')}, peak p/p₀ "
                    f"{fmt(record.get('peak'), '.4f')} (exact {fmt(record.get('peak_exact'), '.4f')})")
        return (f"max |ΔU| {fmt(record.get('degree_error'), '.4f')}, isochrones "
                f"{fmt(record.get('isochrone_error'), '.4f')}")

    def checks(self, results: list[dict[str, Any]]) -> list[dict[str, Any]]:
        quick = bool(getattr(results, "context", {}).get("quick", False))
        return evaluate_checks(results, quick=quick)

    def document(self, results: list[dict[str, Any]], options: argparse.Namespace) -> dict[str, Any]:
        return {"height": HEIGHT, "load": LOAD, "skeleton": SKELETON, "porosity": POROSITY,
                "water_density": WATER_DENSITY, "water_bulk_modulus": WATER_BULK_MODULUS,
                "hydraulic_conductivity": CONDUCTIVITY, "consolidation_coefficient": consolidation_coefficient(
                    "consolidation"), "degree_time_factors": DEGREE_TIME_FACTORS,
                "isochrone_time_factors": ISOCHRONE_TIME_FACTORS,
                "radial": {"radius": RADIAL_RADIUS, "hydraulic_conductivity": RADIAL_CONDUCTIVITY,
                           "from_time_factor": RADIAL_FROM_TIME_FACTOR, "cylinder_cells_high": CYLINDER_CELLS_HIGH,
                           "sphere_chords": SPHERE_CHORDS},
                "tolerances": {"degree": DEGREE_TOLERANCE, "isochrone": ISOCHRONE_TOLERANCE,
                               "undrained": UNDRAINED_TOLERANCE, "mandel": MANDEL_TOLERANCE,
                               "radial": RADIAL_TOLERANCE}}

    def console(self, results: list[dict[str, Any]], checks: list[dict[str, Any]]) -> str:
        return results_table(results)

    def report(self, results: list[dict[str, Any]], out: Path) -> str:
        context = getattr(results, "context", {})
        checks = context.get("checks") or evaluate_checks(results, bool(context.get("quick")))
        lines = [f"## {self.title}", "",
                 "Terzaghi's layer (H = 1 m, drained top, impermeable base, q = 10 kPa) as a one-cell column, "
                 "against the series solution with compressible water "
                 f"(k = {CONDUCTIVITY:g} m/s, c_v = {consolidation_coefficient('consolidation'):.4g} m²/s; "
                 f"--quick: k = {QUICK_CONDUCTIVITY:g} m/s). U = 1 − ⟨p⟩/u₀; the isochrones are compared at the "
                 "centres of the cells (the pressure is the cell's).", "",
                 results_table(list(results)), "", "| check | passed | detail |", "|---|---|---|"]
        lines += [f"| {_cell(c['name'])} | {'yes' if c['passed'] else 'NO'} | {_cell(c.get('detail', DASH))} |"
                  for c in checks]
        figure = Path(out) / "figures" / "consolidation.png"
        if context.get("figures", True) and plot(list(results), Path(out), figure):
            lines += ["", f"![U against T_v and the isochrones]({figure.relative_to(Path(out))})"]
        figure = Path(out) / "figures" / "consolidation_radial.png"
        if context.get("figures", True) and plot_radial(list(results), Path(out), figure):
            lines += ["", "Cryer's sphere and de Leeuw's cylinder (axisymmetric, drained surface, from their "
                      "undrained state): the centre's pore pressure against the closed forms "
                      "(docs/physics.md §10).", "",
                      f"![the centre's pressure of Cryer's sphere and de Leeuw's cylinder]"
                      f"({figure.relative_to(Path(out))})"]
        return "\n".join(lines) + "\n"


CASE = register(Consolidation())
