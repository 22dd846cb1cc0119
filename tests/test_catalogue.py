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
    fields = Simulation.model_fields
    assert typing.get_args(fields["formulation"].annotation) == catalogue.formulations()
    assert typing.get_args(fields["shape_function"].annotation) == catalogue.interpolation_schemes()
    schema = Scenario.model_json_schema()
    assert set(schema["$defs"]["Simulation"]["properties"]["shape_function"]["enum"]) == set(
        catalogue.interpolation_schemes())


@pytest.mark.parametrize("model,extra,k0", [
    ("linear_elastic", {}, 0.25 / 0.75),
    ("neo_hookean", {}, 0.25 / 0.75),
    ("mohr_coulomb", {"friction_angle": 30.0}, 0.5),
])
def test_k0_default_is_the_models(model: str, extra: dict, k0: float) -> None:
    material = MATERIAL_MODELS[model](model=model, density=1000.0, youngs_modulus=1e6, poisson_ratio=0.25, **extra)
    assert material.default_k0() == pytest.approx(k0)
