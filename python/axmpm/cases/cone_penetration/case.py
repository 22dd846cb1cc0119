"""The ``cone_penetration`` verification case (``axmpm verify --case cone_penetration``): a
standard 60° cone pushed ten diameters into weightless Tresca clay at an isotropic in-situ
stress, smooth and rough, for rigidity indices I_r = 50, 100, 300, 500 at R/h = 4 and 8, and
the steady cone factor N_c against Lu, Randolph, Hu & Bugarski (2004) and Teh & Houlsby (1991)
(docs/physics.md §8, docs/verification.md). A domain check repeats the stiffest smooth run at
R/h = 4 in a soil twice as wide and deep.

Outputs (besides the driver's ``verification.json``): ``figures/cone_penetration_depth.png``
(N_c against depth per I_r), ``figures/cone_penetration_factor.png`` (N_c against ln I_r with
both formulas), ``figures/cone_penetration_soil.png`` (the deformed soil around the cone, the
particles coloured by their initial row), and the report section with the table.

``--quick`` (in ``make test``): one coarse, shallow run (I_r = 100, smooth, R/h = 2, three
diameters), whose N_c over the last diameter must lie within 30 % of Lu et al.'s, whose parts
must sum to the cone's force and whose smooth shaft must carry no axial force.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ...report import checks_table, figures_section, fmt, pct
from .. import RunSpec, register
from ..driver import shared_setting
from .scenario import (DIAMETER, MESHES, PUSH, RADIUS, RIGIDITY_INDICES, ROUGHNESS, SLEEVE_AREA, VELOCITY, WINDOW,
                       cone_scenario, domain, lu_et_al, penetration_curve, steady_cone_factor, teh_houlsby)

#: N_c at the finest mesh: enforced within LIMIT of Lu et al., aimed within TARGET.
LIMIT, TARGET = 0.10, 0.05
#: The slope dN_c/d ln I_r (smooth, finest mesh): enforced within this share of Lu's 1.6.
SLOPE_SHARE = 0.20
LU_SLOPE = 1.6
#: Steady: |drift of N_c| per diameter over the averaging window below this.
DRIFT_LIMIT = 0.01
#: Quasi-static: kinetic energy over plastic work over the window, reported against this.
QUASI_STATIC = 0.01
#: Domain check: doubling the soil's radius and depth changes N_c by less than this.
DOMAIN_LIMIT = 0.02
#: The run the domain check doubles (rigidity index, roughness, R/h).
DOMAIN_RUN = (max(RIGIDITY_INDICES), "smooth", MESHES[0])
#: Rate check: half the speed changes N_c by less than this (aim; docs/physics.md §8, "Rate"), on
#: the run RATE_RUN (rigidity index, roughness, R/h).
RATE_LIMIT = 0.02
RATE_RUN = (100, "smooth", MESHES[0])

#: The quick run: (rigidity index, roughness, R/h, push, window) in R; its band around Lu et al.
QUICK = (100, "smooth", 2, 6.0, 2.0)
QUICK_BAND = 0.30
#: A smooth shaft carries no axial force: |sleeve + rest| below this share of the tip's force.
SMOOTH_SHAFT = 1e-6


def run_name(rigidity_index: int, roughness: str, cells: int, scale: float = 1.0, half_speed: bool = False) -> str:
    return (f"ir{rigidity_index}_{roughness}_r{cells}" + ("" if scale == 1.0 else f"_domain{scale:g}")
            + ("_half_speed" if half_speed else ""))


def _params(rigidity_index: int, roughness: str, cells: int, push: float = PUSH, window: float = WINDOW,
            scale: float = 1.0, quick: bool = False, velocity: float = VELOCITY,
            half_speed: bool = False) -> dict[str, Any]:
    alpha = ROUGHNESS[roughness]
    return {"rigidity_index": rigidity_index, "roughness": roughness, "alpha": alpha, "cells_per_radius": cells,
            "quick": quick, "velocity": 0.5 * velocity if half_speed else velocity, "half_speed": half_speed,
            "push_radii": push, "window_radii": window, "domain_scale": scale,
            "domain_radii": list(domain(rigidity_index, scale, push))}


def _positive(flag: str, above: float) -> Callable[[str], float]:
    """An argparse type: a number above ``above``, else the flag's allowed range in the error."""
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not value > above:
            raise argparse.ArgumentTypeError(f"{flag} must be a number > {above:g} (got {text!r})")
        return value
    return parse


