"""The ``taylor_bar`` case and the ``von_mises`` material as the front end sees them: the quick
run (coarse mesh, cpGIMP) balances its energy and lands near the reference length, the metric
rules on a hand-made frame, the enforced checks on fabricated records, and bad J2 input."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from axmpm import material_point
from axmpm.cases import driver, taylor_bar
from axmpm.errors import ScenarioError
from axmpm.scenario import Scenario

from conftest import run_cli


def test_quick_run_balances_energy_and_lands_near_the_reference_length(tmp_path: Path) -> None:
    """R0/h = 8, cpGIMP (about 3 s): energy within 1 %, L_f within 5 % of 21.45 mm."""
    options = argparse.Namespace(quick=True, overrides=[], figures=True)
    data = driver.verify_or_validate("verification", [taylor_bar.CASE], options, tmp_path, jobs=1, log=None)
    (record,) = data["cases"]
    assert record["status"] == "completed", record["message"]
    assert record["name"] == "cpgimp_n08" and record["formulation"] == "axisymmetric"
    assert abs(record["energy_error"]) < 0.01
    assert abs(record["final_length"] / 21.45e-3 - 1.0) < 0.05
    # the bar shortened and spread: plastic work took most of the kinetic energy
    assert record["plastic_work"] > 0.9 * record["initial_kinetic_energy"]
    assert record["impact_radius"] > 2.0 * 3.2e-3 and record["max_plastic_strain"] > 1.0
    assert data["passed"] and all(c["passed"] for c in data["checks"])
    assert record["reference"] == {"impact_radius": 7.12e-3, "final_length": 21.45e-3}
    assert set(record["relative_error"]) == {"impact_radius", "final_length"}
    report = (tmp_path / "report.md").read_text()
    assert "Taylor bar" in report and "figures/taylor_bar/shapes.png" in report
    assert (tmp_path / "figures" / "taylor_bar" / "convergence.png").is_file()


def _frame(x, F, v, stress=None, plastic_work=None, volume=None, mass=None):
    n = len(x)
    state = np.zeros((n, 2))
    if plastic_work is not None:
        state[:, 1] = plastic_work
    return SimpleNamespace(
        time=80e-6, x=np.asarray(x, float), v=np.asarray(v, float), F=np.asarray(F, float),
        stress=np.zeros((n, 4)) if stress is None else np.asarray(stress, float),
        volume=np.ones(n) if volume is None else np.asarray(volume, float), volume0=np.ones(n),
        mass=np.ones(n) if mass is None else np.asarray(mass, float), state=state,
        state_names=["plastic_strain", "plastic_work"])


def test_metric_rules_by_hand() -> None:
    """Four particles, h = 1, l0 = 0.25. L_f = highest z + l0(|F21| + |F22|); R_f = largest
    r + l0(|F11| + |F12|) among centres within one cell of the wall (the particle at r = 5,
    z = 1.5 is above it and does not count)."""
    x = [[0.25, 0.25], [3.0, 0.5], [5.0, 1.5], [0.25, 10.0]]
    F = [[2.0, 0.5, 0.0, 0.5, 1.0], [3.0, -1.0, 0.0, 0.4, 1.0], [1.0, 0.0, 0.0, 1.0, 1.0],
         [1.0, 0.0, 0.2, 1.2, 1.0]]
    v = [[0.0, -10.0]] * 4
    m = taylor_bar.bar_metrics(_frame(x, F, v), 1.0, 0.25, "axisymmetric", 10.0)
    assert m["final_length"] == pytest.approx(10.0 + 0.25 * 1.4)
    assert m["impact_radius"] == pytest.approx(3.0 + 0.25 * 4.0)
    # unmoved, unstressed: no energy went anywhere
    assert m["energy_error"] == pytest.approx(0.0, abs=1e-15)
    assert m["initial_kinetic_energy"] == pytest.approx(2 * math.pi * 0.5 * 4 * 100.0)


def test_energy_terms_by_hand() -> None:
    """At rest, one particle holding pressure p = −1 GPa (E_el = p²/(2K) V) and plastic work w:
    KE0 = E_el + W_p makes the error zero; plane strain totals are per metre."""
    # Simo's copper, E = 117 GPa and ν = 0.35: G = E/(2(1 + ν)), K = E/(3(1 − 2ν)), by hand.
    g, k = 117e9 / 2.7, 117e9 / 0.9
    p = -1e9
    elastic = p * p / (2 * k) * 2.0  # volume 2
    ke0 = 0.5 * 3.0 * 100.0**2  # mass 3
    w = (ke0 - elastic) / 1.0  # volume0 1
    frame = _frame([[0.1, 0.1]], [[1, 0, 0, 1, 1]], [[0.0, 0.0]], stress=[[p, p, p, 0.0]], plastic_work=[w],
                   volume=[2.0], mass=[3.0])
    m = taylor_bar.bar_metrics(frame, 1.0, 0.25, "plane_strain", 100.0)
    assert m["elastic_energy"] == pytest.approx(elastic)
    assert m["plastic_work"] == pytest.approx(w)
    assert m["energy_error"] == pytest.approx(0.0, abs=1e-12)
    # a pure shear stress τ stores τ²/(2G) per volume
    frame = _frame([[0.1, 0.1]], [[1, 0, 0, 1, 1]], [[0.0, 0.0]], stress=[[0, 0, 0, 1e8]], volume=[1.0])
    assert taylor_bar.bar_metrics(frame, 1.0, 0.25, "plane_strain", 1.0)["elastic_energy"] == pytest.approx(
        1e16 / (2 * g))


def _record(name, scheme, n, R, L, e=0.001, status="completed", formulation="axisymmetric", geometry="simo1992"):
    return {"name": name, "scheme": scheme, "cells_per_radius": n, "impact_radius": R, "final_length": L,
            "energy_error": e, "status": status, "formulation": formulation, "geometry": geometry, "message": ""}


def test_checks_apply_the_targets_at_the_finest_mesh_only() -> None:
    results = [
        _record("cpgimp_n08", "cpgimp", 8, 6.0e-3, 20.0e-3),      # coarse: not checked against targets
        _record("cpgimp_n24", "cpgimp", 24, 7.12e-3 * 1.029, 21.45e-3 * 0.986),
        _record("cpdi2_n24", "cpdi2", 24, 7.12e-3 * 1.031, 21.45e-3),  # R_f 3.1 % off
        _record("ugimp_n24", "ugimp", 24, 5.0e-3, 21.9e-3, e=0.02),    # not a target scheme: reported only
        _record("cpdi2_n16", "cpdi2", 16, 7.1e-3, 21.4e-3, e=-0.011),  # energy created: fails on any mesh
    ]
    evaluated = taylor_bar.evaluate_checks(results)
    checks = {c["name"]: c["passed"] for c in evaluated}
    lf = "L_f within 1.5% of 21.45 mm (unconfirmed reference: reported, not enforced)"
    assert checks["cpgimp_n24: R_f within 3.0% of 7.12 mm"]
    assert checks[f"cpgimp_n24: {lf}"]
    assert not checks["cpdi2_n24: R_f within 3.0% of 7.12 mm"]
    assert checks[f"cpdi2_n24: {lf}"]
    # R_f is enforced; L_f (an unconfirmed reference) is an aim: a miss is reported, the run passes
    required = {c["name"]: c.get("required", True) for c in evaluated}
    assert required["cpgimp_n24: R_f within 3.0% of 7.12 mm"] and not required[f"cpgimp_n24: {lf}"]
    long_bar = taylor_bar.evaluate_checks([_record("cpgimp_n24", "cpgimp", 24, 7.12e-3, 21.45e-3 * 1.03)])
    assert [(c["passed"], c.get("required", True)) for c in long_bar if "L_f" in c["name"]] == [(False, False)]
    assert checks["cpgimp_n08: energy balance within 1%"] and not checks["cpdi2_n16: energy balance within 1%"]
    assert not any(name.startswith(("cpgimp_n08: R_f", "cpdi2_n16: R_f", "ugimp_n24")) for name in checks)
    failed = _record("cpdi2_n24", "cpdi2", 24, None, None, e=None, status="failed")
    checks = {c["name"]: c["passed"] for c in taylor_bar.evaluate_checks([failed])}
    assert checks == {"cpdi2_n24: energy balance within 1%": False, "cpdi2_n24: R_f within 3.0% of 7.12 mm": False,
                      f"cpdi2_n24: {lf}": False}
    quick = taylor_bar.evaluate_checks([_record("cpgimp_n08", "cpgimp", 8, 7e-3, 21.45e-3 * 1.06)], quick=True)
    assert [c["passed"] for c in quick] == [True, False]


def test_runs_and_scenarios() -> None:
    runs = taylor_bar.run_specs()
    names = [r.name for r in runs]
    assert len(names) == 4 * 3 + 2 and len(set(names)) == len(names)
    assert "cpgimp_n24_plane_strain" in names and "wilkins_guinan1973_cpgimp_n25" in names
    assert [r.name for r in taylor_bar.run_specs(quick=True)] == ["cpgimp_n08"]
    s = taylor_bar.taylor_scenario("cpdi2", 16)
    body = s.bodies[0]
    assert s.grid.cell_size == pytest.approx(0.2e-3)
    assert body.max[1] == pytest.approx(32.4e-3) and body.max[0] == pytest.approx(3.2e-3)
    assert body.velocity == (0.0, -227.0) and s.simulation.flip_fraction == 1.0
    assert s.simulation.gravity == (0.0, 0.0)
    (wall,) = s.walls  # the rigid frictionless wall z = 0, two cells above the grid's base
    assert (wall.axis, wall.position, wall.material_side, wall.condition) == ("y", 0.0, "positive", "roller")
    assert s.grid.origin[1] == pytest.approx(-2 * 0.2e-3) and body.min[1] == 0.0
    assert s.materials["copper"].model == "von_mises"
    wg = taylor_bar.taylor_scenario("cpgimp", 25, geometry="wilkins_guinan1973")
    assert wg.bodies[0].max[1] == pytest.approx(23.4696e-3) and wg.bodies[0].max[0] == pytest.approx(3.81e-3)
    with pytest.raises(ValueError, match="multiple of 8"):
        taylor_bar.taylor_scenario("cpgimp", 4)


# --------------------------------------------------------------------------- von_mises input


def _bar(**material: object) -> dict:
    data = taylor_bar.taylor_scenario("linear", 8, as_dict=True)
    data["materials"]["copper"].update(material)
    return data


@pytest.mark.parametrize("key, value, message", [
    ("yield_stress", 0.0, "must be > 0"),
    ("yield_stress", -4e8, "must be > 0"),
    ("hardening_modulus", -1.0, "must be >= 0"),
])
def test_bad_von_mises_parameters_name_the_key(key: str, value: float, message: str) -> None:
    with pytest.raises(ScenarioError) as err:
        Scenario.from_dict(_bar(**{key: value}))
    assert any(k == f"materials.copper.{key}" and message in m for k, m in err.value.errors), err.value.errors


def test_yield_keys_on_other_models_are_rejected_with_exit_2(tiny_toml: Path) -> None:
    result = run_cli("check", tiny_toml, "--set", "materials.soil.yield_stress=4e8")
    assert result.returncode == 2, result.stderr
    assert "materials.soil.yield_stress: unknown key" in result.stderr
    assert "von_mises" in result.stderr
    data = _bar()
    del data["materials"]["copper"]["yield_stress"]
    with pytest.raises(ScenarioError) as err:
        Scenario.from_dict(data)
    assert [k for k, _ in err.value.errors] == ["materials.copper.yield_stress"]


def test_von_mises_material_point_yields_at_the_yield_stress() -> None:
    """Uniaxial strain through the binding: the deviator saturates at q = σ_y + H ε̄p."""
    copper = {"model": "von_mises", **taylor_bar.COPPER}
    L = np.tile([-1.0, 0.0, 0.0, 0.0, 0.0], (200, 1))
    response = material_point(copper, L, 1e-4)
    s = response[0][-1]
    q = abs(s[0] - s[1])  # uniaxial strain: q = |σ11 − σ22|
    ep = response.state("plastic_strain")[-1]
    assert ep > 0.0
    assert q == pytest.approx(4e8 + 1e8 * ep, rel=1e-9)
