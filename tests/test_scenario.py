"""Scenario validation: every bad input is reported under its dotted key."""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from axmpm.scenario import Scenario, ScenarioError, apply_overrides, parse_value, read_toml

from conftest import EXAMPLES, TINY_TOML


def base() -> dict:
    return tomllib.loads(TINY_TOML)


def errors_for(overrides: list[str], data: dict | None = None) -> ScenarioError:
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(apply_overrides(data or base(), overrides))
    return info.value


# --------------------------------------------------------------------------- valid input


def test_defaults_are_resolved() -> None:
    s = Scenario.from_dict(base())
    sim = s.simulation
    assert sim.cfl == 0.4 and sim.update_scheme == "musl" and sim.flip_fraction == 0.99
    assert sim.damping == 0.0 and sim.time_step == 0.0 and sim.gravity_ramp_time == 0.0
    assert s.grid.origin == (0.0, 0.0)
    assert s.boundaries.right.condition == "free" and s.boundaries.top.condition == "free"
    assert s.boundaries.left.condition == "roller" and s.boundaries.left.coefficient == 0.0
    assert s.walls == []
    body = s.bodies[0]
    assert body.particles_per_cell == 2 and body.initial_stress == "zero"
    assert body.k0 == pytest.approx(0.3 / 0.7)  # nu / (1 - nu)
    assert s.particle_count() == 5 * 10 * 4


def test_default_gravity() -> None:
    data = base()
    del data["simulation"]["gravity"]
    assert Scenario.from_dict(data).simulation.gravity == (0.0, -9.81)


def test_mohr_coulomb_k0_default_is_jaky() -> None:
    data = apply_overrides(base(), ['materials.soil.model="mohr_coulomb"', "materials.soil.friction_angle=30"])
    s = Scenario.from_dict(data)
    assert s.bodies[0].k0 == pytest.approx(1 - math.sin(math.radians(30)))
    assert s.materials["soil"].dilation_angle == 0.0 and s.materials["soil"].tension_cutoff == 0.0


@pytest.mark.parametrize("key", ["recompaction", "cell_averaged_disconnection", "inertial_friction_angle"])
def test_a_retired_mohr_coulomb_key_is_refused_by_name(key: str) -> None:
    err = errors_for(MOHR_COULOMB + [f"materials.soil.{key}=true"])
    assert err.errors == [(f"materials.soil.{key}",
                           "is not a mohr_coulomb parameter (retired; see docs/studies/granular-variants.md)")]
    # Another model does not know the key at all.
    assert "unknown key" in dict(errors_for([f"materials.soil.{key}=true"]).errors)[f"materials.soil.{key}"]


def test_explicit_k0_is_kept() -> None:
    assert Scenario.from_dict(apply_overrides(base(), ["bodies.0.k0=0.7"])).bodies[0].k0 == 0.7


def test_boundaries_normalised_to_tables_in_dump() -> None:
    s = Scenario.from_dict(apply_overrides(base(), ["boundaries.bottom={condition='friction', coefficient=0.4}"]))
    dumped = json.loads(s.engine_json())
    assert dumped["boundaries"]["left"] == {"condition": "roller", "coefficient": 0.0}
    assert dumped["boundaries"]["bottom"] == {"condition": "friction", "coefficient": 0.4}
    toml = tomllib.loads(s.to_toml())
    assert toml["boundaries"]["left"] == {"condition": "roller", "coefficient": 0.0}


def test_toml_round_trip_is_exact() -> None:
    data = apply_overrides(base(), ['walls.0={axis="x", position=0.05, material_side="negative", condition="roller"}'])
    s = Scenario.from_dict(data)
    assert "removal_time" not in s.to_toml()  # None values are omitted (TOML has no null)
    again = Scenario.from_dict(tomllib.loads(s.to_toml()))
    assert again == s
    assert json.loads(again.engine_json())["walls"][0]["removal_time"] is None


def test_engine_json_has_every_section() -> None:
    d = json.loads(Scenario.from_dict(base()).engine_json())
    assert set(d) == {"simulation", "grid", "materials", "bodies", "boundaries", "walls", "rigid_bodies", "drainage",
                      "surcharges", "probes"}
    assert d["materials"]["soil"]["model"] == "linear_elastic"
    assert d["bodies"][0]["k0"] == pytest.approx(0.3 / 0.7)


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_examples_are_valid(path: Path) -> None:
    Scenario.from_toml(path)


