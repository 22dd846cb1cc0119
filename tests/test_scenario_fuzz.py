"""Property-based robustness of scenario input (issue #5): random and mutated scenarios, random
TOML text and random overrides never raise anything but ScenarioError from the loader, and
``axmpm check`` (run in-process) always exits 0 or 2 without a traceback."""

from __future__ import annotations

import contextlib
import copy
import io
import math
import tomllib
from pathlib import Path
from typing import Any

import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from axmpm.cli import main
from axmpm.scenario import Scenario, ScenarioError

from conftest import TINY_TOML

FUZZ = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])

#: A valid scenario using every section and material model, the starting point of mutations.
VALID = tomllib.loads(TINY_TOML + """
[materials.sand]
model = "mohr_coulomb"
density = 1600.0
youngs_modulus = 2.0e5
poisson_ratio = 0.25
friction_angle = 32.0
dilation_angle = 2.0
cohesion = 10.0

[materials.rubber]
model = "neo_hookean"
density = 1100.0
youngs_modulus = 5.0e5
poisson_ratio = 0.45

[[bodies]]
name = "heap"
material = "sand"
min = [0.05, 0.0]
max = [0.1, 0.05]
particles_per_cell = 3
initial_stress = "geostatic"

[[walls]]
axis = "x"
position = 0.05
material_side = "negative"
condition = "friction"
coefficient = 0.3
removal_time = 0.02
""")
Scenario.from_dict(VALID)  # the starting point is valid

KEYS = sorted({"simulation", "grid", "materials", "bodies", "boundaries", "walls", "formulation",
               "shape_function", "end_time", "output_interval", "gravity", "cfl", "time_step",
               "origin", "extent", "cell_size", "model", "density", "youngs_modulus", "poisson_ratio",
               "friction_angle", "dilation_angle", "cohesion", "material", "min", "max",
               "particles_per_cell", "allow_overlap", "checkpoint_interval", "left", "bottom",
               "condition", "coefficient", "axis", "position", "k0", "velocity"})

names = st.one_of(st.sampled_from(KEYS), st.text(min_size=1, max_size=12))
scalars = st.one_of(
    st.booleans(),
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1.0, max_value=1.0),
    st.text(max_size=12),
    st.sampled_from(["linear", "axisymmetric", "roller", "mohr_coulomb", "soil", "sand", "x", "geostatic"]),
)
values = st.recursive(
    scalars,
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(names, inner, max_size=4)),
    max_leaves=8,
)


def paths(node: Any, prefix: tuple = ()) -> list[tuple]:
    """Every path to a value or table in ``node`` (the root excluded)."""
    out = []
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else []
    for k, v in items:
        out.append(prefix + (k,))
        out.extend(paths(v, prefix + (k,)))
    return out


def containers(node: Any, prefix: tuple = ()) -> list[tuple]:
    out = [prefix] if isinstance(node, dict) else []
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else []
    for k, v in items:
        out.extend(containers(v, prefix + (k,)))
    return out


def at(node: Any, path: tuple) -> Any:
    for p in path:
        node = node[p]
    return node


@st.composite
def mutated(draw: st.DrawFn) -> dict:
    data = copy.deepcopy(VALID)
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["set", "delete", "unknown", "typo", "numeric"]))
        all_paths = paths(data)
        if kind in ("set", "delete", "typo", "numeric") and all_paths:
            path = draw(st.sampled_from(all_paths))
            parent, key = at(data, path[:-1]), path[-1]
            if kind == "set":
                parent[key] = draw(values)
            elif kind == "numeric":
                parent[key] = draw(st.one_of(st.floats(), st.integers(-10, 10), st.sampled_from(
                    [0, 0.0, -0.0, 1e-300, 1e300, -1e300, 0.5, 90, 1e9])))
            elif kind == "delete":
                del parent[key]
            elif isinstance(parent, dict):  # typo: rename a key by dropping/doubling a letter
                i = draw(st.integers(0, max(0, len(key) - 1)))
                new = key[:i] + key[i + 1:] if draw(st.booleans()) else key[:i] + key[i:i + 1] + key[i:]
                parent[new or "x"] = parent.pop(key)
        else:
            table = at(data, draw(st.sampled_from(containers(data))))
            table[draw(names)] = draw(values)
    return data


