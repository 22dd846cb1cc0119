"""Verification at large deformation (ρ0 g H/E = 0.5, docs/physics.md §4): CPDI2 matches the exact
neo-Hookean column in compression (38 % shortening at the base) and in tension (62 % stretch
at the top), in plane strain and axisymmetric away from the axis. The seed paper found that
only CPDI2 matches in tension; original MPM and uGIMP depart in compression.
"""

from __future__ import annotations

import pytest

import axmpm
from axmpm.cases.column_1d import column_errors, column_scenario, stress_difference

CELLS_ALONG = 20
WIDTH = 2 / CELLS_ALONG


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[tuple[str, str], axmpm.run.output.Run]:
    folder = tmp_path_factory.mktemp("large")
    result = {}
    for mode in ("compression", "tension"):
        for formulation, offset in (("plane_strain", 0.0), ("axisymmetric", 10 * WIDTH)):
            scenario = column_scenario(formulation, "cpdi2", mode, cells_along=CELLS_ALONG, load_ratio=0.5,
                                       offset=offset)
            out = folder / f"{mode}_{formulation}"
            summary = axmpm.run(scenario, out, progress=False)
            assert summary["status"] == "completed", summary["message"]
            result[mode, formulation] = axmpm.load_run(out)
    return result


@pytest.mark.parametrize("mode", ["compression", "tension"])
@pytest.mark.parametrize("formulation", ["plane_strain", "axisymmetric"])
def test_cpdi2_matches_exact(runs, mode: str, formulation: str) -> None:
    errors = column_errors(runs[mode, formulation])
    assert errors.stress_l2 < 0.02, str(errors)
    assert errors.displacement_l2 < 0.02, str(errors)


@pytest.mark.parametrize("mode", ["compression", "tension"])
def test_axisymmetric_equals_plane_strain(runs, mode: str) -> None:
    assert stress_difference(runs[mode, "axisymmetric"], runs[mode, "plane_strain"]) < 0.01