def test_examples_exist() -> None:
    names = {p.name for p in EXAMPLES.glob("*.toml")}
    assert {"column_1d_compression.toml", "column_1d_axisymmetric.toml"} <= names


# --------------------------------------------------------------------------- field errors

FIELD_CASES = [
    ("materials.soil.poisson_ratio=0.7", "materials.soil.poisson_ratio", "must be >= 0 and < 0.5 (got 0.7)"),
    ("materials.soil.poisson_ratio=0.5", "materials.soil.poisson_ratio", "< 0.5"),
    ("materials.soil.poisson_ratio=-0.1", "materials.soil.poisson_ratio", ">= 0"),
    ("materials.soil.youngs_modulus=0", "materials.soil.youngs_modulus", "> 0"),
    ("materials.soil.density=-1", "materials.soil.density", "> 0"),
    ("grid.cell_size=0", "grid.cell_size", "> 0"),
    ("grid.extent=[0.1, -0.2]", "grid.extent.1", "> 0"),
    ("bodies.0.particles_per_cell=0", "bodies.0.particles_per_cell", ">= 1 and <= 8"),
    ("bodies.0.particles_per_cell=9", "bodies.0.particles_per_cell", ">= 1 and <= 8"),
    ("simulation.output_interval=0", "simulation.output_interval", "> 0"),
    ("simulation.end_time=-1", "simulation.end_time", "> 0"),
    ("simulation.cfl=0", "simulation.cfl", "> 0 and <= 1"),
    ("simulation.cfl=1.5", "simulation.cfl", "> 0 and <= 1"),
    ("simulation.flip_fraction=1.01", "simulation.flip_fraction", ">= 0 and <= 1"),
    ("simulation.damping=1", "simulation.damping", ">= 0 and < 1"),
    ("simulation.gravity_ramp_time=-0.1", "simulation.gravity_ramp_time", ">= 0"),
    ("simulation.time_step=-1e-5", "simulation.time_step", ">= 0"),
    ("simulation.end_time=nan", "simulation.end_time", "finite"),
    ("simulation.formulation=planestrain", "simulation.formulation", "did you mean 'plane_strain'"),
    ("simulation.shape_function=cpdi", "simulation.shape_function", "did you mean 'cpdi2'"),
    ("simulation.update_scheme=usf", "simulation.update_scheme", "'musl' or 'usl'"),
    ("simulation.volumetric_averaging=fbar", "simulation.volumetric_averaging", "'none' or 'cell'"),
    ("simulation.gravity=[0, -9.81, 0]", "simulation.gravity", "exactly 2"),
    ("grid.extent=[0.1]", "grid.extent", "exactly 2"),
    ("simulation.end_time=soon", "simulation.end_time", "valid number"),
    ("boundaries.bottom=glued", "boundaries.bottom.condition", "'free', 'roller', 'fixed' or 'friction'"),
    ("boundaries.bottom=3", "boundaries.bottom", "condition name"),
    ("boundaries.bottom={condition='friction', coefficient=-0.5}", "boundaries.bottom.coefficient", ">= 0"),
    ("materials.soil.model=elastic", "materials.soil.model", "unknown material model 'elastic'"),
    ("bodies.0.initial_stress=k0", "bodies.0.initial_stress", '"zero", "geostatic", { vertical = ..., horizontal'),
    ("bodies.0.initial_stress={vertical=-1e3}", "bodies.0.initial_stress", "horizontal: Field required"),
    ("bodies.0.k0=-1", "bodies.0.k0", ">= 0"),
]


@pytest.mark.parametrize("override,key,text", FIELD_CASES, ids=[c[0] for c in FIELD_CASES])
def test_field_error_names_the_key(override: str, key: str, text: str) -> None:
    err = errors_for([override])
    assert key in err.keys, err.render()
    message = dict(err.errors)[key]
    assert text in message, message
    assert f"error: {key}: " in str(err)


MOHR_COULOMB = ['materials.soil.model="mohr_coulomb"', "materials.soil.friction_angle=30"]
MC_CASES = [
    ("materials.soil.friction_angle=-1", "materials.soil.friction_angle", ">= 0 and < 90"),
    ("materials.soil.friction_angle=90", "materials.soil.friction_angle", ">= 0 and < 90"),
    # φ = 0 is Tresca: only with a cohesion (the undrained strength).
    ("materials.soil.friction_angle=0", "materials.soil.friction_angle", "= 0 (Tresca) needs cohesion > 0"),
    ("materials.soil.dilation_angle=-1", "materials.soil.dilation_angle", ">= 0"),
    ("materials.soil.dilation_angle=31", "materials.soil.dilation_angle", "<= friction_angle"),
    ("materials.soil.cohesion=-1", "materials.soil.cohesion", ">= 0"),
    ("materials.soil.tension_cutoff=-1", "materials.soil.tension_cutoff", ">= 0"),
]


