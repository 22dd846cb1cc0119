"""The ``taylor_bar`` verification case: a copper bar fired at a rigid wall, J2 plasticity at
50 % compressive strain (Sulsky & Schreyer 1996's axisymmetric application; docs/physics.md §7,
docs/verification.md "Taylor bar").

Scenario (:func:`taylor_scenario`): the bar (radius R0, length L0) stands on the axis on the
wall z = 0 at t = 0 and moves down at V0; the wall is a frictionless roller (v_z = 0 on the
nodes of z = 0 and below, sliding free) — the rigid frictionless wall of Simo (1992), whose
impact-face nodes stay on the wall — two cells above the grid's base; gravity 0; pure FLIP (flip_fraction = 1: a PIC share dissipates kinetic energy
every step, which the energy balance would count as a loss); MUSL; 2 × 2 particles per cell.

Runs (``axmpm verify --case taylor_bar``):

* Simo (1992) copper set — L0 = 32.4 mm, R0 = 3.2 mm, ρ = 8930 kg/m³, E = 117 GPa, ν = 0.35,
  σ_y = 0.4 GPa, H = 0.1 GPa, V0 = 227 m/s, to 80 µs — axisymmetric, the four schemes at
  R0/h = 8, 16, 24 (L0 must lie on a grid line: L0/h = 10.125 R0/h, so R0/h is a multiple of 8);
* the plane-strain counterpart (the bar drawn as a strip of half-width R0) with cpGIMP at the
  finest mesh;
* Wilkins & Guinan (1973) copper geometry (L0 = 23.47 mm, D0 = 7.62 mm, 210 m/s; R0/h = 25,
  L0 = 154 cells = 23.4696 mm) with the same material set, cpGIMP, to 80 µs.

``--quick``: cpGIMP at R0/h = 8 only (the ``make test`` variant).

Metrics from the last frame (:func:`bar_metrics`); a particle's domain is taken as its
deformed square F·[−l0, l0]² (l0 = h/4, the initial half-width), whose half-extents are
hr = l0(|F11| + |F12|) in r and hz = l0(|F21| + |F22|) in z:

* ``final_length`` L_f = max over particles of z_p + hz_p (the wall is z = 0);
* ``impact_radius`` R_f = max of r_p + hr_p over the particles whose centre lies within one cell
  of the wall (z_p ≤ h);
* ``max_plastic_strain`` = max ε̄p over the particles whose centre lies within one cell of the
  axis (r_p ≤ h) (``max_plastic_strain_anywhere`` over all particles);
* ``energy_error`` = (KE0 − (KE + E_el + W_p))/KE0, with E_el = Σ V_p (s:s/(4G) + p²/(2K)) from
  the stresses and W_p = Σ V0_p w_p from the model's ``plastic_work`` (per reference volume),
  totals × 2π in axisymmetry (per metre in plane strain).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

from ..errors import RunError
from ..plotting import pyplot, save_figure, scheme_style
from ..report import DASH, fmt, pct
from ..run.output import load_run
from ..scenario import Scenario
from . import RunSpec, register

SCHEMES: tuple[str, ...] = ("linear", "ugimp", "cpgimp", "cpdi2")
#: Cells per initial radius R0/h of the Simo bar (multiples of 8: L0 = 10.125 R0 on a grid line).
MESHES: tuple[int, ...] = (8, 16, 24)
QUICK_MESH = 8
QUICK_SCHEME = "cpgimp"
#: The schemes the enforced targets apply to (at the finest mesh).
TARGET_SCHEMES: tuple[str, ...] = ("cpgimp", "cpdi2")
PARTICLES_PER_CELL = 2
#: Cells of grid below the wall z = 0.
WALL_CELLS = 2
OUTPUT_INTERVAL = 20e-6  # s

#: Simo (1992) copper (docs/physics.md §7).
COPPER: dict[str, float] = {
    "density": 8930.0,
    "youngs_modulus": 117e9,
    "poisson_ratio": 0.35,
    "yield_stress": 0.4e9,
    "hardening_modulus": 0.1e9,
}

#: geometry key → (title, L0 m, R0 m, V0 m/s, end time s)
GEOMETRIES: dict[str, tuple[str, float, float, float, float]] = {
    "simo1992": ("Simo (1992) copper bar", 32.4e-3, 3.2e-3, 227.0, 80e-6),
    "wilkins_guinan1973": ("Wilkins & Guinan (1973) copper experiment", 23.47e-3, 3.81e-3, 210.0, 80e-6),
}
#: R0/h of the Wilkins & Guinan run: L0/R0 = 6.160 ≈ 154/25, so L0 = 154 cells = 23.4696 mm.
WG_MESH = 25
WG_CELLS_ALONG = 154

#: References and their confidence (docs/verification.md "Taylor bar").
REFERENCES: dict[str, dict[str, Any]] = {
    "simo1992": {
        "impact_radius": 7.12e-3,
        "final_length": 21.45e-3,
        "notes": {
            "impact_radius": "7.12 mm Simo (1992); 7.11 mm Zienkiewicz et al. (1998); 7.22 mm converged Q1/P0 "
                             "(Foulk et al. 2021) — as quoted by the Carina.jl Taylor benchmark notes "
                             "(Cthonios/Carina.jl benchmark/tet15-p1/taylor/README.md), medium confidence",
            "final_length": "no literature value found; 21.42–21.48 mm are the final lengths of the FE runs in "
                            "those notes (TET15-P1 21.42, composite tetrahedron 21.43–21.48), unconfirmed; "
                            "21.45 mm is their mid-point",
        },
    },
    "wilkins_guinan1973": {
        "impact_radius": 8.29e-3,
        "final_length": 15.09e-3,
        "notes": {
            "final_length": "L_f/L0 = 0.643 at 210 m/s from Banerjee's compilation of Wilkins & Guinan's copper "
                            "data (bbanerjee/HighRateExptData TaylorData/DAT/CuWilkins.dat); its digitised profile "
                            "gives 15.03 mm; low confidence (not read from the 1973 paper)",
            "impact_radius": "foot diameter 16.58 mm in the same compilation (digitised profile 8.29 mm); "
                             "low confidence",
            "material": "the Simo (1992) copper set, not a fit to Wilkins & Guinan's copper: the comparison "
                        "shows what that idealisation gives, it does not validate it",
        },
    },
}

#: Targets at the finest mesh for :data:`TARGET_SCHEMES`, and the energy balance. R_f (medium
#: confidence) is enforced; L_f's reference is unconfirmed (other codes' runs), so its
#: comparison is reported as an aim (required = False), not enforced.
IMPACT_RADIUS_TOLERANCE = 0.03
FINAL_LENGTH_TOLERANCE = 0.015
ENERGY_TOLERANCE = 0.01
#: Quick variant (coarse mesh): L_f within 5 % of the reference.
QUICK_LENGTH_TOLERANCE = 0.05

FIGURES = "figures"


# --------------------------------------------------------------------------- runs and scenarios


def run_name(scheme: str, cells_per_radius: int, formulation: str = "axisymmetric",
             geometry: str = "simo1992") -> str:
    name = f"{scheme}_n{cells_per_radius:02d}"
    if formulation != "axisymmetric":
        name += f"_{formulation}"
    if geometry != "simo1992":
        name = f"{geometry}_{name}"
    return name


def run_spec(scheme: str, cells_per_radius: int, formulation: str = "axisymmetric",
             geometry: str = "simo1992") -> RunSpec:
    return RunSpec(run_name(scheme, cells_per_radius, formulation, geometry),
                   {"scheme": scheme, "formulation": formulation, "cells_per_radius": cells_per_radius,
                    "geometry": geometry})


def run_specs(quick: bool = False, schemes: tuple[str, ...] = SCHEMES,
              meshes: tuple[int, ...] = MESHES) -> list[RunSpec]:
    """The runs of the case (module doc)."""
    if quick:
        return [run_spec(QUICK_SCHEME, QUICK_MESH)]
    runs = [run_spec(s, n) for n in meshes for s in schemes]
    runs.append(run_spec("cpgimp", max(meshes), "plane_strain"))
    runs.append(run_spec("cpgimp", WG_MESH, geometry="wilkins_guinan1973"))
    return runs


def cells_along(geometry: str, cells_per_radius: int) -> int:
    """Cells along the bar, L0/h, which must be a whole number."""
    if geometry == "wilkins_guinan1973":
        if cells_per_radius != WG_MESH:
            raise ValueError(f"the Wilkins & Guinan bar is meshed with R0/h = {WG_MESH} only "
                             f"(got {cells_per_radius})")
        return WG_CELLS_ALONG
    _, length, radius, _, _ = GEOMETRIES[geometry]
    n = length / radius * cells_per_radius
    if abs(n - round(n)) > 1e-9:
        raise ValueError(f"R0/h = {cells_per_radius} puts L0 = {length * 1e3:g} mm off the grid "
                         f"(L0/h = {n:g}); use a multiple of 8")
    return int(round(n))


def taylor_scenario(scheme: str, cells_per_radius: int, formulation: str = "axisymmetric",
                    geometry: str = "simo1992", *, as_dict: bool = False) -> Any:
    """The scenario of one run (module doc): a :class:`~axmpm.scenario.Scenario`, or its plain
    dict (``as_dict``)."""
    _, length, radius, velocity, end_time = GEOMETRIES[geometry]
    h = radius / cells_per_radius
    n_along = cells_along(geometry, cells_per_radius)
    if geometry == "wilkins_guinan1973":
        length = n_along * h  # 23.4696 mm
    # Room for the mushroom (R_f ≈ 2.2 R0 axisymmetric; the strip spreads beyond 4 R0) and the
    # particle domains.
    widths = 3.0 if formulation == "axisymmetric" else 6.0
    n_across = int(math.ceil(widths * cells_per_radius))
    data = {
        "simulation": {
            "formulation": formulation,
            "shape_function": scheme,
            "end_time": end_time,
            "output_interval": OUTPUT_INTERVAL,
            "gravity": [0.0, 0.0],
            "flip_fraction": 1.0,
            "update_scheme": "musl",
        },
        # The wall z = 0 lies WALL_CELLS cells above the grid's base: a particle that a scheme's
        # interpolation pushes through the wall (uGIMP's fixed domains do) stays on the grid.
        "grid": {"origin": [0.0, -WALL_CELLS * h], "extent": [n_across * h, (n_along + 2 + WALL_CELLS) * h],
                 "cell_size": h},
        "materials": {"copper": {"model": "von_mises", **COPPER}},
        "bodies": [{
            "name": "bar",
            "material": "copper",
            "min": [0.0, 0.0],
            "max": [radius, length],
            "particles_per_cell": PARTICLES_PER_CELL,
            "velocity": [0.0, -velocity],
        }],
        # r = 0 (x = 0 in plane strain: the symmetry plane of the strip) is a roller.
        "boundaries": {"left": "roller", "bottom": "roller", "right": "free", "top": "free"},
        # The rigid frictionless wall: v_z = 0 on the nodes of z = 0 and below (bilateral, so the
        # impact face stays on the wall as in Simo 1992; docs/verification.md).
        "walls": [{"axis": "y", "position": 0.0, "material_side": "positive", "condition": "roller"}],
    }
    if as_dict:
        return data

    return Scenario.from_dict(data, source=f"taylor_bar {run_name(scheme, cells_per_radius, formulation, geometry)}")


# --------------------------------------------------------------------------- metrics


def _elastic_moduli() -> tuple[float, float]:
    e, nu = COPPER["youngs_modulus"], COPPER["poisson_ratio"]
    return e / (2.0 * (1.0 + nu)), e / (3.0 * (1.0 - 2.0 * nu))


def bar_metrics(frame: Any, cell_size: float, half_width: float, formulation: str,
                initial_speed: float, wall: float = 0.0, axis: float = 0.0) -> dict[str, Any]:
    """The figures of one frame (module doc). ``frame`` has the arrays of
    :class:`axmpm.output.FrameData` (x, v, stress, volume, volume0, mass, F, state, state_names)."""
    import numpy as np

    x, v, s, F = (np.asarray(a, dtype=float) for a in (frame.x, frame.v, frame.stress, frame.F))
    names = list(frame.state_names)
    state = np.asarray(frame.state, dtype=float).reshape(len(x), -1)
    plastic_strain = state[:, names.index("plastic_strain")]
    plastic_work = state[:, names.index("plastic_work")]
    volume, volume0, mass = (np.asarray(a, dtype=float) for a in (frame.volume, frame.volume0, frame.mass))
    h, l0 = cell_size, half_width
    hr = l0 * (np.abs(F[:, 0]) + np.abs(F[:, 1]))
    hz = l0 * (np.abs(F[:, 2]) + np.abs(F[:, 3]))
    near_wall = x[:, 1] - wall <= h
    near_axis = x[:, 0] - axis <= h
    total = 2.0 * math.pi if formulation == "axisymmetric" else 1.0
    g, k = _elastic_moduli()
    p = s[:, :3].mean(axis=1)
    dev = s[:, :3] - p[:, None]
    ss = (dev**2).sum(axis=1) + 2.0 * s[:, 3] ** 2
    kinetic0 = 0.5 * mass.sum() * initial_speed**2 * total
    kinetic = 0.5 * (mass * (v**2).sum(axis=1)).sum() * total
    elastic = (volume * (ss / (4.0 * g) + p**2 / (2.0 * k))).sum() * total
    plastic = (volume0 * plastic_work).sum() * total
    return {
        "time": float(frame.time),
        "final_length": float((x[:, 1] + hz).max() - wall),
        "impact_radius": float((x[near_wall, 0] + hr[near_wall]).max() - axis) if near_wall.any() else None,
        "max_plastic_strain": float(plastic_strain[near_axis].max()) if near_axis.any() else None,
        "max_plastic_strain_anywhere": float(plastic_strain.max()),
        "initial_kinetic_energy": float(kinetic0),
        "kinetic_energy": float(kinetic),
        "elastic_energy": float(elastic),
        "plastic_work": float(plastic),
        "energy_error": float((kinetic0 - kinetic - elastic - plastic) / kinetic0),
        "volume_ratio_mean": float((volume / volume0).mean()),
    }


def run_metrics(run_dir: Path) -> dict[str, Any]:
    """:func:`bar_metrics` of the last frame of a run folder (None values if it has no frame)."""
    run = load_run(run_dir)
    sc = run.scenario
    body = sc.bodies[0]
    h = sc.grid.cell_size
    try:
        frame = run.last
        frame.x  # noqa: B018 - loads the frame
    except Exception:  # noqa: BLE001 - a run without frames
        return {k: None for k in ("final_length", "impact_radius", "max_plastic_strain", "energy_error")}
    wall = sc.walls[0].position if sc.walls else sc.grid.origin[1]
    m = bar_metrics(frame, h, h / (2 * body.particles_per_cell), sc.simulation.formulation,
                    math.hypot(*body.velocity), wall=wall, axis=sc.grid.origin[0])
    m["cell_size"] = h
    m["particles"] = int(len(frame.x))
    return m


# --------------------------------------------------------------------------- checks


def _finest(results: list[dict[str, Any]], scheme: str) -> dict[str, Any] | None:
    group = [r for r in results if r.get("scheme") == scheme and r.get("formulation") == "axisymmetric"
             and r.get("geometry", "simo1992") == "simo1992"]
    return max(group, key=lambda r: r["cells_per_radius"]) if group else None


def _within(value: Any, reference: float, tolerance: float) -> tuple[bool, float | None]:
    if not isinstance(value, (int, float)) or value is None or not math.isfinite(value):
        return False, None
    err = (value - reference) / reference
    return abs(err) <= tolerance, err


def evaluate_checks(results: list[dict[str, Any]], quick: bool = False) -> list[dict[str, Any]]:
    """The enforced criteria, from the records alone (testable on fabricated records).

    Full run: at the finest Simo mesh, cpGIMP and CPDI2 have R_f within 3 % of 7.12 mm
    (enforced) and L_f within 1.5 % of 21.45 mm (an aim, reported: the L_f reference is
    unconfirmed); every cpGIMP and CPDI2 run (every mesh, the strip, Wilkins & Guinan) balances
    its energy within 1 %. Original MPM and uGIMP are reported, not enforced (docs/verification.md
    says why they miss). Quick run: the energy balance and L_f within a 5 % sanity band."""
    ref = REFERENCES["simo1992"]
    checks: list[dict[str, Any]] = []
    for r in results:
        if r.get("scheme") not in TARGET_SCHEMES:
            continue
        ok = r.get("status") == "completed"
        e = r.get("energy_error")
        passed = ok and isinstance(e, (int, float)) and abs(e) <= ENERGY_TOLERANCE
        checks.append({"name": f"{r['name']}: energy balance within {ENERGY_TOLERANCE:.0%}",
                       "passed": bool(passed), "measured": e, "limit": ENERGY_TOLERANCE,
                       "detail": f"energy error {pct(e, 2)}" if ok else f"{r.get('status')}: {r.get('message', '')}"})
    if quick:
        for r in results:
            passed, err = _within(r.get("final_length"), ref["final_length"], QUICK_LENGTH_TOLERANCE)
            checks.append({"name": f"{r['name']}: L_f within {QUICK_LENGTH_TOLERANCE:.0%} of "
                                   f"{ref['final_length'] * 1e3:g} mm",
                           "passed": passed and r.get("status") == "completed", "measured": err,
                           "limit": QUICK_LENGTH_TOLERANCE,
                           "detail": f"L_f = {fmt(_mm(r.get('final_length')), '.3f')} mm ({pct(err, 2)})"})
        return checks
    for scheme in TARGET_SCHEMES:
        r = _finest(results, scheme)
        if r is None:
            continue
        for key, label, tol, required in (("impact_radius", "R_f", IMPACT_RADIUS_TOLERANCE, True),
                                          ("final_length", "L_f", FINAL_LENGTH_TOLERANCE, False)):
            passed, err = _within(r.get(key), ref[key], tol)
            unconfirmed = "" if required else " (unconfirmed reference: reported, not enforced)"
            checks.append({"name": f"{r['name']}: {label} within {tol:.1%} of {ref[key] * 1e3:g} mm{unconfirmed}",
                           "passed": passed and r.get("status") == "completed", "measured": err, "limit": tol,
                           "required": required,
                           "detail": f"{label} = {fmt(_mm(r.get(key)), '.3f')} mm ({pct(err, 2)})"})
    return checks


def _mm(value: Any) -> float | None:
    return None if not isinstance(value, (int, float)) else 1e3 * value


# --------------------------------------------------------------------------- report


def results_table(results: list[dict[str, Any]]) -> str:
    lines = ["| run | scheme | formulation | R0/h | R_f mm | vs ref | L_f mm | vs ref | max ε̄p at axis | "
             "energy error | wall s | status |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        rel = r.get("relative_error") or {}
        lines.append(
            f"| {r['name']} | {r['scheme']} | {r['formulation']} | {r['cells_per_radius']} | "
            f"{fmt(_mm(r.get('impact_radius')), '.3f')} | {pct(rel.get('impact_radius'), 1)} | "
            f"{fmt(_mm(r.get('final_length')), '.3f')} | {pct(rel.get('final_length'), 2)} | "
            f"{fmt(r.get('max_plastic_strain'), '.2f')} | {pct(r.get('energy_error'), 2)} | "
            f"{fmt(r.get('wall_seconds'), '.0f')} | {r.get('status', DASH)} |")
    return "\n".join(lines)


def _last_frame(base: Path, record: dict[str, Any]) -> Any:
    return load_run(base / record["run_dir"])


def _profile(run: Any) -> tuple[Any, Any]:
    """Outer profile of the final shape: per band of one cell in z, the largest r_p + hr_p."""
    import numpy as np

    frame = run.last
    h = run.scenario.grid.cell_size
    l0 = h / (2 * run.scenario.bodies[0].particles_per_cell)
    x, F = np.asarray(frame.x), np.asarray(frame.F)
    hr = l0 * (np.abs(F[:, 0]) + np.abs(F[:, 1]))
    hz = l0 * (np.abs(F[:, 2]) + np.abs(F[:, 3]))
    top = (x[:, 1] + hz).max()
    bands = np.floor(x[:, 1] / h).astype(int)
    zs, rs = [], []
    for b in range(bands.max() + 1):
        sel = bands == b
        if sel.any():
            zs.append((b + 0.5) * h)
            rs.append((x[sel, 0] + hr[sel]).max())
    zs = [0.0] + zs + [top, top]
    rs = [rs[0]] + rs + [rs[-1], 0.0]
    return np.array(rs), np.array(zs)


def plot_shapes(results: list[dict[str, Any]], base: Path, path: Path) -> bool:
    """Final outer profiles of all schemes at the finest Simo mesh over each other (mm), the
    reference R_f and L_f marked."""
    finest = [r for r in (_finest(results, s) for s in SCHEMES) if r is not None and r.get("status") == "completed"]
    if not finest:
        return False
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 7))
    _, length, radius, _, _ = GEOMETRIES["simo1992"]
    ax.plot([0, radius * 1e3, radius * 1e3, 0], [0, 0, length * 1e3, length * 1e3], color="0.6", lw=0.8,
            ls=":", label="initial bar")
    dashes = {"linear": "-", "ugimp": "-", "cpgimp": "--", "cpdi2": ":"}  # cpGIMP and CPDI2 nearly coincide
    for r in finest:
        rs, zs = _profile(_last_frame(base, r))
        st = scheme_style(r["scheme"])
        ax.plot(rs * 1e3, zs * 1e3, color=st["color"], lw=1.4, ls=dashes.get(r["scheme"], "-"),
                label=f"{st['label']} (R0/h = {r['cells_per_radius']})")
    ref = REFERENCES["simo1992"]
    ax.axvline(ref["impact_radius"] * 1e3, color="k", ls="--", lw=0.8, label="R_f = 7.12 mm (Simo 1992)")
    ax.axhline(ref["final_length"] * 1e3, color="k", ls="-.", lw=0.8, label="L_f ≈ 21.45 mm (unconfirmed)")
    ax.set_xlabel("r (mm)")
    ax.set_ylabel("z (mm)")
    ax.set_aspect("equal")
    ax.set_xlim(0, 9)
    ax.set_ylim(0, length * 1e3 + 1)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    ax.set_title("Taylor bar at 80 µs: outer profile (max r + half-width per cell band)", fontsize=8)
    save_figure(fig, path)
    return True


def plot_plastic_strain(results: list[dict[str, Any]], base: Path, path: Path) -> bool:
    """ε̄p on the particles of the finest cpGIMP and CPDI2 runs and of the plane-strain strip."""
    import numpy as np

    panels = [r for r in (_finest(results, "cpgimp"), _finest(results, "cpdi2")) if r is not None]
    panels += [r for r in results if r.get("formulation") == "plane_strain"]
    panels = [r for r in panels if r.get("status") == "completed"]
    if not panels:
        return False
    plt = pyplot()
    widths = [15.0 if r["formulation"] == "plane_strain" else 9.0 for r in panels]
    fig, axes = plt.subplots(1, len(panels), figsize=(0.45 * sum(widths) + 1.5, 6.5), squeeze=False,
                             gridspec_kw={"width_ratios": widths})
    def plastic_strain(frame: Any) -> Any:
        return np.asarray(frame.state)[:, list(frame.state_names).index("plastic_strain")]

    # Colour scale to the 99.5th percentile: a few stray particles at the foot's edge reach far
    # higher values than the bulk.
    vmax = max(float(np.percentile(plastic_strain(_last_frame(base, r).last), 99.5)) for r in panels)
    image = None
    for ax, r in zip(axes[0], panels):
        run = _last_frame(base, r)
        frame = run.last
        ep = plastic_strain(frame)
        image = ax.scatter(frame.x[:, 0] * 1e3, frame.x[:, 1] * 1e3, c=ep, s=1.5, cmap="viridis", vmin=0,
                           vmax=vmax, linewidths=0)
        ax.set_aspect("equal")
        ax.set_xlim(0, 15 if r["formulation"] == "plane_strain" else 9)
        ax.set_ylim(0, 24)
        ax.set_xlabel("r (mm)" if r["formulation"] == "axisymmetric" else "x (mm)")
        if ax is axes[0][0]:
            ax.set_ylabel("z (mm)")
        ax.set_title(f"{r['scheme']}, {r['formulation'].replace('_', ' ')}, R0/h = {r['cells_per_radius']}",
                     fontsize=8)
    fig.colorbar(image, ax=axes[0].tolist(), shrink=0.7, label="equivalent plastic strain ε̄p")
    save_figure(fig, path)
    return True


def plot_convergence(results: list[dict[str, Any]], path: Path) -> bool:
    """R_f and L_f against R0/h per scheme, with the reference and the target bands."""
    axi = [r for r in results if r.get("formulation") == "axisymmetric" and r.get("geometry") == "simo1992"
           and r.get("status") == "completed"]
    if not axi:
        return False
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    ref = REFERENCES["simo1992"]
    for ax, key, tol, label in ((a1, "impact_radius", IMPACT_RADIUS_TOLERANCE, "R_f (mm)"),
                                (a2, "final_length", FINAL_LENGTH_TOLERANCE, "L_f (mm)")):
        for scheme in SCHEMES:
            group = sorted((r for r in axi if r["scheme"] == scheme and r.get(key) is not None),
                           key=lambda r: r["cells_per_radius"])
            if group:
                st = scheme_style(scheme)
                ax.plot([r["cells_per_radius"] for r in group], [r[key] * 1e3 for r in group], marker=st["marker"],
                        color=st["color"], label=st["label"])
        ax.axhline(ref[key] * 1e3, color="k", ls="--", lw=0.8, label="reference")
        ax.axhspan(ref[key] * 1e3 * (1 - tol), ref[key] * 1e3 * (1 + tol), color="0.85", zorder=0,
                   label=f"target ±{tol:.1%}")
        ax.set_xlabel("cells per initial radius R0/h")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    a1.set_title("impact-face radius (reference 7.12 mm, Simo 1992)", fontsize=9)
    a2.set_title("final length (reference 21.45 mm, unconfirmed)", fontsize=9)
    fig.tight_layout()
    save_figure(fig, path)
    return True


def _scheme_findings(results: list[dict[str, Any]]) -> str:
    """One factual line per scheme at its finest mesh: pass/fail of the two targets with numbers."""
    ref = REFERENCES["simo1992"]
    lines = []
    for scheme in SCHEMES:
        r = _finest(results, scheme)
        if r is None:
            continue
        if r.get("status") != "completed":
            lines.append(f"* {scheme}, R0/h = {r['cells_per_radius']}: {r.get('status')} ({r.get('message', '')}).")
            continue
        bits = []
        for key, label, tol in (("impact_radius", "R_f", IMPACT_RADIUS_TOLERANCE),
                                ("final_length", "L_f", FINAL_LENGTH_TOLERANCE)):
            ok, err = _within(r.get(key), ref[key], tol)
            bits.append(f"{label} {fmt(_mm(r.get(key)), '.3f')} mm ({pct(err, 2)}, {'within' if ok else 'outside'} "
                        f"±{tol:.1%})")
        lines.append(f"* {scheme}, R0/h = {r['cells_per_radius']}: " + "; ".join(bits) + ".")
    return "\n".join(lines)


def report_text(results: list[dict[str, Any]], out: Path, checks: list[dict[str, Any]], figures: bool = True) -> str:
    out = Path(out)
    fig_dir = out / FIGURES / "taylor_bar"
    made = {}
    if figures:
        made["shapes"] = plot_shapes(results, out, fig_dir / "shapes.png")
        made["plastic_strain"] = plot_plastic_strain(results, out, fig_dir / "plastic_strain.png")
        made["convergence"] = plot_convergence(results, fig_dir / "convergence.png")
    rel = f"{FIGURES}/taylor_bar"
    figs = []
    if made.get("shapes"):
        figs.append(f"![final shapes]({rel}/shapes.png)\n\n*Outer profiles at 80 µs of the four schemes at the finest "
                    "mesh over each other; dashed: R_f = 7.12 mm (Simo 1992), dash-dotted: L_f ≈ 21.45 mm "
                    "(unconfirmed).*")
    if made.get("plastic_strain"):
        figs.append(f"![plastic strain]({rel}/plastic_strain.png)\n\n*Equivalent plastic strain on the particles "
                    "(finest cpGIMP and CPDI2, and the plane-strain strip).*")
    if made.get("convergence"):
        figs.append(f"![convergence]({rel}/convergence.png)\n\n*R_f and L_f against R0/h; grey: the targets.*")
    passed = sum(bool(c["passed"]) for c in checks)
    checks_md = "\n".join(f"| {c['name']} | {c.get('detail', '')} | {'pass' if c['passed'] else '**FAIL**'} |"
                          for c in checks)
    return f"""# Taylor bar impact (J2 plasticity)

