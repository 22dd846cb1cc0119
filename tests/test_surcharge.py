"""Initial stress by value, surcharges on a free surface, and the geostatic stress of stacked
bodies (docs/physics.md §8, "In-situ stress and surcharge")."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import axmpm
from axmpm.errors import ScenarioError
from axmpm.run.output import load_run
from axmpm.scenario import Scenario

S_V0 = 66e3  # Pa, the in-situ stress of the cone penetration test's clay (compression)


def weightless_layer(formulation: str, **top: object) -> dict:
    """A weightless Tresca layer 0.5 m × 0.5 m at σ_v = σ_h = −66 kPa, held by a 66 kPa
    surcharge on its top and rollers on its sides and base; 1000 steps of a fixed Δt."""
    return {
        "simulation": {"formulation": formulation, "shape_function": "cpgimp", "gravity": [0.0, 0.0],
                       "time_step": 5e-5, "end_time": 0.05, "output_interval": 0.05,
                       "volumetric_averaging": "cell"},
        "grid": {"extent": [0.5, 0.75], "cell_size": 0.05},
        "materials": {"clay": {"model": "mohr_coulomb", "density": 1800.0, "youngs_modulus": 5.4e6,
                               "poisson_ratio": 0.49, "friction_angle": 0.0, "cohesion": 18e3}},
        "bodies": [{"material": "clay", "min": [0.0, 0.0], "max": [0.5, 0.5],
                    "initial_stress": {"vertical": -S_V0, "horizontal": -S_V0}}],
        "boundaries": {"left": "roller", "right": "roller", "bottom": "roller"},
        "surcharges": [{"name": "overburden", "pressure": S_V0, "level": 0.5, **top}],
    }


@pytest.mark.parametrize("formulation", ["plane_strain", "axisymmetric"])
def test_a_surcharge_holds_a_weightless_layer_at_its_in_situ_stress(tmp_path: Path, formulation: str) -> None:
    """After 1000 steps every particle's σ_xx, σ_yy and σ_zz is within 1 % of −66 kPa (the
    surcharge balances the layer's stress at its top; without it the top would unload), and
    the history reports the surcharge's force: −q B per metre, −q π R² for the ring."""
    summary = axmpm.run(weightless_layer(formulation), tmp_path / "run", threads=1, progress=False)
    assert summary["status"] == "completed" and summary["steps"] == 1000
    run = load_run(tmp_path / "run")
    stress = run.last.stress
    for component in (0, 1, 2):
        error = np.abs(stress[:, component] + S_V0).max() / S_V0
        assert error < 0.01, (component, error)
    area = 0.5 if formulation == "plane_strain" else math.pi * 0.5**2
    assert run.history["overburden.applied_force_y"][-1] == pytest.approx(-S_V0 * area, rel=1e-12)


def test_without_the_surcharge_the_layer_does_not_stay_at_rest(tmp_path: Path) -> None:
    """The check above can fail: the same layer without its surcharge unloads at the top."""
    data = weightless_layer("plane_strain")
    data.pop("surcharges")
    axmpm.run(data, tmp_path / "run", threads=1, progress=False)
    stress = load_run(tmp_path / "run").last.stress
    assert np.abs(stress[:, 1] + S_V0).max() / S_V0 > 0.05


