"""``axmpm convergence``: a validation case on a sequence of meshes (the column collapse).

Runs the case through the generic driver once per cell size (``DIR/h<size>mm/``), then
tabulates, per case and mesh, the two runout measures and the final height against Lube et
al. (2004), and estimates the mesh-converged value of each relative difference by Richardson
extrapolation (Roache 1998, *Verification and Validation in Computational Science and
Engineering*, ch. 5) when three or more meshes are refined by a constant ratio:

    order  p  = ln((e₁ − e₂) / (e₂ − e₃)) / ln r,   e∞ = e₃ + (e₃ − e₂) / (r^p − 1),

with e₁, e₂, e₃ the values on the three finest meshes (coarse to fine) and r the
refinement ratio. The estimate is given only when the changes shrink monotonically
(same sign) at an observed order p ≥ ``MIN_ORDER`` (0.5; below that the extrapolation
amplifies the last change by more than 2.4× and means nothing); otherwise the quantity is
reported as not converging. The relative
difference to the law is extrapolated, not the raw value, because heights are rounded to
whole cells, so the simulated aspect ratio changes a little with the mesh.

Writes ``DIR/convergence.json`` and ``DIR/convergence.md`` (table and figure). A mesh
whose runs already completed in ``DIR`` with the same cases and settings is not run again
(its deposits are re-analysed), so the command can be repeated with more cell sizes.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

from ..cases import RunSpec
from ..cases.column_collapse import case
from ..cases.column_collapse.deposit import profile_difference
from ..errors import RunError
from ..report import pct

NAME = "convergence"

DEFAULT_CELL_SIZES = (0.002, 0.001, 0.0005)

#: Changes below this (relative) count as no change.
ROUND_OFF = 1e-9
#: Smallest observed order of convergence that is extrapolated.
MIN_ORDER = 0.5



def _case() -> Any:
    """The case whose meshes are compared: the column collapse (it has ``convergence_quantities``
    and a ``cell_size`` builder parameter)."""
    return case


def quantities() -> dict[str, tuple[str, Any, Any]]:
    """The quantities followed across meshes: key → (label, value getter, relative difference
    to the reference getter), from the case's ``convergence_quantities``."""
    return _case().CASE.convergence_quantities


def richardson(values: list[float], ratio: float) -> dict[str, Any]:
    """Observed order and extrapolated limit of the last three of ``values`` (coarse to
    fine, refinement ``ratio``); ``converging`` False when the changes do not shrink
    monotonically."""
    if len(values) < 3 or not ratio > 1.0:
        return {"converging": None, "order": None, "extrapolated": None}
    e1, e2, e3 = values[-3:]
    d12, d23 = e1 - e2, e2 - e3
    # Changes at round-off level (e.g. an undisturbed height reproduced exactly): converged.
    if abs(d23) <= ROUND_OFF * max(1.0, abs(e3)):
        return {"converging": True, "order": None, "extrapolated": e3}
    if d12 == 0.0 or d12 * d23 < 0.0 or abs(d23) >= abs(d12):
        return {"converging": False, "order": None, "extrapolated": None}
    p = math.log(d12 / d23) / math.log(ratio)
    if p < MIN_ORDER:
        return {"converging": False, "order": p, "extrapolated": None}
    return {"converging": True, "order": p, "extrapolated": e3 + (e3 - e2) / (ratio**p - 1.0)}


def constant_ratio(cell_sizes: list[float]) -> float | None:
    """The common refinement ratio of the three finest meshes, or None."""
    if len(cell_sizes) < 3:
        return None
    h1, h2, h3 = cell_sizes[-3:]
    r12, r23 = h1 / h2, h2 / h3
    return r12 if abs(r12 - r23) <= 1e-6 * r12 and r12 > 1.0 else None


def summarise(runs: dict[float, dict[str, Any]],
              run_dirs: dict[float, Path] | None = None) -> dict[str, Any]:
    """Per case: every mesh's quantities and the Richardson estimate of each relative
    difference. ``runs`` maps cell size → the ``validation.json`` data of that mesh;
    ``run_dirs`` (cell size → the mesh's folder) adds each coarser mesh's
    ``profile_difference`` to the finest deposit (:func:`~axmpm.cases.column_collapse.deposit.profile_difference`)."""
    QUANTITIES = quantities()
    sizes = sorted(runs, reverse=True)
    ratio = constant_ratio(sizes)
    names = [c["name"] for c in runs[sizes[0]]["cases"]]
    cases = []
    for name in names:
        meshes = []
        for h in sizes:
            case = next(c for c in runs[h]["cases"] if c["name"] == name)
            entry = {"cell_size": h, "cells_per_radius": case["cells_per_radius"],
                     "aspect_ratio": case["aspect_ratio"], "status": case["status"],
                     "particles": case.get("particles"), "wall_seconds": case.get("wall_seconds"),
                     "run_dir": case.get("run_dir", f"cases/{name}")}
            for key, (_, value, rel) in QUANTITIES.items():
                entry[key] = value(case)
                entry[key + "_rel_diff"] = rel(case)
            meshes.append(entry)
        _add_profile_differences(name, sizes, meshes, run_dirs)
        estimates = {}
        for key in QUANTITIES:
            diffs = [m[key + "_rel_diff"] for m in meshes]
            ok = all(d is not None for d in diffs) and all(m["status"] == "completed" for m in meshes)
            estimates[key] = richardson(diffs, ratio) if ok and ratio else {
                "converging": None, "order": None, "extrapolated": None}
        cases.append({"name": name, "meshes": meshes, "richardson": estimates})
    return {"cell_sizes": sizes, "refinement_ratio": ratio, "cases": cases}


