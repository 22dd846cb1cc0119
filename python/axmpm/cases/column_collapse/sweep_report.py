"""Report of the aspect-ratio sweep: ``axmpm validate --case column_collapse
--aspect-ratios ...``.

* A power law (R∞ − R_i)/R_i = λ a^β fitted on each side of a break point by least squares in
  log–log (numpy ``lstsq``), with 95 % confidence intervals for λ and β from the Student t
  quantile (:data:`T975`, a table: scipy is not a dependency). The break point is the split of
  the sorted aspect ratios (at least 2 points on each side) with the smallest total squared
  residual; it is reported as the intersection of the two fitted lines when that lies between
  the neighbouring points, else their geometric mean.
* Every case against Lube et al. 2004 and the Lajeunesse et al. 2004 runout (its small-a
  branch unconfirmed, docs/physics.md §6), with H∞, the mean J = V/V0 of the deposit and its
  energy budget (:mod:`.energy`).
* Figures: ``sweep_laws.png`` (points over the laws, each branch over its own range, dashed
  where unconfirmed, and the fits), ``energy.png`` (the budget over time at the smallest a,
  at a = 5.4 and at the largest a).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ...report import DASH, fmt, pct
from .animation import write_animations
from .energy import TERMS, plot_energy
from .laws import TABLE_LAWS
from .status import status_text

__all__ = ["T975", "t975", "fit_power_law", "fit_two_branches", "sweep_report", "plot_sweep_laws"]

#: Two-sided 95 % Student t quantiles t_{0.975}(ν) (standard tables).
T975: dict[int, float] = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306,
                          9: 2.262, 10: 2.228, 12: 2.179, 15: 2.131, 20: 2.086, 30: 2.042}


def t975(dof: int) -> float:
    """t_{0.975}(dof); between table entries the next smaller dof (conservative); 1.96 above 30."""
    if dof < 1:
        raise ValueError("at least one degree of freedom is needed")
    if dof > 30:
        return 1.96
    return T975[max(k for k in T975 if k <= dof)]


def fit_power_law(a: Any, y: Any) -> dict[str, Any]:
    """y = λ a^β by least squares on (ln a, ln y): λ, β, their 95 % intervals (None with only two
    points), the points used and the RMS residual in ln y."""
    a = np.asarray(a, dtype=float)
    y = np.asarray(y, dtype=float)
    if a.size < 2 or np.any(a <= 0) or np.any(y <= 0):
        raise ValueError("a power-law fit needs at least two points with positive a and y")
    A = np.column_stack([np.ones_like(a), np.log(a)])
    coef, *_ = np.linalg.lstsq(A, np.log(y), rcond=None)
    resid = np.log(y) - A @ coef
    n = a.size
    out: dict[str, Any] = {"n": int(n), "a_min": float(a.min()), "a_max": float(a.max()),
                           "lambda": float(math.exp(coef[0])), "beta": float(coef[1]),
                           "rms_log_residual": float(np.sqrt(np.mean(resid**2))),
                           "lambda_ci": None, "beta_ci": None, "sse": float(resid @ resid)}
    if n > 2:
        s2 = float(resid @ resid) / (n - 2)
        cov = s2 * np.linalg.inv(A.T @ A)
        t = t975(n - 2)
        se_b, se_c = math.sqrt(cov[1, 1]), math.sqrt(cov[0, 0])
        out["beta_ci"] = [float(coef[1] - t * se_b), float(coef[1] + t * se_b)]
        out["lambda_ci"] = [float(math.exp(coef[0] - t * se_c)), float(math.exp(coef[0] + t * se_c))]
    return out


def fit_two_branches(a: Any, y: Any, min_points: int = 2) -> dict[str, Any] | None:
    """:func:`fit_power_law` on each side of the best break point (module doc); None with fewer
    than 2 × ``min_points`` points."""
    order = np.argsort(np.asarray(a, dtype=float))
    a = np.asarray(a, dtype=float)[order]
    y = np.asarray(y, dtype=float)[order]
    best = None
    for k in range(min_points, a.size - min_points + 1):
        lo, hi = fit_power_law(a[:k], y[:k]), fit_power_law(a[k:], y[k:])
        sse = lo["sse"] + hi["sse"]
        if best is None or sse < best[0] - 1e-15:
            best = (sse, k, lo, hi)
    if best is None:
        return None
    _, k, lo, hi = best
    cross = None
    if abs(lo["beta"] - hi["beta"]) > 1e-12:
        cross = math.exp(math.log(hi["lambda"] / lo["lambda"]) / (lo["beta"] - hi["beta"]))
    if cross is not None and a[k - 1] <= cross <= a[k]:
        brk, how = cross, "intersection of the two fits"
    else:
        brk, how = math.sqrt(a[k - 1] * a[k]), "geometric mean of the neighbouring aspect ratios"
    return {"break": float(brk), "break_rule": how, "below": lo, "above": hi}


def _law_branches(ax: Any, law: Any, colour: str, a_lo: float, a_hi: float) -> None:
    """Each runout regime of ``law`` over its own range only (no joining line at a jump),
    solid where confirmed, dashed where not."""
    first = True
    for r in law.runout:
        lo, hi = max(r.a_min, a_lo), min(r.a_max, a_hi)
        if lo >= hi:
            continue
        x = np.logspace(math.log10(lo), math.log10(hi), 100)
        ax.plot(x, r(x), color=colour, ls="-" if r.confirmed else "--", lw=1.3,
                label=(law.label if first else None))
        first = False


def _formulation(cases: list[dict[str, Any]]) -> str:
    """The formulation of the sweep's runs (plane strain if any run is)."""
    return "plane_strain" if any(c.get("formulation") == "plane_strain" for c in cases) else "axisymmetric"


