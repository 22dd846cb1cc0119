"""``axmpm demo --column``: the 1D column in compression at small deformation
(ρ0 g H/E = 0.01), linear MPM, axisymmetric, against the exact solution of docs/physics.md §4."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ...run.output import load_run
from ...run.runner import run
from .scenario import ColumnErrors, column_errors, column_scenario


@dataclass
class DemoResult:
    out: Path
    summary: dict[str, Any]
    errors: ColumnErrors | None


def run_demo(out: str | Path = "runs/demo", overwrite: bool = False, threads: int = 0,
             progress: bool | None = None) -> DemoResult:
    """Run the demo column and compare its last frame with the exact solution."""
    scenario = column_scenario(
        "axisymmetric", "linear", "compression", cells_along=32, cells_across=2, load_ratio=0.01
    )
    summary = run(scenario, out, threads=threads, overwrite=overwrite, progress=progress)
    errors = column_errors(load_run(out)) if summary["status"] == "completed" else None
    return DemoResult(Path(out), summary, errors)