def _add_profile_differences(name: str, sizes: list[float], meshes: list[dict[str, Any]],
                             run_dirs: dict[float, Path] | None) -> None:
    """``profile_difference`` of every mesh's deposit to the finest one's (None where the
    column differs, e.g. a height rounded to another number of cells, or a run is missing)."""
    finest = sizes[-1]
    for h, m in zip(sizes, meshes):
        m["profile_difference"] = None
        if run_dirs is None or h == finest or m["status"] != "completed" or meshes[-1]["status"] != "completed":
            continue
        try:
            m["profile_difference"] = profile_difference(run_dirs[h] / m["run_dir"],
                                                         run_dirs[finest] / meshes[-1]["run_dir"])
        except (ValueError, OSError, KeyError):
            pass


def table(summary: dict[str, Any]) -> str:
    QUANTITIES = quantities()
    lines = ["| case | cells/R_i | a | " + " | ".join(f"{lab} | vs Lube" for lab, _, _ in QUANTITIES.values())
             + " | deposit vs finest | wall s |",
             "|---|---|---|" + "---|---|" * len(QUANTITIES) + "---|---|"]
    for c in summary["cases"]:
        for m in c["meshes"]:
            cells = " | ".join(f"{m[k]:.3f} | {pct(m[k + '_rel_diff'])}" for k in QUANTITIES)
            wall = m.get("wall_seconds")
            pd = m.get("profile_difference")
            pd_cell = "—" if pd is None else f"{100 * pd:.1f} %"
            lines.append(f"| {c['name']} | {m['cells_per_radius']:.0f} | {m['aspect_ratio']:.3g} | {cells} | "
                         f"{pd_cell} | {'—' if wall is None else f'{wall:.0f}'} |")
        est = []
        for k in QUANTITIES:
            r = c["richardson"][k]
            if r["converging"] is None:
                est.append("— | —")
            elif not r["converging"]:
                est.append("not converging | —")
            else:
                order = "—" if r["order"] is None else f"p = {r['order']:.2f}"
                est.append(f"{order} | {pct(r['extrapolated'])}")
        lines.append(f"| {c['name']} | → ∞ (Richardson) | | " + " | ".join(est) + " | | |")
    return "\n".join(lines)


def plot(summary: dict[str, Any], path: Path) -> None:
    """Relative difference to Lube et al. 2004 against cells per radius, one panel per
    quantity, one line per case."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    QUANTITIES = quantities()
    fig, axes = plt.subplots(1, len(QUANTITIES), figsize=(4.2 * len(QUANTITIES), 3.6), squeeze=False)
    for ax, (key, (label, _, _)) in zip(axes[0], QUANTITIES.items()):
        for c in summary["cases"]:
            n = [m["cells_per_radius"] for m in c["meshes"]]
            d = [100 * (m[key + "_rel_diff"] if m[key + "_rel_diff"] is not None else math.nan)
                 for m in c["meshes"]]
            (line,) = ax.plot(n, d, "o-", label=c["name"])
            ext = c["richardson"][key]
            if ext["converging"] and ext["extrapolated"] is not None:
                ax.axhline(100 * ext["extrapolated"], color=line.get_color(), ls=":", lw=0.9)
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_xscale("log")
        ax.set_xlabel("cells per initial radius")
        ax.set_ylabel("difference to Lube et al. 2004 (%)")
        ax.set_title(label, fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _reuse(folder: Path, cases: list[str], formulation: str, overrides: list[str] | None,
           builder: dict[str, Any]) -> dict[str, Any] | None:
    """The results of an earlier call with the same cases and settings in ``folder``, all
    completed, re-analysed with the current rules; None if anything differs or is missing."""
    case = _case()

    try:
        old = json.loads((folder / "validation.json").read_text())
    except (OSError, ValueError):
        return None
    expected = list(overrides or []) + [f"{k}={v}" for k, v in builder.items()]
    done = {c["name"]: c for c in old.get("cases", [])}
    if (old.get("formulation") != formulation or old.get("overrides") != expected
            or any(done.get(c, {}).get("status") != "completed" for c in cases)):
        return None
    return {**old, "cases": [{**done[c], **case.CASE.metrics(RunSpec(c, {}), folder / done[c].get("run_dir", f"cases/{c}"))}
                             for c in cases]}


def run_convergence(out: str | Path, cases: list[str], cell_sizes: list[float],
                    formulation: str = "axisymmetric", jobs: int | None = None,
                    overrides: list[str] | None = None, **builder: Any) -> dict[str, Any]:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    runs, folders = {}, {}
    for h in sorted(cell_sizes, reverse=True):
        mesh_builder = {**builder, "cell_size": h}
        folder = folders[h] = out / f"h{h * 1e3:g}mm"
        runs[h] = _reuse(folder, cases, formulation, overrides, mesh_builder) or _case().run_validation(
            folder, cases, formulation, jobs, overrides, report=False, **mesh_builder)
    summary = summarise(runs, folders)
    summary["formulation"] = formulation
    summary["overrides"] = list(overrides or []) + [f"{k}={v}" for k, v in builder.items()]
    (out / "convergence.json").write_text(json.dumps(summary, indent=2) + "\n")
    plot(summary, out / "convergence.png")
    text = f"""# axmpm mesh convergence: axisymmetric granular column collapse