def load(data: Any) -> None:
    """The loader either accepts the data or raises ScenarioError with keyed messages."""
    try:
        s = Scenario.from_dict(data)
    except ScenarioError as exc:
        assert exc.errors
        for key, message in exc.errors:
            assert isinstance(key, str) and message
        assert "Traceback" not in exc.render()
    else:
        # an accepted scenario is usable: it dumps, and its resolved form loads again
        s.engine_json()
        assert Scenario.from_dict(tomllib.loads(s.to_toml())) == s
        assert s.particle_count() > 0


def check_file(path: Path, text: str | bytes, *extra: str) -> None:
    """``axmpm check`` in-process on ``text``: exit 0 or 2, only ``error: `` lines on stderr."""
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text)
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["check", str(path), *extra])
    stderr = err.getvalue()
    assert code in (0, 2), stderr
    assert "Traceback" not in stderr
    if code == 2:
        assert stderr.startswith("error: "), stderr
        assert all(line.startswith("error: ") for line in stderr.rstrip("\n").split("\n"))
    else:
        assert out.getvalue().startswith("ok: ")


def to_toml(data: dict) -> str | None:
    try:
        return tomli_w.dumps(data)
    except Exception:  # values TOML cannot hold (mixed-key tables, None, ...)
        return None


@pytest.fixture(scope="module")
def scratch(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("fuzz")


@FUZZ
@given(data=mutated())
def test_mutated_scenarios_load_or_raise_scenario_error(data: dict) -> None:
    load(data)


@FUZZ
@given(data=st.dictionaries(st.one_of(st.sampled_from(KEYS[:6]), names), values, max_size=6))
def test_random_scenarios_load_or_raise_scenario_error(data: dict) -> None:
    load(data)


@FUZZ
@given(data=mutated())
def test_check_on_mutated_files_exits_0_or_2(data: dict, scratch: Path) -> None:
    text = to_toml(data)
    if text is not None:
        check_file(scratch / "mutated.toml", text)


@FUZZ
@given(text=st.one_of(
    st.text(max_size=200),
    st.binary(max_size=100),
    # valid TOML, then a random cut or splice: syntax errors at every place
    st.tuples(st.integers(0, len(TINY_TOML)), st.text(max_size=8)).map(
        lambda t: TINY_TOML[: t[0]] + t[1] + TINY_TOML[t[0]:]),
))
def test_check_on_random_toml_text_exits_0_or_2(text: str | bytes, scratch: Path) -> None:
    check_file(scratch / "random.toml", text)


@FUZZ
@given(overrides=st.lists(st.one_of(
    st.text(max_size=30),
    st.tuples(st.sampled_from([".".join(map(str, p)) for p in paths(VALID)] + ["bodies.2", "walls.1.axis"]),
              st.sampled_from(["0", "-1", "1e400", "nan", "inf", "'x'", "[1, 2, 3]", "{a=1}", "true",
                               "[]", "1979-05-27", "[[1]]", "\"\"", "0.5"])).map(lambda t: f"{t[0]}={t[1]}"),
), max_size=4))
def test_check_with_random_overrides_exits_0_or_2(overrides: list[str], scratch: Path) -> None:
    check_file(scratch / "base.toml", TINY_TOML, *[f"--set={o}" for o in overrides])


def test_fuzz_start_is_valid_and_keeps_errors_keyed() -> None:
    assert math.isclose(Scenario.from_dict(VALID).bodies[1].k0, 1 - math.sin(math.radians(32)))