@pytest.mark.parametrize("override,key,text", MC_CASES, ids=[c[0] for c in MC_CASES])
def test_mohr_coulomb_ranges(override: str, key: str, text: str) -> None:
    err = errors_for(MOHR_COULOMB + [override])
    assert key in err.keys, err.render()
    assert text in dict(err.errors)[key]


def test_missing_friction_angle() -> None:
    err = errors_for(['materials.soil.model="mohr_coulomb"'])
    assert dict(err.errors)["materials.soil.friction_angle"] == "required key is missing"


def test_missing_sections_and_keys() -> None:
    data = base()
    del data["grid"]
    del data["simulation"]["end_time"]
    err = errors_for([], data)
    assert {"grid", "simulation.end_time"} <= set(err.keys)


@pytest.mark.parametrize(
    "override,key,suggestion",
    [
        ("simulation.gravty=[0, -10]", "simulation.gravty", "gravity"),
        ("materials.soil.poisson=0.3", "materials.soil.poisson", "poisson_ratio"),
        ("bodies.0.particle_per_cell=2", "bodies.0.particle_per_cell", "particles_per_cell"),
        ("boundaries.botom=fixed", "boundaries.botom", "bottom"),
        ("simulaton.end_time=1", "simulaton", "simulation"),
        ("grid.cellsize=0.01", "grid.cellsize", "cell_size"),
    ],
)
def test_unknown_keys_suggest_the_closest(override: str, key: str, suggestion: str) -> None:
    err = errors_for([override])
    message = dict(err.errors)[key]
    assert message.startswith("unknown key") and f"did you mean '{suggestion}'" in message


def test_key_of_another_material_model() -> None:
    err = errors_for(["materials.soil.friction_angle=30"])
    assert "only valid for model = 'mohr_coulomb'" in dict(err.errors)["materials.soil.friction_angle"]


def test_all_field_errors_reported_at_once() -> None:
    err = errors_for(["materials.soil.poisson_ratio=0.7", "simulation.cfl=2", "grid.cellsize=1"])
    assert {"materials.soil.poisson_ratio", "simulation.cfl", "grid.cellsize"} <= set(err.keys)
    assert len(str(err).splitlines()) == len(err.errors)


# --------------------------------------------------------------------------- cross checks

CROSS_CASES = [
    ("grid.extent=[0.105, 0.2]", "grid.extent.0", "whole number of cells"),
    ("bodies.0.max=[0.055, 0.1]", "bodies.0.max.0", "grid line"),
    ("bodies.0.min=[0.0, 0.0005]", "bodies.0.min.1", "grid line"),
    ("bodies.0.max=[0.05, 0.3]", "bodies.0.max.1", "inside the grid"),
    ("bodies.0.min=[-0.01, 0.0]", "bodies.0.min.0", "inside the grid"),
    ("bodies.0.min=[0.05, 0.0]", "bodies.0.max.0", "must be > min.0"),
    ("bodies.0.material=sand", "bodies.0.material", "unknown material 'sand'"),
    ("bodies.0.material=sooil", "bodies.0.material", "did you mean 'soil'"),
    ('walls.0={axis="x", position=0.055, material_side="negative", condition="roller"}',
     "walls.0.position", "grid line"),
    ('walls.0={axis="y", position=0.5, material_side="negative", condition="fixed"}',
     "walls.0.position", "inside the grid"),
]


@pytest.mark.parametrize("override,key,text", CROSS_CASES, ids=[c[0] for c in CROSS_CASES])
def test_cross_check_names_the_key(override: str, key: str, text: str) -> None:
    err = errors_for([override])
    assert key in err.keys, err.render()
    assert text in dict(err.errors)[key]


def test_grid_tolerance_accepts_rounding() -> None:
    # 0.3 / 0.1 is 2.9999999999999996: a whole number of cells within 1e-6.
    data = apply_overrides(base(), ["grid.cell_size=0.1", "grid.extent=[0.3, 0.3]",
                                    "bodies.0.min=[0.0, 0.0]", "bodies.0.max=[0.3, 0.1]"])
    assert Scenario.from_dict(data).grid.cells() == (3, 3)