Formulation: {formulation}. Cell sizes: {', '.join(f'{h * 1e3:g} mm' for h in summary['cell_sizes'])}.
Overrides: {', '.join(summary['overrides']) or 'none'}.

Differences are relative to Lube et al. (2004) at the simulated aspect ratio (heights are
rounded to whole cells). "Particle edge": outermost particle of the continuous deposit;
"one grain thick": where the solid thickness falls below one grain diameter (1.15 mm); both
rules in docs/validation.md. Richardson extrapolation (observed order p) of the three finest
meshes where the changes shrink monotonically. "Deposit vs finest": ∫|h − h_finest| dA /
∫ h_finest dA of the final solid-thickness profiles (2 mm bins) — the fraction of the
deposit volume placed differently from the finest mesh (— where the column's height was
rounded to another number of cells).

{table(summary)}

![convergence](convergence.png)

*Relative difference to Lube et al. 2004 against cells per radius; dotted: extrapolated limit.*

Runs: h<size>mm/cases/column_collapse/NAME (ParaView: particles.pvd); data: convergence.json.
"""
    (out / "convergence.md").write_text(text)
    return summary


def add_parser(sub: Any) -> argparse.ArgumentParser:
    p = sub.add_parser(NAME, help="run column-collapse cases on a sequence of meshes (Richardson extrapolation)")
    p.add_argument("--cases", default="a056",
                   help=f"comma-separated columns (default a056; known: {','.join(_case().CASES)})")
    p.add_argument("--cell-sizes", default=",".join(f"{h:g}" for h in DEFAULT_CELL_SIZES),
                   help="comma-separated cell sizes in m, coarse to fine (default 0.002,0.001,0.0005)")
    p.add_argument("--formulation", choices=["axisymmetric", "plane_strain"], default="axisymmetric")
    p.add_argument("--out", type=Path, default=Path("runs/convergence"), help="output folder (default runs/convergence)")
    p.add_argument("--jobs", type=int, default=0, help="parallel runs, 1 engine thread each (default: cores)")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                   help="override in every run, as for axmpm validate")
    return p


def main(args: argparse.Namespace) -> int:
    case = _case()
    cases = case.parse_cases(args.cases)
    try:
        sizes = [float(v) for v in args.cell_sizes.split(",") if v.strip()]
    except ValueError:
        raise RunError(f"--cell-sizes: expected comma-separated numbers in m, got {args.cell_sizes!r}") from None
    if not sizes or any(not (0.0 < h < 1.0) for h in sizes) or len(set(sizes)) != len(sizes):
        raise RunError(f"--cell-sizes: each must be in (0, 1) m and distinct, got {args.cell_sizes!r}")
    overrides, builder = case.split_overrides(args.overrides)
    if "cell_size" in builder:
        raise RunError("--set cell_size: use --cell-sizes for axmpm convergence")
    summary = run_convergence(args.out, cases, sizes, args.formulation, args.jobs or None, overrides, **builder)
    print(table(summary))
    print(f"convergence.json and convergence.md in {args.out}")
    failed = [f"{c['name']} at {m['cell_size']:g} m" for c in summary["cases"] for m in c["meshes"]
              if m["status"] != "completed"]
    if failed:
        print(f"error: run(s) did not complete: {', '.join(failed)}")
        return 3
    return 0