class ConePenetration:
    """Cone penetration in Tresca clay: the steady cone factor against Lu et al. and Teh & Houlsby."""

    name = "cone_penetration"
    kind = "verification"
    title = "Cone penetration test in undrained clay (cone factor against rigidity index and roughness)"
    default = False  # hours on one core

    def add_options(self, parser: argparse.ArgumentParser) -> None:
        parser.add_argument("--cone-meshes", type=int, nargs="+", default=None, metavar="R/h",
                            help=f"cone_penetration: cells per cone radius (default {' '.join(map(str, MESHES))})")
        parser.add_argument("--cone-rigidity", type=int, nargs="+", default=None, metavar="I_r",
                            help="cone_penetration: rigidity indices G/s_u "
                            f"(default {' '.join(map(str, RIGIDITY_INDICES))})")
        parser.add_argument("--cone-roughness", choices=tuple(ROUGHNESS), nargs="+", default=None,
                            help="cone_penetration: smooth (alpha = 0) and/or rough (adhesion = s_u); default both")
        parser.add_argument("--cone-velocity", type=_positive("--cone-velocity", 0.0), default=VELOCITY,
                            metavar="V", help=f"cone_penetration: the cone's speed, m/s, > 0 (default {VELOCITY:g})")
        parser.add_argument("--cone-push", type=_positive("--cone-push", WINDOW), default=PUSH, metavar="RADII",
                            help=f"cone_penetration: travel in cone radii, > {WINDOW:g} (the last {WINDOW:g} R "
                                 f"give N_c; default {PUSH:g})")

    def runs(self, options: argparse.Namespace) -> list[RunSpec]:
        if getattr(options, "quick", False):
            ir, rough, cells, push, window = QUICK
            return [RunSpec(run_name(ir, rough, cells), _params(ir, rough, cells, push, window, quick=True))]
        meshes = sorted(set(getattr(options, "cone_meshes", None) or MESHES))
        indices = sorted(set(getattr(options, "cone_rigidity", None) or RIGIDITY_INDICES))
        roughness = [r for r in ROUGHNESS if r in (getattr(options, "cone_roughness", None) or ROUGHNESS)]
        rate = {"push": getattr(options, "cone_push", PUSH), "velocity": getattr(options, "cone_velocity", VELOCITY)}
        runs = [RunSpec(run_name(ir, r, n), _params(ir, r, n, **rate)) for n in meshes for ir in indices
                for r in roughness]
        ir, r, n = DOMAIN_RUN
        if ir in indices and r in roughness and n in meshes:
            runs.append(RunSpec(run_name(ir, r, n, 2.0), _params(ir, r, n, scale=2.0, **rate)))
        ir, r, n = RATE_RUN
        if ir in indices and r in roughness and n in meshes:
            runs.append(RunSpec(run_name(ir, r, n, half_speed=True), _params(ir, r, n, half_speed=True, **rate)))
        return runs

    def scenario(self, run: RunSpec) -> Any:
        p = run.params
        return cone_scenario(p["rigidity_index"], p["roughness"], p["cells_per_radius"], push=p["push_radii"],
                             domain_scale=p["domain_scale"], velocity=p.get("velocity", VELOCITY))

    def reference(self, run: RunSpec) -> dict[str, Any]:
        p = run.params
        return {"cone_factor": lu_et_al(p["rigidity_index"], p["alpha"]),
                "cone_factor_teh_houlsby": teh_houlsby(p["rigidity_index"], p["alpha"])}

    def metrics(self, run: RunSpec, run_dir: Path) -> dict[str, Any]:
        empty = {"cone_factor": None, "cone_factor_teh_houlsby": None}
        try:
            curve = penetration_curve(run_dir)
            summary = json.loads((Path(run_dir) / "summary.json").read_text())
        except (FileNotFoundError, KeyError, ValueError):
            return empty
        p = run.params
        push, window = p["push_radii"], p["window_radii"]
        nc, drift = steady_cone_factor(curve["travel"], curve["cone_factor"], push, window)
        from ...run.output import load_run

        history = load_run(run_dir).history
        travel = -history["cone.displacement_y"] / DIAMETER
        late = travel >= (push - window) * RADIUS / DIAMETER - 1e-9
        work = history["plastic_work"][late]
        kinetic = history["kinetic_energy"][late]
        ratio = float(np.max(kinetic / work)) if late.any() and np.all(work > 0) else None
        total = np.abs(curve["total"]).max() if len(curve["total"]) else 0.0
        balance = float(np.abs(curve["parts_sum"] - curve["total"]).max() / total) if total > 0 else None
        shaft = curve["total"] - curve["tip"]
        window_rows = curve["travel"] >= (push - window) * RADIUS / DIAMETER - 1e-9
        sleeve = float(np.mean(curve["sleeve"][window_rows])) / SLEEVE_AREA if window_rows.any() else None
        return {"cone_factor": nc, "cone_factor_teh_houlsby": nc,
                "cone_factor_drift": drift,
                "final_cone_factor": float(curve["cone_factor"][-1]) if len(curve["cone_factor"]) else None,
                "kinetic_to_plastic": ratio,
                "parts_balance": balance,
                "shaft_axial_share": float(np.abs(shaft).max() / np.abs(curve["tip"]).max()) if total > 0 else None,
                "sleeve_friction": sleeve,
                "particles": summary.get("particles"), "steps": summary.get("steps"),
                "engine_seconds": summary.get("engine_seconds"), "threads": summary.get("threads")}

    def cost(self, run: RunSpec) -> float:
        p = run.params
        width, below = p["domain_radii"]
        # particles ∝ (R/h)² × area, steps ∝ R/h × c_p ∝ √I_r
        return p["cells_per_radius"] ** 3 * width * (below + p["push_radii"]) * math.sqrt(p["rigidity_index"])

    def progress(self, record: dict[str, Any]) -> str:
        nc = record.get("cone_factor")
        if record["status"] == "completed" and nc is not None:
            err = record["relative_error"]["cone_factor"]
            return (f"N_c = {nc:.3f} ({100 * err:+.1f} % of Lu et al.), drift "
                    f"{pct(record.get('cone_factor_drift'))}/D, KE/W_p {fmt(record.get('kinetic_to_plastic'), '.2g')}")
        return f"{record['status']}: {record['message']}"

    def checks(self, results: list[dict[str, Any]]) -> list[dict[str, Any]]:
        if any(r.get("quick") for r in results):
            return quick_checks(results)
        return full_checks(results)

    def document(self, results: list[dict[str, Any]], options: argparse.Namespace) -> dict[str, Any]:
        from . import scenario as s

        return {"formulas": {"lu_et_al_2004": "N_c = 3.4 + 1.6 ln I_r - 1.9 Delta + 1.3 alpha",
                             "teh_houlsby_1991": "N_c = (4/3)(1 + ln I_r)(1.25 + I_r/2000) + 2.4 alpha_f - 0.2 alpha_s "
                                                 "- 1.8 Delta"},
                "parameters": {"radius": s.RADIUS, "apex_angle_degrees": 60.0, "undrained_strength": s.UNDRAINED_STRENGTH,
                               "in_situ_stress": s.IN_SITU_STRESS, "poisson_ratio": s.POISSON_RATIO,
                               "density": s.DENSITY, "velocity": getattr(options, "cone_velocity", s.VELOCITY),
                               "push_radii": getattr(options, "cone_push", s.PUSH), "embedment_radii": s.EMBEDMENT,
                               "sleeve_length": s.SLEEVE_LENGTH, "scheme": "cpgimp", "particles_per_cell": 2,
                               "volumetric_averaging": "cell", "flip_fraction": shared_setting(results, "flip_fraction")}}

    def console(self, results: list[dict[str, Any]], checks: list[dict[str, Any]]) -> str:
        return nc_table(results)

    def report(self, results: list[dict[str, Any]], out: Path) -> str:
        context = getattr(results, "context", {})
        checks = context.get("checks") or self.checks(results)

        def draw() -> str:
            figure_dir = Path(out) / "figures"
            plot_depth(results, Path(out), figure_dir / "cone_penetration_depth.png")
            plot_factor(results, figure_dir / "cone_penetration_factor.png")
            shown = plot_soil(results, Path(out), figure_dir / "cone_penetration_soil.png")
            figures = ("![N_c against depth](figures/cone_penetration_depth.png)\n\n"
                       "*N_c = (q_c − σ_v0)/s_u against the tip's depth (q_c: the tip's force over πR², the mean "
                       "over each 0.05R of travel); shaded: the averaging window.*\n\n"
                       "![N_c against ln I_r](figures/cone_penetration_factor.png)\n\n"
                       "*Steady N_c against ln I_r at the finest mesh, with Lu et al. (2004) and Teh & Houlsby "
                       "(1991).*\n\n")
            if shown:
                figures += ("![deformed soil](figures/cone_penetration_soil.png)\n\n"
                            f"*The soil around the cone at the end of run {shown}: particles coloured by the "
                            "band of their initial depth (one band per cone radius).*\n")
            return figures

        figures = figures_section(results, draw)
        return f"""# axmpm verification: cone penetration in undrained clay

A standard cone (R = 17.85 mm, 60° apex, a shaft of radius R behind it) pushed into weightless
Tresca clay (s_u = 18 kPa, ν = 0.49 with cell averaging, G = I_r s_u) at σ_v0 = σ_h0 = 66 kPa,
held by a 66 kPa surcharge on the soil's top; axisymmetric, cpGIMP, 2 × 2 particles per cell,
FLIP 0.99, no damping. The cone starts with its tip 4R below the surface and is pushed at
1 m/s (reached over 0.25R of travel). q_c = tip force / πR², the tip being the cone below its
shoulder (the rigid body's part `tip`); N_c = (q_c − σ_v0)/s_u, its mean over the last
3 diameters of the push. Smooth: no friction; rough: adhesion s_u (α = 1). References:
Lu et al. (2004) N_c = 3.4 + 1.6 ln I_r + 1.3α (checked) and Teh & Houlsby (1991)
N_c = (4/3)(1 + ln I_r)(1.25 + I_r/2000) + 2.4α_f − 0.2α_s (reported); docs/physics.md §8.

## N_c per run

{nc_table(results)}

## Checks

{checks_table(checks)}

## Figures

{figures}"""


