"""The column scenario builder and error measures (no engine needed)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from axmpm.cases.column_1d import exact
from axmpm.cases.column_1d import column_errors, column_geometry, column_scenario


@pytest.mark.parametrize("formulation", ["plane_strain", "axisymmetric"])
@pytest.mark.parametrize("mode", ["compression", "tension"])
def test_column_scenarios_are_valid(formulation: str, mode: str) -> None:
    s = column_scenario(formulation, "cpdi2", mode, cells_along=10, load_ratio=0.5)
    geo = column_geometry(s)
    assert geo.mode == mode and geo.height == pytest.approx(1.0)
    assert s.materials["column"].poisson_ratio == 0.0
    assert s.simulation.gravity_ramp_time > 0 and s.simulation.end_time > s.simulation.gravity_ramp_time
    if mode == "tension":
        # room below the column for the exact elongation (29 % of H at s0 = 0.5)
        stretch = -exact.vertical_displacement(0.0, 1.0, 1000.0, 10.0, geo.youngs_modulus, "tension")
        assert geo.base - s.grid.origin[1] > stretch
        assert s.boundaries.top.condition == "fixed"
        assert s.bodies[0].max[1] == pytest.approx(s.grid.origin[1] + s.grid.extent[1])
    else:
        assert s.boundaries.bottom.condition == "fixed" and geo.base == s.grid.origin[1]


def test_offset_axisymmetric_column_has_inner_wall() -> None:
    s = column_scenario("axisymmetric", offset=0.5, cells_along=20, cells_across=2)
    assert s.grid.origin[0] == 0.0 and s.grid.extent[0] == pytest.approx(0.6)
    assert len(s.walls) == 1
    wall = s.walls[0]
    assert (wall.axis, wall.position, wall.material_side, wall.condition) == ("x", 0.5, "positive", "roller")
    assert s.bodies[0].min[0] == pytest.approx(0.5)


def test_offset_must_be_on_the_grid() -> None:
    with pytest.raises(ValueError, match="whole number of cells"):
        column_scenario("axisymmetric", offset=0.51, cells_along=20)


def test_column_errors_of_the_exact_state_are_zero() -> None:
    s = column_scenario("plane_strain", mode="compression", cells_along=8, load_ratio=0.3)
    geo = column_geometry(s)
    X0 = np.column_stack([np.full(50, 0.05), np.linspace(0.01, 0.99, 50)])
    args = (geo.height, geo.density, geo.gravity, geo.youngs_modulus, "compression")
    x = X0.copy()
    x[:, 1] = exact.vertical_position(X0[:, 1], *args)
    stress = np.zeros((50, 4))
    stress[:, 1] = exact.vertical_stress(X0[:, 1], *args)
    frame = SimpleNamespace(X0=X0, x=x, stress=stress)
    errors = column_errors(frame, s)
    assert errors.stress_l2 == pytest.approx(0, abs=1e-14)
    assert errors.displacement_l2 == pytest.approx(0, abs=1e-12)
    stress[:, 1] *= 1.01
    assert column_errors(frame, s).stress_l2 == pytest.approx(0.01)
    assert column_errors(frame, s).stress_max == pytest.approx(0.01)
