"""What the column collapse's comparison with the laws is worth: the status line of its reports
and the runout scores against the primary law alone and against the closer law.

The default model (Drucker–Prager with the Mohr–Coulomb section and F-bar at the beads'
avalanche angle) was chosen among variants by its agreement with the axisymmetric laws of Lube
et al. 2004 and Lajeunesse et al. 2004, scored against whichever of the two is closer at each
aspect ratio (docs/validation.md). Its agreement with those laws is therefore calibration, not
validation, and the reports say so, with the score against one law beside the lenient
closer-law score."""

from __future__ import annotations

import math
from typing import Any

from .laws import TABLE_LAWS, primary_law

__all__ = ["STATUS", "law_scores", "status_text"]

#: The status line of every column-collapse report.
STATUS = ("**Status: calibrated.** The default model was chosen among variants by its agreement with "
          "the same axisymmetric laws (Lube et al. 2004 and Lajeunesse et al. 2004, each a scored against "
          "the closer of the two; docs/validation.md), so these comparisons are calibration, not "
          "validation. The laws are reported, not enforced.")


def law_scores(cases: list[dict[str, Any]], within: float = 0.10) -> dict[str, Any] | None:
    """Runout agreement of the analysed ``cases``: against the primary law alone (Lube et al.
    2004, or Lube et al. 2005 in plane strain) and against the closer of the tabulated laws at
    each aspect ratio: mean |relative difference| and how many lie within ``within``. None
    without an analysed case."""
    analysed = [c for c in cases if c.get("laws")]
    if not analysed:
        return None
    formulation = analysed[0].get("formulation") or "axisymmetric"
    primary = primary_law(formulation).key

    def diff(case: dict[str, Any], key: str) -> float | None:
        d = (case["laws"].get(key) or {}).get("runout_normalised_rel_diff")
        return abs(d) if d is not None and math.isfinite(d) else None

    single = [d for c in analysed if (d := diff(c, primary)) is not None]
    closer = [min(ds) for c in analysed
              if (ds := [d for law in TABLE_LAWS[formulation] if (d := diff(c, law.key)) is not None])]
    if not single or not closer:
        return None
    return {"primary": primary, "runs": len(analysed), "tolerance": within,
            "single_mean": sum(single) / len(single), "single_within": sum(d <= within for d in single),
            "single_runs": len(single),
            "closer_mean": sum(closer) / len(closer), "closer_within": sum(d <= within for d in closer),
            "closer_runs": len(closer)}


def status_text(cases: list[dict[str, Any]]) -> str:
    """The status paragraph of a report: :data:`STATUS` and the two scores of ``cases``."""
    scores = law_scores(cases)
    if scores is None:
        return STATUS
    formulation = next((c.get("formulation") for c in cases if c.get("laws")), None) or "axisymmetric"
    name = primary_law(formulation).label
    tol = f"{100 * scores['tolerance']:.0f} %"
    return (f"{STATUS}\n\nRunout against {name} alone: mean |difference| {100 * scores['single_mean']:.1f} %, "
            f"{scores['single_within']} of {scores['single_runs']} within {tol}. Against the closer law at each a "
            f"(the lenient measure the model was chosen by): mean {100 * scores['closer_mean']:.1f} %, "
            f"{scores['closer_within']} of {scores['closer_runs']} within {tol}.")