def _completed(results: list[dict[str, Any]]) -> list[dict[str, Any]]:
    return [r for r in results if r.get("cone_factor") is not None]


def _run(results: list[dict[str, Any]], which: tuple[int, str, int], scale: float = 1.0,
         half_speed: bool = False) -> dict[str, Any] | None:
    """The completed run of (rigidity index, roughness, R/h) with that domain scale and speed."""
    return next((r for r in _completed(results) if (r["rigidity_index"], r["roughness"], r["cells_per_radius"]) == which
                 and r["domain_scale"] == scale and bool(r.get("half_speed")) == half_speed), None)


def _finest(results: list[dict[str, Any]], rigidity_index: int, roughness: str) -> dict[str, Any] | None:
    group = [r for r in _completed(results) if r["rigidity_index"] == rigidity_index and r["roughness"] == roughness
             and r["domain_scale"] == 1.0 and not r.get("half_speed")]
    return max(group, key=lambda r: r["cells_per_radius"]) if group else None


def slope(records: list[dict[str, Any]]) -> float | None:
    """dN_c/d ln I_r: the least-squares slope over the records (None with fewer than two I_r)."""
    if len({r["rigidity_index"] for r in records}) < 2:
        return None
    x = np.log([r["rigidity_index"] for r in records])
    return float(np.polyfit(x, [r["cone_factor"] for r in records], 1)[0])


