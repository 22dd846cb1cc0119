"""The rigid-body contact on the quantity it exists for: the bearing capacity factor of a smooth
footing on weightless Tresca soil at the coarsest verification mesh (B/h = 10), strip and circle,
within 3 % of the exact values (Prandtl 2 + π; Shield / Eason & Shield 5.69; docs/physics.md §8).

A few seconds per run. The circle is the sensitive one: a contact that reaches further from the
body's surface (the covered nodes captured earlier) raises its N_c by several per cent.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from axmpm.cases.footing.scenario import EXACT, bearing_capacity_factor, footing_scenario, load_settlement
from axmpm.run.runner import run

TOLERANCE = 0.03


@pytest.mark.parametrize("formulation", ["plane_strain", "axisymmetric"])
def test_smooth_footing_bearing_capacity_at_ten_cells_per_width(tmp_path: Path, formulation: str) -> None:
    run(footing_scenario(formulation, "smooth", 10, "cpgimp"), tmp_path / "run", threads=1)
    settlement, nc = load_settlement(tmp_path / "run", formulation)
    factor = bearing_capacity_factor(settlement, nc)
    exact = EXACT[(formulation, "smooth")]
    assert factor is not None, "the footing did not reach the settlement window"
    assert abs(factor / exact - 1.0) <= TOLERANCE, f"N_c = {factor:.3f} against the exact {exact:.3f}"