def test_axisymmetric_axis_checks() -> None:
    err = errors_for(["simulation.formulation=axisymmetric", "boundaries.left=free", "grid.origin=[0.01, 0.0]",
                      "bodies.0.min=[0.01, 0.0]"])
    messages = dict(err.errors)
    assert "always a roller" in messages["boundaries.left"]
    assert "grid.origin.0" in messages
    # the axis as a roller is fine, also written as a table
    Scenario.from_dict(apply_overrides(base(), ["simulation.formulation=axisymmetric",
                                                "boundaries.left={condition='roller'}"]))


def test_cross_checks_report_all_at_once() -> None:
    err = errors_for(["bodies.0.material=sand", "bodies.0.max=[0.055, 0.1]"])
    assert {"bodies.0.material", "bodies.0.max.0"} <= set(err.keys)


# --------------------------------------------------------------------------- overrides


def test_overrides_parse_toml_values() -> None:
    d = apply_overrides(base(), [
        "materials.soil.density=1600",
        "bodies.0.max=[0.04,0.08]",
        "simulation.formulation=axisymmetric",
        'bodies.0.name="a b"',
        "simulation.damping=0.05",
        "walls.0.axis=x",
    ])
    assert d["materials"]["soil"]["density"] == 1600
    assert d["bodies"][0]["max"] == [0.04, 0.08]
    assert d["simulation"]["formulation"] == "axisymmetric"
    assert d["bodies"][0]["name"] == "a b"
    assert d["simulation"]["damping"] == 0.05
    assert d["walls"] == [{"axis": "x"}]  # index == length appends a table
    assert base()["materials"]["soil"]["density"] == 1000.0  # input untouched


def test_override_into_shorthand_face() -> None:
    d = apply_overrides(base(), ["boundaries.left.coefficient=0.3"])
    assert d["boundaries"]["left"] == {"condition": "roller", "coefficient": 0.3}


@pytest.mark.parametrize(
    "override,key,text",
    [
        ("bodies.5.min=[0,0]", "bodies.5.min", "out of range"),
        ("bodies.x.min=[0,0]", "bodies.x.min", "expected an index"),
        ("simulation.end_time.x=1", "simulation.end_time.x", "not a table"),
        ("simulation.cfl", "simulation.cfl", "key.path=value"),
    ],
)
def test_bad_overrides(override: str, key: str, text: str) -> None:
    with pytest.raises(ScenarioError) as info:
        apply_overrides(base(), [override])
    assert text in dict(info.value.errors)[key]


@settings(max_examples=60, deadline=None)
@given(st.one_of(st.integers(-10**9, 10**9), st.floats(allow_nan=False, allow_infinity=False),
                 st.booleans(), st.lists(st.floats(-1e6, 1e6), max_size=3)))
def test_parse_value_round_trips_toml_literals(value) -> None:
    import tomli_w

    literal = tomli_w.dumps({"v": value}).split("=", 1)[1].strip().replace("\n", "")
    assert parse_value(literal) == value


@settings(max_examples=60, deadline=None)
@given(st.floats(-2.0, 2.0, allow_nan=False))
def test_poisson_ratio_range_property(nu: float) -> None:
    data = base()
    data["materials"]["soil"]["poisson_ratio"] = nu
    if 0.0 <= nu < 0.5:
        assert Scenario.from_dict(data).materials["soil"].poisson_ratio == nu
    else:
        with pytest.raises(ScenarioError) as info:
            Scenario.from_dict(data)
        assert info.value.keys == ["materials.soil.poisson_ratio"]


# --------------------------------------------------------------------------- files


def test_toml_syntax_error_names_the_line(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text("[simulation]\nformulation = \"plane_strain\"\nend_time = = 1\n")
    with pytest.raises(ScenarioError) as info:
        read_toml(path)
    assert "line 3" in str(info.value) and "invalid TOML" in str(info.value)


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError) as info:
        Scenario.from_toml(tmp_path / "nope.toml")
    assert "not found" in str(info.value) and "nope.toml" in str(info.value)


def test_schema_lists_sections() -> None:
    schema = Scenario.model_json_schema()
    assert set(schema["properties"]) == {"simulation", "grid", "materials", "bodies", "boundaries", "walls",
                                         "rigid_bodies", "drainage", "surcharges", "probes"}
    assert schema["$defs"]["Simulation"]["properties"]["cfl"]["exclusiveMinimum"] == 0.0
