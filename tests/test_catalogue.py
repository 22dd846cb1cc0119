"""One list of what the engine offers (``axmpm.catalogue``), and the scenario schema covers it:
every engine material model has a ``[materials.NAME]`` section, every region shape a body class,
and the schema's formulations and schemes are the engine's."""

from __future__ import annotations

import typing

import pytest

from axmpm import catalogue
from axmpm.scenario import MATERIAL_MODELS, REGION_SHAPES, Scenario
from axmpm.scenario.sections import Simulation


def test_catalogue_has_the_four_lists() -> None:
    lists = catalogue.catalogue()
    assert set(lists) == {"formulations", "interpolation_schemes", "material_models", "region_shapes"}
    assert all(lists[k] and len(set(lists[k])) == len(lists[k]) for k in lists)


def test_every_engine_material_model_has_a_scenario_schema() -> None:
    assert set(MATERIAL_MODELS) >= set(catalogue.material_models())
    for name in catalogue.material_models():
        assert MATERIAL_MODELS[name].model_fields["model"].annotation == typing.Literal[name]


def test_every_engine_region_shape_has_a_body_schema() -> None:
    assert set(REGION_SHAPES) >= set(catalogue.region_shapes())


def test_schema_choices_are_the_engines() -> None:
    props = Scenario.model_json_schema()["$defs"]["Simulation"]["properties"]
    assert props["formulation"]["enum"] == list(catalogue.formulations())
    assert props["shape_function"]["enum"] == list(catalogue.interpolation_schemes())


def test_a_name_the_engine_does_not_know_is_refused_with_the_choices() -> None:
    from pathlib import Path

    from axmpm.scenario import ScenarioError, apply_overrides, read_toml

    data = read_toml(Path(__file__).resolve().parents[1] / "examples" / "column_collapse_a056.toml")
    bad = ['simulation.formulation="axisymetric"', "simulation.shape_function=3", 'materials.sand.model="mohr_coulmb"']
    with pytest.raises(ScenarioError) as err:
        Scenario.from_dict(apply_overrides(data, bad))
    assert err.value.render().splitlines() == [
        "error: simulation.formulation: must be 'plane_strain' or 'axisymmetric' (got 'axisymetric'); "
        "did you mean 'axisymmetric'?",
        "error: simulation.shape_function: must be 'linear', 'ugimp', 'cpgimp' or 'cpdi2' (got 3)",
        "error: materials.sand.model: unknown material model 'mohr_coulmb'; expected one of 'linear_elastic', "
        "'neo_hookean', 'mohr_coulomb', 'von_mises', 'granular_fluidity', 'drucker_prager'; did you mean "
        "'mohr_coulomb'?",
    ]


@pytest.mark.parametrize("model,extra,k0", [
    ("linear_elastic", {}, 0.25 / 0.75),
    ("neo_hookean", {}, 0.25 / 0.75),
    ("mohr_coulomb", {"friction_angle": 30.0}, 0.5),
    ("von_mises", {"yield_stress": 4e8}, 0.25 / 0.75),
    ("drucker_prager", {"friction": 0.4}, 0.6),
])
def test_k0_default_is_the_models(model: str, extra: dict, k0: float) -> None:
    material = MATERIAL_MODELS[model](model=model, density=1000.0, youngs_modulus=1e6, poisson_ratio=0.25, **extra)
    assert material.default_k0() == pytest.approx(k0)
