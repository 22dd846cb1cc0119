"""Verification: the 1D column under self-weight against its exact solution (docs/physics.md §4).

Small deformation (ρ0 g H/E = 0.01), original (linear) MPM, 32 cells along the column,
2 across, 2×2 particles per cell, in plane strain, in axisymmetric touching the axis, and in
axisymmetric with the inner face 10 column widths from the axis.

Linear MPM's particle stress is constant in each cell, so even a perfect static solution
differs from the exact linear profile by ±ρ0 g h/4 at the particles: a relative L2 error of
about √3/(4·32) ≈ 1.4 % here, which is why 2 % is the bound (20 cells would give ≈ 2.2 %).
"""

from __future__ import annotations

from pathlib import Path

import pytest

import axmpm
from axmpm.cases.column_1d import column_errors, column_scenario, stress_difference

CELLS_ALONG = 32
CELLS_ACROSS = 2
WIDTH = CELLS_ACROSS / CELLS_ALONG  # m, H = 1 m

CASES = {
    "plane_strain": dict(formulation="plane_strain"),
    "axisymmetric_axis": dict(formulation="axisymmetric", offset=0.0),
    "axisymmetric_offset": dict(formulation="axisymmetric", offset=10 * WIDTH),
}


@pytest.fixture(scope="module")
def column_runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, axmpm.run.output.Run]:
    folder = tmp_path_factory.mktemp("column")
    runs = {}
    for name, kwargs in CASES.items():
        scenario = column_scenario(
            shape_function="linear", mode="compression", cells_along=CELLS_ALONG, cells_across=CELLS_ACROSS,
            load_ratio=0.01, **kwargs,
        )
        summary = axmpm.run(scenario, folder / name, progress=False)
        assert summary["status"] == "completed", summary["message"]
        runs[name] = axmpm.load_run(folder / name)
    return runs


@pytest.mark.parametrize("name", list(CASES))
def test_vertical_stress_matches_exact(column_runs, name: str) -> None:
    errors = column_errors(column_runs[name])
    assert errors.stress_l2 < 0.02, str(errors)
    assert errors.displacement_l2 < 0.02, str(errors)


@pytest.mark.parametrize("name", list(CASES))
def test_column_is_at_rest(column_runs, name: str) -> None:
    history = column_runs[name].history
    # kinetic energy at the end is negligible next to the work done by gravity
    assert history["kinetic_energy"][-1] < 1e-5 * history["gravity_work"][-1]


@pytest.mark.parametrize("name", ["axisymmetric_axis", "axisymmetric_offset"])
def test_axisymmetric_equals_plane_strain(column_runs, name: str) -> None:
    assert stress_difference(column_runs[name], column_runs["plane_strain"], component=1) < 0.01


def test_lateral_stress_is_zero(column_runs) -> None:
    # nu = 0: the radial, hoop and shear stresses vanish in uniaxial strain
    for run in column_runs.values():
        stress = run.frames[-1].stress
        scale = abs(stress[:, 1]).max()
        assert abs(stress[:, [0, 2, 3]]).max() < 1e-6 * scale


def test_offset_column_geometry(column_runs) -> None:
    frame = column_runs["axisymmetric_offset"].frames[-1]
    assert frame.X0[:, 0].min() > 10 * WIDTH
    assert frame.X0[:, 0].max() < 11 * WIDTH