def plot_sweep_laws(cases: list[dict[str, Any]], fits: dict[str, Any] | None, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    a = np.array([c["aspect_ratio"] for c in cases])
    y = np.array([c["runout_normalised"] for c in cases])
    a_lo, a_hi = 0.8 * min(a.min(), 0.4), 1.25 * max(a.max(), 10.0)
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for law, colour in zip(TABLE_LAWS[_formulation(cases)], ("tab:red", "tab:blue", "tab:green")):
        _law_branches(ax, law, colour, a_lo, a_hi)
    ax.plot(a, y, "ko", ms=6, label="axmpm", zorder=5)
    if fits:
        for side, ls in (("below", "k:"), ("above", "k-.")):
            f = fits[side]
            x = np.logspace(math.log10(f["a_min"]), math.log10(f["a_max"]), 50)
            ax.plot(x, f["lambda"] * x ** f["beta"], ls, lw=1.0,
                    label=f"fit {f['lambda']:.2f} a^{f['beta']:.2f} ({'a <' if side == 'below' else 'a >'} "
                    f"{fits['break']:.2g})")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("a = H_i / R_i")
    ax.set_ylabel("(R∞ − R_i) / R_i")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(f"{_formulation(cases).replace('_', ' ')}: runout against the laws (dashed: unconfirmed branch)",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _fit_text(f: dict[str, Any]) -> str:
    if f["beta_ci"] is None:
        return f"λ = {f['lambda']:.3f}, β = {f['beta']:.3f} (2 points: no interval)"
    return (f"λ = {f['lambda']:.3f} [{f['lambda_ci'][0]:.3f}, {f['lambda_ci'][1]:.3f}], "
            f"β = {f['beta']:.3f} [{f['beta_ci'][0]:.3f}, {f['beta_ci'][1]:.3f}] "
            f"({f['n']} points, a = {f['a_min']:g}–{f['a_max']:g}, RMS ln-residual {f['rms_log_residual']:.3f})")


def _share(c: dict[str, Any], key: str) -> str:
    e = c.get("energy") or {}
    v = (e.get("shares") or {}).get(key)
    return DASH if v is None else f"{100 * v:.1f} %"


def _compression_work(c: dict[str, Any]) -> str:
    return pct(((c.get("plastic_work_by_lode") or {}).get("shares") or {}).get("compression"), 1, signed=False)


def _sideways(c: dict[str, Any]) -> str:
    v = (c.get("sideways_energy") or {}).get("peak_sideways_share")
    return DASH if v is None else f"{100 * v:.1f} %"


#: Table headers of the laws.
SHORT_NAMES = {"lube2004": "Lube 2004", "lajeunesse2004_kk": "Lajeunesse 2004", "lube2005_planar": "Lube 2005",
               "lajeunesse2005_planar": "Lajeunesse 2005", "kumar2015_dem": "Kumar 2D DEM"}


def sweep_table(cases: list[dict[str, Any]]) -> str:
    laws = TABLE_LAWS[_formulation(cases)]
    head = " | ".join(f"{SHORT_NAMES.get(law.key, law.label)} | diff" for law in laws)
    first = SHORT_NAMES.get(laws[0].key, laws[0].label)
    lines = [f"| run | a | cells/R_i | (R∞−R_i)/R_i | {head} | at 3 d | diff | mass beyond {first} | "
             "H∞/R_i | mean J | peak sideways KE | plastic | of it near compression | base friction | base impact | kinetic | residual | wall s | "
             "status |",
             "|---|---|---|---|" + "---|---|" * len(laws) + "---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in cases:
        if "laws" not in c:
            lines.append(f"| {c['name']} | {c.get('nominal_aspect_ratio', DASH)} | "
                         + " | ".join([DASH] * (14 + 2 * len(laws)))
                         + f" | {fmt(c.get('wall_seconds'), '.0f')} | {c['status']}: {c.get('message', '')} |")
            continue
        cells = []
        for law in laws:
            entry = c["laws"].get(law.key) or {}
            unconf = "" if entry.get("runout_confirmed") else " (unconf.)"  # every planar branch
            cells.append(f"{fmt(entry.get('runout_normalised'), '.3f')}{unconf} | "
                         f"{pct(entry.get('runout_normalised_rel_diff'), 1)}")
        lines.append(
            f"| {c['name']} | {c['aspect_ratio']:.3g} | {c['cells_per_radius']:.0f} | {c['runout_normalised']:.3f} | "
            + " | ".join(cells) + " | "
            f"{fmt(c.get('runout_normalised_3_grains'), '.3f')} | "
            f"{pct((c.get('runout_3_grains_rel_diff') or {}).get(laws[0].key), 1)} | "
            f"{pct((c.get('mass_beyond_law') or {}).get(laws[0].key), 1, signed=False)} | "
            f"{c['final_height_normalised']:.3f} | {c.get('volume_ratio_mean', float('nan')):.3f} | "
            f"{_sideways(c)} | {_share(c, 'plastic_work')} | {_compression_work(c)} | "
            f"{_share(c, 'boundary_friction_dissipation')} | "
            f"{_share(c, 'boundary_normal_dissipation')} | {_share(c, 'kinetic_energy')} | "
            f"{_share(c, 'energy_residual')} | {fmt(c.get('wall_seconds'), '.0f')} | {c['status']} |")
    return "\n".join(lines)


def law_agreement(cases: list[dict[str, Any]], fits: dict[str, Any] | None,
                  within: float = 0.10) -> list[dict[str, Any]]:
    """Which tabulated law the runs follow, on each side of the fitted break (or over all runs
    without a fit): per law, the mean |relative difference| of the runout over the runs the law
    covers and how many of them lie within `within`; the closest law is the one with the
    smallest mean. Where the laws disagree with each other this says which one the model
    follows."""
    if fits is None:
        groups = [("all a", cases)]
    else:
        b = fits["break"]
        groups = [(f"a < {b:.3g}", [c for c in cases if c["aspect_ratio"] < b]),
                  (f"a > {b:.3g}", [c for c in cases if c["aspect_ratio"] > b])]
    result = []
    for label, group in groups:
        per_law = []
        for law in TABLE_LAWS[_formulation(cases)]:
            diffs = [abs(d) for c in group
                     if (d := (c["laws"].get(law.key) or {}).get("runout_normalised_rel_diff")) is not None
                     and math.isfinite(d)]
            if diffs:
                per_law.append({"law": law.key, "name": SHORT_NAMES.get(law.key, law.label), "runs": len(diffs),
                                "mean_abs_diff": sum(diffs) / len(diffs),
                                "within": sum(d <= within for d in diffs)})
        if per_law:
            closest = min(per_law, key=lambda r: r["mean_abs_diff"])
            result.append({"range": label, "runs": len(group), "laws": per_law, "closest": closest["law"],
                           "tolerance": within})
    return result


def _agreement_text(agreement: list[dict[str, Any]]) -> str:
    if not agreement:
        return "no completed run to compare"
    lines = []
    for g in agreement:
        laws = "; ".join(f"{r['name']} {100 * r['mean_abs_diff']:.1f} % ({r['within']} of {r['runs']} within "
                         f"{100 * g['tolerance']:.0f} %)" for r in g["laws"])
        closest = next(r["name"] for r in g["laws"] if r["law"] == g["closest"])
        lines.append(f"* {g['range']} ({g['runs']} runs): mean |difference| {laws}. Closest: **{closest}**.")
    return "\n".join(lines)


def _energy_runs(cases: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The runs of the energy figure: nearest to a = 0.56, to 5.4, and the largest a."""
    ok = [c for c in cases if "laws" in c and c.get("energy") and c.get("status") == "completed"]
    if not ok:
        return []
    picks = [min(ok, key=lambda c: abs(math.log(c["aspect_ratio"] / t))) for t in (0.56, 5.4)]
    picks.append(max(ok, key=lambda c: c["aspect_ratio"]))
    return list({id(c): c for c in picks}.values())


def _comparison_text(formulation: str) -> str:
    """The tabulated laws' runout formulas (laws.py), for the fit's paragraph."""
    laws = "; ".join(f"{law.label} {law.runout_formula()}" for law in TABLE_LAWS[formulation])
    if formulation == "plane_strain":
        return ("For comparison (planar laws, all secondary quotations of medium–low confidence, "
                f"docs/physics.md §6a): {laws}.")
    return f"For comparison: {laws}."


def _laws_note(formulation: str) -> str:
    if formulation == "plane_strain":
        return ("Planar laws (plane strain: a column of length L_i against the channel's back wall, the "
                "roller at x = 0; R_i stands for L_i): Lube et al. 2005, Lajeunesse et al. 2005 and Kumar's "
                "2D DEM fit, each with its transition as quoted (laws.py); none is confirmed "
                "(\"(unconf.)\", dashed in the figure).")
    return ("Lajeunesse 2004: the KK transcription, 1.35 a below a = 0.74 (unconfirmed) and 2.0 a^0.5 above\n"
            "(medium confidence).")


def sweep_report(cases: list[dict[str, Any]], out: Path, document: dict[str, Any], figures: bool = True) -> str:
    # A failed run (e.g. a particle left the grid) still has a last frame with laws, but not a
    # deposit: it is tabulated with its status and left out of the fit and the figures.
    ok = [c for c in cases if "laws" in c and c.get("runout_normalised", 0) > 0 and c.get("status") == "completed"]
    a = [c["aspect_ratio"] for c in ok]
    y = [c["runout_normalised"] for c in ok]
    fits = fit_two_branches(a, y) if len(ok) >= 4 else None
    if fits is not None:
        for c in cases:
            c.setdefault("context_fit", None)
        if cases:
            cases[0]["sweep_fit"] = fits  # validation.json keeps it with the first record
    energy_runs = _energy_runs(cases)
    agreement = law_agreement(ok, fits)
    if cases:
        cases[0]["law_agreement"] = agreement  # validation.json keeps it with the first record
    animations = ""
    if figures and ok:
        animations = write_animations(ok, out)
        plot_sweep_laws(ok, fits, out / "sweep_laws.png")
        if energy_runs:
            plot_energy([(f"{c['name']}: a = {c['aspect_ratio']:.3g}", out / c["run_dir"]) for c in energy_runs],
                        out / "energy.png")
    cpr = sorted({round(c["cells_per_radius"], 1) for c in ok})
    fit_text = "too few completed runs for the fit (4 needed)" if fits is None else (
        f"break point a_b = {fits['break']:.3g} ({fits['break_rule']}).\n\n"
        f"* a < a_b: {_fit_text(fits['below'])}\n* a > a_b: {_fit_text(fits['above'])}\n\n"
        + _comparison_text(_formulation(cases)) + " Intervals: 95 %, Student t on n − 2 degrees of freedom.")
    energy_lines = []
    for c in energy_runs:
        e = c["energy"]
        parts = ", ".join(f"{label} {100 * e['shares'][k]:.1f} %" for k, label in TERMS if e["shares"].get(k) is not None)
        energy_lines.append(f"* {c['name']} (a = {c['aspect_ratio']:.3g}, t = {e['time']:.2f} s, released "
                            f"{e['released']:.4g} J): {parts}")
    failed = [c["name"] for c in cases if c.get("status") != "completed"]
    return f"""# axmpm validation: aspect-ratio sweep of the granular column collapse

{status_text(cases)}

Formulation: {document['formulation']}. Mesh: {', '.join(f'{x:g}' for x in cpr) or DASH} cells per R_i.
Overrides: {', '.join(document['overrides']) or 'none'}. Runs: {len(cases)} ({len(ok)} analysed{', failed: ' + ', '.join(failed) if failed else ''}).
Set-up, analysis rules (one-grain runout R∞, H∞) and the laws' sources: docs/validation.md,
docs/physics.md §6, `axmpm/cases/column_collapse/laws.py`.

## Fit (R∞ − R_i)/R_i = λ a^β

{fit_text}

## Which law the runs follow

{_agreement_text(agreement)}

## Every case

{sweep_table(cases)}

{_laws_note(_formulation(cases))} mean J = V/V0 over the deposit's particles at the last frame. Energy
columns: shares of the potential energy released at the last output (docs/physics.md §1,
"Energy budget"): plastic = the material's own dissipation, base friction / impact = the
tangential / normal kinetic energy removed by the base's velocity corrections, residual = what
the scheme loses (released − all terms). Peak sideways KE: the largest kinetic energy of the
radial (plane strain: horizontal) motion over the output frames, as a share of the potential
energy released by the end (Staron & Hinch 2005's "energy available for the sideways flow";
`energy.sideways_energy`). Of it near compression: the share of the plastic work dissipated
near triaxial compression (Lode parameter ξ < −½ at the frame after it was dissipated;
`energy.plastic_work_by_lode`), where a Drucker–Prager cone calibrated in shear is weaker than
Mohr–Coulomb with the same shear strength (it reads the returned stress: meaningful as a
loading measure for Drucker–Prager, whose radial return keeps the trial stress's Lode angle;
Mohr–Coulomb returns to an edge of the pyramid sit at ξ = ±1 by construction).

## Energy budget

{chr(10).join(energy_lines) or 'no run with an energy budget'}

![energy](energy.png)

*Each term over time as a fraction of the final released potential energy.*

![laws](sweep_laws.png)

*(R∞ − R_i)/R_i against a: axmpm (dots), the laws (each branch over its own range; dashed:
unconfirmed) and the two fitted power laws.*

{animations}"""
