"""Saturated soil as the front end sees it: the ``consolidation`` case's quick run against
Terzaghi, the closed form itself, frames with the pore pressure, and bad ``saturated`` input
refused naming the key (exit 2 from the command line)."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pytest

from axmpm.cases import consolidation, driver
from axmpm.cases.consolidation import exact
from axmpm.errors import ScenarioError
from axmpm.scenario import Scenario

from conftest import run_cli


def test_closed_form_degree_and_isochrones() -> None:
    # The tabulated T_v of U = 0.2 … 0.9 (Terzaghi's table) are the series' own.
    for u, tv in zip((0.2, 0.4, 0.5, 0.6, 0.8, 0.9), consolidation.DEGREE_TIME_FACTORS):
        assert abs(exact.degree(tv) - u) < 2e-4
        assert abs(exact.time_factor_of_degree(u) - tv) < 1e-3 * tv
    # U is the depth average of 1 − u/u₀ (midpoint rule over 2000 slices).
    z = (np.arange(2000) + 0.5) / 2000
    for tv in (0.01, 0.2, 1.0):
        assert abs(1.0 - exact.pressure(z, tv).mean() - exact.degree(tv)) < 1e-6
    # At the impermeable base (derived values of the reference: 0.997, 0.949, 0.772, 0.371, 0.108).
    base = [exact.pressure(1.0, tv)[0] for tv in (0.05, 0.1, 0.2, 0.5, 1.0)]
    assert np.allclose(base, [0.997, 0.949, 0.772, 0.371, 0.108], atol=6e-4)
    # Drained top: u = 0; before any drainage (T_v → 0) u = u₀ inside.
    assert abs(exact.pressure(0.0, 0.1)[0]) < 1e-12 and abs(exact.pressure(0.5, 1e-6)[0] - 1.0) < 1e-6
    assert exact.undrained_pressure(1.0, 0.4, 2e7, 1e7) == pytest.approx(5.0 / 6.0)
    assert exact.consolidation_coefficient(1e-3, 1000.0, 0.4, 2.2e9, 1e7) == pytest.approx(
        1e-3 / (9810.0 * (1e-7 + 0.4 / 2.2e9)))


def test_quick_run_meets_terzaghi(tmp_path: Path) -> None:
    """H/h = 10 in both formulations and the undrained run (a few seconds)."""
    options = argparse.Namespace(quick=True, overrides=[], figures=False)
    data = driver.verify_or_validate("verification", [consolidation.CASE], options, tmp_path, jobs=1, log=None)
    records = {r["name"]: r for r in data["cases"]}
    assert set(records) == {"plane_strain_n10", "axisymmetric_n10", "undrained", "mandel_n10"}
    for name in ("plane_strain_n10", "axisymmetric_n10"):
        r = records[name]
        assert r["status"] == "completed", r["message"]
        assert r["degree_error"] < consolidation.DEGREE_TOLERANCE
        assert r["isochrone_error"] < consolidation.ISOCHRONE_TOLERANCE
    assert abs(records["undrained"]["undrained_ratio"] - 1.0) < consolidation.UNDRAINED_TOLERANCE
    mandel_run = records["mandel_n10"]
    assert mandel_run["status"] == "completed", mandel_run["message"]
    assert mandel_run["mandel_error"] < consolidation.MANDEL_TOLERANCE
    assert mandel_run["peak"] > 1.0  # the Mandel–Cryer effect
    assert mandel_run["field_error"] < consolidation.MANDEL_TOLERANCE
    assert mandel_run["column_spread"] < consolidation.CHECKERBOARD_TOLERANCE
    assert data["passed"] and all(c["passed"] for c in data["checks"])
    # Frames carry the pore pressure, the porosity and the water velocity.
    from axmpm.run.output import load_run

    frame = load_run(tmp_path / records["plane_strain_n10"]["run_dir"]).last
    assert frame.pore_pressure.shape == (len(frame.x),) and frame.water_velocity.shape == (len(frame.x), 2)
    # The skeleton compressed: the porosity fell below its initial 0.4.
    assert (frame.porosity < consolidation.POROSITY).all() and (frame.porosity > 0.3).all()


def test_mandel_closed_form() -> None:
    from axmpm.cases.consolidation import mandel

    material = consolidation.mandel_material(1e-3)
    # Incompressible grains, stiff water: B → 1 and ν_u → 1/2.
    assert 0.999 < material.skempton < 1.0 and 0.499 < material.undrained_poisson_ratio < 0.5
    nu, nu_u = 0.2, 0.4
    alpha = mandel.roots(nu, nu_u, 50)
    assert np.allclose(np.tan(alpha), (1 - nu) / (nu_u - nu) * alpha, rtol=1e-9)
    assert 0 < alpha[0] < np.pi / 2 and np.all(np.diff(alpha) > 0)
    # Uniform p₀ at t → 0 inside (the rise grows as √T), zero at the drained side, decay at last.
    assert mandel.pressure(0.5, 1e-7, material)[0] == pytest.approx(1.0, abs=1e-3)
    assert abs(mandel.pressure(1.0, 0.1, material)[0]) < 1e-9
    early = mandel.centre_pressure([1e-6, 1e-4], material) - 1.0
    assert early[1] / early[0] == pytest.approx(10.0, rel=0.02)
    assert mandel.centre_pressure(8.0, material)[0] < 1e-3
    # The Mandel–Cryer effect: the centre rises above p₀, then falls below it.
    centre = mandel.centre_pressure(np.linspace(0.001, 1.0, 500), material)
    assert 1.1 < centre.max() < 1.2 and centre[-1] < 0.5


def test_checks_fail_on_bad_records() -> None:
    good = {"run": "a", "kind": "consolidation", "formulation": "plane_strain", "cells": 10,
            "degree_error": 0.01, "isochrone_error": 0.02}
    finer = dict(good, run="b", cells=20, degree_error=0.005)
    assert all(c["passed"] for c in consolidation.evaluate_checks([good, finer]))
    worse = dict(finer, degree_error=0.015)
    assert not consolidation.evaluate_checks([good, worse])[-1]["passed"]
    assert not consolidation.evaluate_checks([dict(good, degree_error=0.03)], quick=True)[0]["passed"]
    assert not consolidation.evaluate_checks([dict(good, isochrone_error=None)], quick=True)[1]["passed"]
    undrained = {"run": "undrained", "kind": "undrained", "undrained_ratio": 1.02, "undrained_error": 0.02}
    assert not consolidation.evaluate_checks([undrained], quick=True)[0]["passed"]
    m10 = {"run": "mandel_n10", "kind": "mandel", "cells": 10, "mandel_error": 0.03, "peak": 1.1,
           "field_error": 0.004, "column_spread": 0.0003}
    m20 = dict(m10, run="mandel_n20", cells=20, mandel_error=0.02, field_error=0.002)
    assert all(c["passed"] for c in consolidation.evaluate_checks([m10, m20]))

    def failed(records: list[dict], quick: bool = False) -> list[str]:
        return [c["name"] for c in consolidation.evaluate_checks(records, quick=quick) if not c["passed"]]

    assert failed([m10, dict(m20, mandel_error=0.04)]) == ["Mandel: the error shrinks with the mesh"]
    assert failed([m10, dict(m20, field_error=0.005)]) == ["Mandel: the pressure field's error shrinks with the mesh"]
    assert "centre pressure within" in failed([dict(m10, mandel_error=0.06)], quick=True)[0]
    assert "Mandel–Cryer" in failed([dict(m10, peak=0.99)], quick=True)[0]
    assert "the pressure field within" in failed([dict(m10, field_error=0.06)], quick=True)[0]
    assert "no checkerboard" in failed([dict(m10, column_spread=0.02)], quick=True)[0]
    assert len(failed([dict(m10, field_error=None, column_spread=None)], quick=True)) == 2


def _scenario(**saturated):
    data = consolidation.column_scenario("plane_strain", 10, as_dict=True)
    data["bodies"][0]["saturated"].update(saturated)
    return data


@pytest.mark.parametrize("key, value, message", [
    ("porosity", 1.0, "must be > 0 and < 1"),
    ("porosity", 0.0, "must be > 0 and < 1"),
    ("hydraulic_conductivity", 0.0, "must be > 0"),
    ("water_bulk_modulus", -1.0, "must be > 0"),
    ("water_density", 0.0, "must be > 0"),
    ("surface_load", -5.0, "must be >= 0"),
    ("water_table", 5.0, "must lie inside the grid"),
])
def test_bad_saturated_input_names_the_key(key: str, value: float, message: str) -> None:
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(_scenario(**{key: value}))
    text = str(info.value)
    assert f"bodies.0.saturated.{key}" in text and message in text, text


def test_one_pore_water_and_one_initial_pressure() -> None:
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(_scenario(water_table=0.5, pore_pressure=1e3))
    assert "bodies.0.saturated.pore_pressure" in str(info.value)
    data = _scenario()
    second = dict(data["bodies"][0], name="other", min=[0.0, 1.0], max=[0.1, 1.1])
    second["saturated"] = dict(second["saturated"], water_bulk_modulus=1e9)
    data["bodies"].append(second)
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(data)
    assert "bodies.1.saturated.water_bulk_modulus" in str(info.value)
    bad = _scenario()
    bad["drainage"] = {"top": "leaky"}
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(bad)
    assert "drainage.top" in str(info.value)


def test_loading_plate_needs_the_top_on_a_grid_line() -> None:
    data = consolidation.mandel_scenario(10, consolidation.MANDEL_CONDUCTIVITY, as_dict=True)
    Scenario.from_dict(data)
    data["bodies"][0]["max"] = [1.0, 0.45]
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(data)
    assert "bodies.0.saturated.loading_plate" in str(info.value) and "grid line" in str(info.value)
    data = consolidation.mandel_scenario(10, consolidation.MANDEL_CONDUCTIVITY, as_dict=True)
    data["bodies"][0]["saturated"]["surface_load"] = 0.0
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(data)
    assert "bodies.0.saturated.loading_plate" in str(info.value) and "surface_load > 0" in str(info.value)


def test_prescribed_pressure_needs_a_drained_face() -> None:
    data = _scenario()
    data["drainage"] = {"pressure": {"bottom": 5e3}}
    assert Scenario.from_dict(data).drainage.pressure.bottom == 5e3
    data["drainage"] = {"bottom": "impermeable", "pressure": {"bottom": 5e3}}
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(data)
    assert "drainage.pressure.bottom" in str(info.value) and "drained face" in str(info.value)
    data["drainage"] = {"pressure": {"bottom": "high"}}
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(data)
    assert "drainage.pressure.bottom" in str(info.value)


def test_command_line_exits_2_naming_the_key(tmp_path: Path) -> None:
    import tomli_w

    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(_scenario(hydraulic_conductivity=-1e-5)))
    result = run_cli("check", path)
    assert result.returncode == 2, result.stderr
    assert "bodies.0.saturated.hydraulic_conductivity" in result.stderr and "Traceback" not in result.stderr


def test_penalty_contact_is_refused_next_to_a_saturated_body() -> None:
    # The saturated step imposes a rigid body's contact at the nodes only.
    data = _scenario()
    data["rigid_bodies"] = [{"name": "plate", "shape": "rectangle", "min": [0.0, 1.0], "max": [0.1, 1.1],
                             "velocity": [0.0, 0.0], "contact": "penalty", "experimental": True}]
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(data)
    assert "rigid_bodies.0.contact" in str(info.value) and "saturated" in str(info.value)
    data["rigid_bodies"][0]["contact"] = "nodes"
    Scenario.from_dict(data)