def test_the_surcharge_ramps_in_with_gravity(tmp_path: Path) -> None:
    """With gravity_ramp_time, the surcharge's force grows in proportion to the time."""
    data = weightless_layer("plane_strain")
    data["simulation"].update(gravity_ramp_time=0.1, history_interval=0.01)
    axmpm.run(data, tmp_path / "run", threads=1, progress=False)
    history = load_run(tmp_path / "run").history
    expect = -S_V0 * 0.5 * np.minimum(history["time"] / 0.1, 1.0)
    assert np.allclose(history["overburden.applied_force_y"], expect, rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("formulation", ["plane_strain", "axisymmetric"])
def test_stacked_geostatic_bodies_count_the_weight_above(tmp_path: Path, formulation: str) -> None:
    """Sand under a 2 m clay layer and a 10 kPa surcharge: the sand starts at
    σ_v = q + ρ_c g 2 m + ρ_s g (its depth in the sand), σ_h = K0 σ_v with the sand's K0, the
    clay at q + ρ_c g (its depth); geostatic with a surcharge. Exact to round-off (a layer's
    particles carry its weight per unit width exactly)."""
    g, rho_c, rho_s, q = 9.81, 1800.0, 2000.0, 10e3
    data = {
        "simulation": {"formulation": formulation, "shape_function": "cpgimp", "gravity": [0.0, -g],
                       "end_time": 1e-3, "output_interval": 1e-3},
        "grid": {"extent": [1.0, 4.0], "cell_size": 0.25},
        "materials": {
            "clay": {"model": "linear_elastic", "density": rho_c, "youngs_modulus": 1e7, "poisson_ratio": 0.4},
            "sand": {"model": "linear_elastic", "density": rho_s, "youngs_modulus": 5e7, "poisson_ratio": 0.25}},
        "bodies": [
            {"name": "sand", "material": "sand", "min": [0.0, 0.0], "max": [1.0, 1.5], "initial_stress": "geostatic"},
            {"name": "clay", "material": "clay", "min": [0.0, 1.5], "max": [1.0, 3.5], "initial_stress": "geostatic"}],
        "boundaries": {"left": "roller", "right": "roller", "bottom": "fixed"},
        "surcharges": [{"pressure": q, "level": 3.5}],
    }
    s = Scenario.from_dict(data)
    from axmpm._core import Simulation

    sim = Simulation(s.engine_json(), 1)
    y, stress = np.asarray(sim.positions())[:, 1], np.asarray(sim.stresses())
    sand = np.asarray(sim.material_ids()) == sim.material_names().index("sand")
    expect_v = np.where(sand, -(q + rho_c * g * 2.0 + rho_s * g * (1.5 - y)), -(q + rho_c * g * (3.5 - y)))
    k0 = np.where(sand, 0.25 / 0.75, 0.4 / 0.6)
    assert np.allclose(stress[:, 1], expect_v, rtol=1e-12)
    assert np.allclose(stress[:, 0], k0 * expect_v, rtol=1e-12)
    assert np.allclose(stress[:, 2], k0 * expect_v, rtol=1e-12)
    # The example, written out: the top of the sand carries the clay (35.3 kPa), not
    # only its own half particle.
    assert stress[sand, 1].max() < -(q + rho_c * g * 2.0)


BAD = [
    ({"surcharges": [{"pressure": -1.0, "level": 0.5}]}, "surcharges.0.pressure", ">= 0"),
    ({"surcharges": [{"pressure": 1.0, "level": 2.0}]}, "surcharges.0.level", "must lie in the grid"),
    ({"surcharges": [{"pressure": 1.0, "level": 0.5, "range": [0.4, 0.1]}]}, "surcharges.0.range", "x0 < x1"),
    ({"surcharges": [{"pressure": 1.0, "level": 0.5, "range": [0.0, 0.9]}]}, "surcharges.0.range",
     "must lie in the grid"),
    ({"surcharges": [{"name": "bottom", "pressure": 1.0, "level": 0.5}]}, "surcharges.0.name", "duplicate"),
]


@pytest.mark.parametrize(("change", "key", "text"), BAD)
def test_bad_surcharges_are_refused_naming_the_key(change: dict, key: str, text: str) -> None:
    data = weightless_layer("plane_strain")
    data.update(change)
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(data)
    errors = dict(info.value.errors)
    assert key in errors and text in errors[key], errors


def test_geostatic_without_gravity_is_refused_naming_the_key() -> None:
    data = weightless_layer("plane_strain")
    data["bodies"][0]["initial_stress"] = "geostatic"
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(data)
    errors = dict(info.value.errors)
    assert "needs gravity" in errors["bodies.0.initial_stress"]


def test_a_surcharge_off_the_surface_is_refused_by_the_engine() -> None:
    """A level with no material surface on it (inside the layer's air above): the engine
    names the surcharge."""
    data = weightless_layer("plane_strain")
    data["surcharges"][0]["level"] = 0.7
    from axmpm._core import Simulation

    with pytest.raises(Exception, match=r"surcharges\[0\]: no material has its surface at level = 0.7"):
        Simulation(Scenario.from_dict(data).engine_json(), 1)


def test_initial_stress_by_components_is_given_to_every_particle() -> None:
    data = weightless_layer("axisymmetric")
    data["bodies"][0]["initial_stress"] = {"xx": -10e3, "yy": -20e3, "zz": -30e3, "xy": 5e3}
    from axmpm._core import Simulation

    stress = np.asarray(Simulation(Scenario.from_dict(data).engine_json(), 1).stresses())
    assert np.all(stress == np.array([-10e3, -20e3, -30e3, 5e3]))
