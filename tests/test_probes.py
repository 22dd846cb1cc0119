"""Point probes (``[[probes]]``): the moving least-squares estimate itself, the history columns
of a run against fields known in closed form (the geostatic stress of a column under gravity,
Terzaghi's pore pressure at a depth), the water's history columns, and bad input refused
naming the key."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from axmpm.cases import consolidation
from axmpm.cases.consolidation import exact
from axmpm.errors import ScenarioError
from axmpm.run.output import load_run
from axmpm.run.probes import interpolate
from axmpm.run.runner import run
from axmpm.scenario import Scenario

from conftest import run_cli


def _lattice(lo: tuple[float, float], hi: tuple[float, float], spacing: float) -> np.ndarray:
    xs = np.arange(lo[0] + spacing / 2, hi[0], spacing)
    ys = np.arange(lo[1] + spacing / 2, hi[1], spacing)
    return np.array([(x, y) for y in ys for x in xs])


def test_a_linear_field_is_reproduced_also_at_a_free_surface() -> None:
    rng = np.random.default_rng(1)
    x = _lattice((0.0, 0.0), (1.0, 1.0), 0.05) + rng.uniform(-0.01, 0.01, (400, 2))
    volume = rng.uniform(0.5, 1.5, len(x))
    field = np.column_stack([3.0 + 2.0 * x[:, 0] - 7.0 * x[:, 1], -x[:, 1]])
    for point in [(0.5, 0.5), (0.3, 1.0), (0.0, 0.0), (0.97, 0.42)]:  # inside, surface, corner, near a side
        value = interpolate(point, x, volume, field, 0.1)
        assert value == pytest.approx([3.0 + 2.0 * point[0] - 7.0 * point[1], -point[1]], abs=1e-12)
    # A curved field: the estimate's error is second order in the cell size.
    errors = [abs(interpolate((0.5, 0.5), x, volume, np.sin(3 * x[:, 1]), h) - np.sin(1.5)) for h in (0.2, 0.1)]
    assert errors[1] < 0.35 * errors[0], errors
    # No particle within one cell of the point: NaN; particles on one line only: their weighted mean.
    assert np.isnan(interpolate((5.0, 5.0), x, volume, field[:, 0], 0.1))
    line = np.array([[0.0, 0.0], [0.01, 0.0], [0.02, 0.0]])
    assert interpolate((0.01, 0.0), line, np.ones(3), np.array([1.0, 2.0, 6.0]), 0.1) == pytest.approx(
        (0.9 * 1 + 1.0 * 2 + 0.9 * 6) / 2.8)


def _gravity_column(probes: list[dict]) -> dict:
    """A 1 m × 0.2 m linear elastic column, rollers on its sides, fixed base, under gravity,
    starting from its geostatic stress (σ_yy = −ρ g depth; static from the start)."""
    return {
        "simulation": {"formulation": "plane_strain", "shape_function": "linear", "end_time": 2e-3,
                       "output_interval": 1e-3, "gravity": [0.0, -9.81]},
        "grid": {"origin": [0.0, 0.0], "extent": [0.4, 1.2], "cell_size": 0.05},
        "materials": {"soil": {"model": "linear_elastic", "density": 2000.0, "youngs_modulus": 1e7,
                               "poisson_ratio": 0.25}},
        "bodies": [{"material": "soil", "min": [0.0, 0.0], "max": [0.2, 1.0], "initial_stress": "geostatic"}],
        "boundaries": {"left": "roller", "bottom": "fixed"},
        "walls": [{"axis": "x", "position": 0.2, "material_side": "negative", "condition": "roller"}],
        "probes": probes,
    }


def test_probe_records_the_geostatic_stress_of_a_column(tmp_path: Path) -> None:
    probes = [{"name": "mid", "point": [0.1, 0.4]}, {"name": "surface", "point": [0.05, 1.0]}]
    run(Scenario.from_dict(_gravity_column(probes)), tmp_path / "run")
    history = load_run(tmp_path / "run").history
    assert len(history["time"]) == 3
    for name, depth in (("mid", 0.6), ("surface", 0.0)):
        sigma_yy = -2000.0 * 9.81 * depth
        k0 = 0.25 / 0.75
        # Within 0.5 % of ρ g H: the column stays at its geostatic state for these few steps.
        assert np.allclose(history[f"{name}.stress_yy"], sigma_yy, atol=5e-3 * 2000 * 9.81), history[f"{name}.stress_yy"]
        assert np.allclose(history[f"{name}.stress_xx"], k0 * sigma_yy, atol=5e-3 * 2000 * 9.81)
        assert np.allclose(history[f"{name}.displacement_x"], 0.0, atol=1e-9)
        assert f"{name}.pore_pressure" not in history  # a dry run


def test_probe_follows_terzaghi_in_the_consolidating_column(tmp_path: Path) -> None:
    data = consolidation.column_scenario("plane_strain", 10, conductivity=consolidation.QUICK_CONDUCTIVITY,
                                         as_dict=True)
    cv = consolidation.consolidation_coefficient("consolidation", consolidation.QUICK_CONDUCTIVITY)
    data["simulation"]["end_time"] = 0.5 / cv
    data["simulation"]["output_interval"] = 0.05 / cv
    # At the depth of a cell centre (the pressure is constant over each cell).
    data["probes"] = [{"name": "deep", "point": [0.05, 0.25]}]
    run(Scenario.from_dict(data), tmp_path / "run")
    history = load_run(tmp_path / "run").history
    u0 = exact.undrained_pressure(consolidation.LOAD, consolidation.POROSITY, consolidation.WATER_BULK_MODULUS,
                                  consolidation.OEDOMETER_MODULUS)
    tv = history["time"] * cv
    later = tv > 0.04
    expected = np.array([exact.pressure(0.75, t)[0] for t in tv[later]])
    # Within 1 % of u₀ at every row (the case holds the isochrones to 3 %; at a cell centre the
    # pressure is closer).
    assert np.max(np.abs(history["deep.pore_pressure"][later] / u0 - expected)) < 0.01
    assert np.all(np.isfinite(history["deep.stress_yy"]))
    # The water's columns: the outflow grows as the column drains, the drag dissipates.
    assert history["water_outflow"][0] == 0.0 and np.all(np.diff(history["water_outflow"]) > 0.0)
    assert np.all(np.diff(history["drag_dissipation"]) > 0.0) and np.all(history["water_kinetic_energy"] >= 0.0)


@pytest.mark.parametrize("probes, key, message", [
    ([{"name": "a", "point": [0.1, 9.0]}], "probes.0.point.1", "must lie inside the grid"),
    ([{"name": "a", "point": [-0.1, 0.5]}], "probes.0.point.0", "must lie inside the grid"),
    ([{"name": "a", "point": [0.1, 0.5]}, {"name": "a", "point": [0.1, 0.6]}], "probes.1.name", "duplicate"),
    ([{"name": "a.b", "point": [0.1, 0.5]}], "probes.0.name", "should match"),
])
def test_bad_probes_name_the_key(probes: list[dict], key: str, message: str) -> None:
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(_gravity_column(probes))
    text = str(info.value)
    assert key in text and message in text, text


def test_command_line_exits_2_on_a_probe_outside_the_grid(tmp_path: Path) -> None:
    import tomli_w

    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(_gravity_column([{"name": "a", "point": [0.1, 9.0]}])))
    result = run_cli("check", path)
    assert result.returncode == 2, result.stderr
    assert "probes.0.point.1" in result.stderr and "Traceback" not in result.stderr