def quick_checks(results: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The quick run: N_c over its last diameter within QUICK_BAND of Lu et al., the parts sum to
    the cone's force, the smooth shaft carries no axial force."""
    checks: list[dict[str, Any]] = []
    for r in results:
        nc = r.get("cone_factor")
        err = r.get("relative_error", {}).get("cone_factor")
        checks.append({"name": f"{r['name']}: N_c within {100 * QUICK_BAND:g} % of Lu et al. (coarse, shallow)",
                       "passed": err is not None and abs(err) <= QUICK_BAND,
                       "detail": f"N_c = {fmt(nc, '.3f')} vs {lu_et_al(r['rigidity_index'], r['alpha']):.3f} ({pct(err)})"})
        balance = r.get("parts_balance")
        checks.append({"name": f"{r['name']}: tip + sleeve + rest = the cone's force",
                       "passed": balance is not None and balance < 1e-9,
                       "detail": f"largest difference {fmt(balance, '.2g')} of the largest force"})
        if r["roughness"] == "smooth":
            share = r.get("shaft_axial_share")
            checks.append({"name": f"{r['name']}: the smooth shaft carries no axial force",
                           "passed": share is not None and share < SMOOTH_SHAFT,
                           "detail": f"|total − tip| / |tip| up to {fmt(share, '.2g')}"})
    return checks


def full_checks(results: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The enforced criteria of the full case (module doc of scenario.py; docs/verification.md)."""
    checks: list[dict[str, Any]] = []
    for r in results:
        if r.get("cone_factor") is None:
            checks.append({"name": f"{r['name']}: completed and reached the window", "passed": False,
                           "detail": f"{r['status']}: {r.get('message', '')}"})
            continue
        drift = r.get("cone_factor_drift")
        checks.append({"name": f"{r['name']}: steady (|drift| < {100 * DRIFT_LIMIT:g} % per diameter)",
                       "passed": drift is not None and abs(drift) < DRIFT_LIMIT, "detail": f"{pct(drift, 2)}/D"})
        ratio = r.get("kinetic_to_plastic")
        checks.append({"name": f"{r['name']}: quasi-static (kinetic energy < {100 * QUASI_STATIC:g} % of the plastic work)",
                       "passed": ratio is not None and ratio < QUASI_STATIC, "detail": f"largest {fmt(ratio, '.2g')}",
                       "required": False})
    for ir in sorted({r["rigidity_index"] for r in results}):
        for roughness in ROUGHNESS:
            best = _finest(results, ir, roughness)
            if best is None:
                continue
            err = best["relative_error"]["cone_factor"]
            where = (f"N_c = {best['cone_factor']:.3f} at R/h = {best['cells_per_radius']} vs Lu et al. "
                     f"{lu_et_al(ir, ROUGHNESS[roughness]):.3f} ({pct(err)})")
            label = f"I_r = {ir} {roughness}"
            checks.append({"name": f"{label}: N_c within {100 * LIMIT:g} % of Lu et al. at the finest mesh",
                           "passed": abs(err) <= LIMIT, "detail": where})
            checks.append({"name": f"{label}: N_c within {100 * TARGET:g} % (aim)", "passed": abs(err) <= TARGET,
                           "detail": where, "required": False})
    smooth = [b for b in (_finest(results, ir, "smooth") for ir in sorted({r["rigidity_index"] for r in results}))
              if b is not None]
    s = slope(smooth)
    if s is not None:
        checks.append({"name": f"smooth: dN_c/d ln I_r within {100 * SLOPE_SHARE:g} % of Lu et al.'s {LU_SLOPE}",
                       "passed": abs(s - LU_SLOPE) <= SLOPE_SHARE * LU_SLOPE, "detail": f"slope {s:.3f}"})
    ir, roughness, cells = DOMAIN_RUN
    base, big = _run(results, DOMAIN_RUN), _run(results, DOMAIN_RUN, scale=2.0)
    if base is not None and big is not None:
        change = big["cone_factor"] / base["cone_factor"] - 1.0
        checks.append({"name": f"domain: twice the soil's radius and depth changes N_c by < {100 * DOMAIN_LIMIT:g} % "
                       f"(I_r = {ir}, {roughness}, R/h = {cells})", "passed": abs(change) < DOMAIN_LIMIT,
                       "detail": f"{base['cone_factor']:.3f} → {big['cone_factor']:.3f} ({pct(change)})"})
    base, slow = _run(results, RATE_RUN), _run(results, RATE_RUN, half_speed=True)
    if base is not None and slow is not None:
        change = slow["cone_factor"] / base["cone_factor"] - 1.0
        ir, roughness, cells = RATE_RUN
        checks.append({"name": f"rate: half the speed changes N_c by < {100 * RATE_LIMIT:g} % "
                       f"(I_r = {ir}, {roughness}, R/h = {cells}; aim)", "passed": abs(change) < RATE_LIMIT,
                       "detail": f"{base['cone_factor']:.3f} at {base['velocity']:g} m/s → {slow['cone_factor']:.3f} "
                                 f"at {slow['velocity']:g} m/s ({pct(change)})", "required": False})
    return checks


def nc_table(results: list[dict[str, Any]]) -> str:
    """Per run: N_c, the references and errors, drift, quasi-static ratio and cost."""
    head = ("| run | I_r | α | R/h | domain (R) | N_c | Lu et al. | error | Teh & Houlsby | error | drift /D "
            "| KE/W_p | particles | steps | engine s |")
    lines = [head, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(results, key=lambda x: (x["cells_per_radius"], x["domain_scale"], x["roughness"],
                                            x["rigidity_index"])):
        errors = r.get("relative_error", {})
        width, below = r["domain_radii"]
        lines.append(
            f"| {r['name']} | {r['rigidity_index']} | {r['alpha']:g} | {r['cells_per_radius']} | {width:.0f} × "
            f"{below + r['push_radii'] + 4:.0f} | {fmt(r.get('cone_factor'), '.3f')} "
            f"| {lu_et_al(r['rigidity_index'], r['alpha']):.3f} | {pct(errors.get('cone_factor'))} "
            f"| {teh_houlsby(r['rigidity_index'], r['alpha']):.3f} | {pct(errors.get('cone_factor_teh_houlsby'))} "
            f"| {pct(r.get('cone_factor_drift'), 2)} | {fmt(r.get('kinetic_to_plastic'), '.2g')} "
            f"| {fmt(r.get('particles'), ',.0f')} | {fmt(r.get('steps'), ',.0f')} "
            f"| {fmt(r.get('engine_seconds'), '.0f')} |")
    return "\n".join(lines)


def plot_depth(results: list[dict[str, Any]], out: Path, path: Path) -> Path:
    from ...plotting import pyplot, save_figure

    plt = pyplot()
    present = [r for r in ROUGHNESS if any(x["roughness"] == r for x in results)]
    fig, axes = plt.subplots(1, len(present), figsize=(5.5 * len(present), 4.5), squeeze=False)
    colours = dict(zip(RIGIDITY_INDICES, ("tab:blue", "tab:green", "tab:orange", "tab:red")))
    for ax, roughness in zip(axes[0], present):
        for rec in sorted((x for x in results if x["roughness"] == roughness),
                          key=lambda x: (x["rigidity_index"], x["cells_per_radius"], x["domain_scale"])):
            try:
                curve = penetration_curve(out / rec["run_dir"])
            except (FileNotFoundError, KeyError, ValueError):
                continue
            ir = rec["rigidity_index"]
            style = "-" if rec["cells_per_radius"] == max(x["cells_per_radius"] for x in results) else "--"
            if rec["domain_scale"] != 1.0:
                style = ":"
            if rec.get("half_speed"):
                style = (0, (8, 2, 2, 2))
            ax.plot(curve["depth"], curve["cone_factor"], ls=style, lw=1.0, color=colours.get(ir, "tab:gray"),
                    label=f"I_r = {ir}, R/h = {rec['cells_per_radius']}"
                    + ("" if rec["domain_scale"] == 1.0 else f", domain × {rec['domain_scale']:g}")
                    + (f", half speed ({rec['velocity']:g} m/s)" if rec.get("half_speed") else ""))
            ax.axhline(lu_et_al(ir, ROUGHNESS[roughness]), color=colours.get(ir, "tab:gray"), lw=0.8, ls="-.")
        push, window = results[0]["push_radii"], results[0]["window_radii"]
        embed = 2.0  # diameters (EMBEDMENT R)
        ax.axvspan(embed + (push - window) * RADIUS / DIAMETER, embed + push * RADIUS / DIAMETER, color="0.9", zorder=0)
        ax.set_title(f"{roughness} (dash-dot: Lu et al.)")
        ax.set_xlabel("tip depth / D")
        ax.set_ylabel("N_c = (q_c − σ_v0) / s_u")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    return save_figure(fig, path)


def plot_factor(results: list[dict[str, Any]], path: Path) -> Path:
    from ...plotting import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ir = np.linspace(math.log(30), math.log(700), 60)
    for roughness, colour in (("smooth", "tab:blue"), ("rough", "tab:red")):
        alpha = ROUGHNESS[roughness]
        ax.plot(ir, [lu_et_al(math.exp(x), alpha) for x in ir], color=colour, lw=1.0, label=f"Lu et al., {roughness}")
        ax.plot(ir, [teh_houlsby(math.exp(x), alpha) for x in ir], color=colour, lw=1.0, ls="--",
                label=f"Teh & Houlsby, {roughness}")
        pts = [b for b in (_finest(results, i, roughness) for i in sorted({r["rigidity_index"] for r in results}))
               if b is not None]
        if pts:
            ax.plot([math.log(p["rigidity_index"]) for p in pts], [p["cone_factor"] for p in pts], "o", color=colour,
                    label=f"axmpm, {roughness}")
    ax.set_xlabel("ln I_r")
    ax.set_ylabel("N_c")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, path)


def plot_soil(results: list[dict[str, Any]], out: Path, path: Path) -> str | None:
    """The deformed soil near the cone at the end of one run (I_r = 100 smooth at the finest mesh
    when there is one, else the first completed run); returns that run's name."""
    from ...plotting import pyplot, save_figure
    from ...run.output import load_run

    done = _completed(results)
    if not done:
        return None
    pick = _finest(results, 100, "smooth") or done[0]
    run = load_run(out / pick["run_dir"])
    frame = run.last
    x, X0 = np.asarray(frame.x), np.asarray(frame.X0)
    outline = run.history
    tip_travel = -outline["cone.displacement_y"][-1]
    surface = X0[:, 1].max()
    tip0 = surface - 4.0 * RADIUS
    tip = tip0 - tip_travel
    near = (x[:, 0] < 10 * RADIUS) & (np.abs(x[:, 1] - tip) < 10 * RADIUS)
    band = np.floor((surface - X0[near, 1]) / RADIUS).astype(int) % 2
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5, 6))
    ax.scatter(x[near, 0] / RADIUS, (x[near, 1] - tip) / RADIUS, c=band, s=2, cmap="coolwarm", vmin=0, vmax=1,
               linewidths=0)
    from .scenario import SHOULDER

    ax.plot([0, 1, 1], [0, SHOULDER / RADIUS, 10], color="k", lw=1.5)
    ax.set_aspect("equal")
    ax.set_xlim(0, 10)
    ax.set_ylim(-10, 10)
    ax.set_xlabel("r / R")
    ax.set_ylabel("(z − z_tip) / R")
    ax.set_title(pick["name"])
    save_figure(fig, path)
    return str(pick["name"])


CASE = register(ConePenetration())
