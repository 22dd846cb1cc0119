"""``axmpm demo``: the a = 0.56 axisymmetric granular column collapse at 30 cells per radius
(1 mm cells, R_i = 3 cm: the mesh on which a ≤ 0.8 is converged, docs/validation.md), its
free-surface profiles and its runout and height against Lube et al. 2004 (the ``a056`` run of
the ``column_collapse`` case, in a single run folder)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ...run.runner import run
from .case import CASES, case_result, plot_profiles, results_table
from .scenario import DEFAULTS, collapse_scenario

#: Cell size of the demo, m: 30 cells per R_i = 3 cm, where a ≤ 0.8 is converged (docs/validation.md).
DEMO_CELL_SIZE = 0.001


@dataclass
class CollapseDemoResult:
    out: Path
    summary: dict[str, Any]
    case: dict[str, Any] | None  # validation.json-style entry (metrics + laws)
    figure: Path | None
    report: Path | None


def model_description(builder: dict[str, Any] | None = None) -> str:
    """One line naming the collapse's material model and its parameters, from the builder's
    defaults updated by ``builder``."""
    import math

    p = {**DEFAULTS, **(builder or {})}
    model = p["material_model"]
    if model == "drucker_prager":
        mu = p["friction_coefficient"]
        text = f"Drucker-Prager (mu = {mu:.3f} = tan {math.degrees(math.atan(mu)):.1f} deg"
        text += ", Mohr-Coulomb section)" if p["mohr_coulomb_section"] else ")"
    elif model == "granular_fluidity":
        text = f"nonlocal granular fluidity (mu_s = {p['static_friction']})"
    else:
        text = f"Mohr-Coulomb (phi {p['friction_angle']:g}, psi {p['dilation_angle']:g})"
    if p["volumetric_averaging"] == "cell":
        text += ", F-bar"
    return text


def run_collapse_demo(out: str | Path = "runs/demo", overwrite: bool = False, threads: int = 0,
                      progress: bool | None = None, **builder: Any) -> CollapseDemoResult:
    """Run the a = 0.56 collapse; write ``profiles.png`` and ``demo.json``/``demo.md`` in ``out``."""
    out = Path(out)
    builder.setdefault("cell_size", DEMO_CELL_SIZE)
    scenario = collapse_scenario(CASES["a056"], **builder)
    summary = run(scenario, out, threads=threads, overwrite=overwrite, progress=progress)
    if summary["status"] != "completed":
        return CollapseDemoResult(out, summary, None, None, None)
    case = {"name": "a056", **case_result("a056", out, CASES["a056"]), "status": summary["status"],
            "message": summary["message"], "wall_seconds": summary["wall_seconds"], "run_dir": str(out)}
    figure = out / "profiles.png"
    plot_profiles([case], figure)
    (out / "demo.json").write_text(json.dumps(case, indent=2) + "\n")
    report = out / "demo.md"
    report.write_text("# axmpm demo: granular column collapse, a = 0.56\n\n"
                      + results_table([case]) + "\n\n![profiles](profiles.png)\n\n"
                      f"{case['cells_per_radius']:.0f} cells per radius; H_i is rounded to whole cells "
                      f"(a = {case['aspect_ratio']:.3f}). Other meshes and the mesh convergence of the "
                      "runout: docs/validation.md.\n")
    return CollapseDemoResult(out, summary, case, figure, report)
