"""``axmpm demo``: the a = 0.56 axisymmetric granular column collapse at default resolution
(2 mm cells, R_i = 3 cm), its free-surface profiles and its runout and height against
Lube et al. 2004. ``axmpm demo --column``: the 1D column in compression at small
deformation (ρ0 g H/E = 0.01), linear MPM, axisymmetric, against the exact solution of
PHYSICS.md §4."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .column import ColumnErrors, column_errors, column_scenario
from .output import load_run
from .runner import run


@dataclass
class DemoResult:
    out: Path
    summary: dict[str, Any]
    errors: ColumnErrors | None


@dataclass
class CollapseDemoResult:
    out: Path
    summary: dict[str, Any]
    case: dict[str, Any] | None  # validation.json-style entry (metrics + laws)
    figure: Path | None
    report: Path | None


def run_demo(out: str | Path = "runs/demo", overwrite: bool = False, threads: int = 0,
             progress: bool | None = None) -> DemoResult:
    """Run the demo column and compare its last frame with the exact solution."""
    scenario = column_scenario(
        "axisymmetric", "linear", "compression", cells_along=32, cells_across=2, load_ratio=0.01
    )
    summary = run(scenario, out, threads=threads, overwrite=overwrite, progress=progress)
    errors = column_errors(load_run(out)) if summary["status"] == "completed" else None
    return DemoResult(Path(out), summary, errors)


def run_collapse_demo(out: str | Path = "runs/demo", overwrite: bool = False, threads: int = 0,
                      progress: bool | None = None, **builder: Any) -> CollapseDemoResult:
    """Run the a = 0.56 collapse; write ``profiles.png`` and ``demo.json``/``demo.md`` in ``out``."""
    from .collapse import collapse_scenario
    from .validate import case_result, plot_profiles, results_table

    out = Path(out)
    scenario = collapse_scenario(0.56, **builder)
    summary = run(scenario, out, threads=threads, overwrite=overwrite, progress=progress)
    if summary["status"] != "completed":
        return CollapseDemoResult(out, summary, None, None, None)
    case = case_result("a056", out, 0.56, summary["wall_seconds"])
    figure = out / "profiles.png"
    plot_profiles([case], figure)
    (out / "demo.json").write_text(json.dumps(case, indent=2) + "\n")
    report = out / "demo.md"
    report.write_text("# axmpm demo: granular column collapse, a = 0.56\n\n"
                      + results_table([case]) + "\n\n![profiles](profiles.png)\n\n"
                      "At 15 cells per radius H_i is rounded to 16 mm (a = 0.533); finer meshes and the mesh "
                      "convergence of the runout: docs/validation.md.\n")
    return CollapseDemoResult(out, summary, case, figure, report)