Copper bar onto a rigid frictionless wall (Simo 1992 set: L0 = 32.4 mm, R0 = 3.2 mm, ρ = 8930 kg/m³,
E = 117 GPa, ν = 0.35, σ_y = 0.4 GPa, H = 0.1 GPa, 227 m/s, 80 µs), axisymmetric, pure FLIP, MUSL,
2 × 2 particles per cell, the wall z = 0 a frictionless roller (bilateral, as in Simo 1992). Rules
(docs/verification.md): L_f = highest particle edge; R_f = outermost particle edge (centre + half-extent
of F·[−l0, l0]²) among the particles whose centre lies within one cell of the wall; max ε̄p among the
particles within one cell of the axis; energy error = (KE0 − KE − E_el − W_p)/KE0. Enforced: the targets
for cpGIMP and CPDI2 at the finest mesh and their energy balance (within 1 %) on every run; original MPM
and uGIMP are reported.

## Results

{results_table(results)}

References: R_f = 7.12 mm (Simo 1992; 7.11 mm Zienkiewicz et al. 1998; 7.22 mm converged FE,
Foulk et al. 2021 — medium confidence, quoted secondhand); L_f = 21.45 mm (**unconfirmed**: FE runs in a
code's benchmark notes, 21.42–21.48 mm). Wilkins & Guinan: L_f ≈ 15.09 mm, foot radius ≈ 8.29 mm
(**low confidence**, a compilation of the measured profile), material: the Simo set.

At the finest mesh:

{_scheme_findings(results)}

## Checks ({passed}/{len(checks)} pass)

| check | measured | result |
|---|---|---|
{checks_md}

## Figures

{chr(10).join(figs) if figs else '(no figures)'}
"""


# --------------------------------------------------------------------------- the case


def _parse_list(text: str | None, kind: type, default: tuple[Any, ...], what: str) -> tuple[Any, ...]:
    if not text:
        return default
    try:
        return tuple(kind(t.strip()) for t in text.split(",") if t.strip())
    except ValueError:
        raise RunError(f"{what}: expected a comma-separated list (got {text!r})") from None


class TaylorBar:
    """Taylor bar impact: J2 plasticity at large strain, every scheme and three meshes."""

    name = "taylor_bar"
    kind = "verification"
    title = "Taylor bar impact (J2 plasticity, Simo 1992 copper; Wilkins & Guinan 1973 geometry)"
    default = False  # ~10 CPU minutes: run it by name

    def add_options(self, parser: argparse.ArgumentParser) -> None:
        parser.add_argument("--taylor-schemes", default=None,
                            help=f"taylor_bar: comma-separated schemes (default {','.join(SCHEMES)})")
        parser.add_argument("--taylor-meshes", default=None,
                            help="taylor_bar: comma-separated cells per radius R0/h, multiples of 8 "
                                 f"(default {','.join(map(str, MESHES))})")

    def runs(self, options: argparse.Namespace) -> list[RunSpec]:
        schemes = _parse_list(getattr(options, "taylor_schemes", None), str, SCHEMES, "--taylor-schemes")
        unknown = [s for s in schemes if s not in SCHEMES]
        if unknown:
            raise RunError(f"--taylor-schemes: unknown scheme(s) {', '.join(unknown)}; known: {', '.join(SCHEMES)}")
        meshes = _parse_list(getattr(options, "taylor_meshes", None), int, MESHES, "--taylor-meshes")
        bad = [n for n in meshes if n <= 0 or n % 8]
        if bad:
            raise RunError(f"--taylor-meshes: R0/h must be a positive multiple of 8 so that L0 = 32.4 mm lies on a "
                           f"grid line (got {', '.join(map(str, bad))})")
        return run_specs(bool(getattr(options, "quick", False)), schemes, meshes)

    def scenario(self, run: RunSpec) -> Any:
        p = run.params
        return taylor_scenario(p["scheme"], p["cells_per_radius"], p["formulation"], p["geometry"])

    def reference(self, run: RunSpec) -> dict[str, Any]:
        """R_f and L_f of the geometry (plane strain: none — it is a different problem)."""
        if run.params["formulation"] != "axisymmetric":
            return {}
        ref = REFERENCES[run.params["geometry"]]
        return {"impact_radius": ref["impact_radius"], "final_length": ref["final_length"]}

    def metrics(self, run: RunSpec, run_dir: Path) -> dict[str, Any]:
        return run_metrics(run_dir)

    def cost(self, run: RunSpec) -> float:
        p = run.params
        factor = {"linear": 0.6, "ugimp": 0.9, "cpgimp": 1.0, "cpdi2": 1.7}.get(p["scheme"], 1.0)
        return factor * p["cells_per_radius"] ** 3

    def progress(self, record: dict[str, Any]) -> str:
        if record.get("status") != "completed":
            return f"{record.get('status')}: {record.get('message', '')}"
        return (f"R_f {fmt(_mm(record.get('impact_radius')), '.3f')} mm, L_f {fmt(_mm(record.get('final_length')), '.3f')}"
                f" mm, energy error {pct(record.get('energy_error'), 2)}")

    def checks(self, results: list[dict[str, Any]]) -> list[dict[str, Any]]:
        quick = bool(getattr(results, "context", {}).get("quick", False))
        return evaluate_checks(results, quick=quick)

    def document(self, results: list[dict[str, Any]], options: argparse.Namespace) -> dict[str, Any]:
        return {"material": dict(COPPER),
                "geometries": {k: {"title": t, "length": L, "radius": R, "velocity": V, "end_time": T}
                               for k, (t, L, R, V, T) in GEOMETRIES.items()},
                "references": REFERENCES,
                "rules": {"final_length": "max over particles of z_p + l0(|F21| + |F22|)",
                          "impact_radius": "max of r_p + l0(|F11| + |F12|) over particles with z_p <= h",
                          "max_plastic_strain": "max plastic_strain over particles with r_p <= h",
                          "energy_error": "(KE0 - KE - elastic - plastic work)/KE0, totals x 2 pi"},
                "boundary": "base: roller (frictionless, bilateral: the impact face stays on the wall, as in Simo "
                            "1992); axis: roller",
                "flip_fraction": 1.0}

    def console(self, results: list[dict[str, Any]], checks: list[dict[str, Any]]) -> str:
        return results_table(results)

    def report(self, results: list[dict[str, Any]], out: Path) -> str:
        context = getattr(results, "context", {})
        checks = context.get("checks") or evaluate_checks(results, bool(context.get("quick")))
        return report_text(list(results), Path(out), checks, figures=context.get("figures", True))


CASE = register(TaylorBar())
