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
    assert set(records) == {"plane_strain_n10", "axisymmetric_n10", "undrained", "mandel_n10", "cryer_n10",
                            "deleeuw_n10"}
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
    for name in ("cryer_n10", "deleeuw_n10"):
        r = records[name]
        assert r["status"] == "completed", r["message"]
        assert r["centre_error"] < consolidation.RADIAL_TOLERANCE
        assert r["peak"] > 1.0 and r["peak_exact"] > 1.2  # the rise, resolved
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
    for shape in consolidation.RADIAL_SHAPES:
        r10 = {"run": f"{shape}_n10", "kind": "radial", "shape": shape, "cells": 10, "centre_error": 0.03,
               "peak": 1.5}
        r20 = dict(r10, run=f"{shape}_n20", cells=20, centre_error=0.01)
        checks = consolidation.evaluate_checks([r10, r20])
        assert len(checks) == 5 and all(c["passed"] for c in checks)
        assert not consolidation.evaluate_checks([r10, dict(r20, centre_error=0.035)])[-1]["passed"]
        assert not consolidation.evaluate_checks([dict(r10, centre_error=0.051)], quick=True)[0]["passed"]
        assert not consolidation.evaluate_checks([dict(r10, centre_error=None)], quick=True)[0]["passed"]
        assert not consolidation.evaluate_checks([dict(r10, peak=0.98)], quick=True)[1]["passed"]


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


def _radial_reference(coupling: float, dimension: int, times: list[float], cells: int = 80) -> np.ndarray:
    """The centre's p/p₀ from a finite-volume solution of ∂p/∂T + η d⟨p⟩/dT = ∇²p on the unit
    disc (``dimension`` 2) or ball (3), p = 0 at ρ = 1 and p = 1 at T = 0 (docs/physics.md §10):
    the equation the series solve, integrated without them. Backward Euler on a geometric time
    grid, Richardson-extrapolated over two step counts; the centre from the two inner cells
    (p is even in ρ)."""
    edges = np.linspace(0.0, 1.0, cells + 1)
    centres = 0.5 * (edges[1:] + edges[:-1])
    volume = (edges[1:] ** dimension - edges[:-1] ** dimension) / dimension
    area = edges ** (dimension - 1)
    h = 1.0 / cells
    laplacian = np.zeros((cells, cells))
    for i in range(cells):
        if i + 1 < cells:
            laplacian[i, i + 1] += area[i + 1] / h / volume[i]
            laplacian[i, i] -= area[i + 1] / h / volume[i]
        else:
            laplacian[i, i] -= area[cells] / (0.5 * h) / volume[i]  # p = 0 on the surface
        if i > 0:
            laplacian[i, i - 1] += area[i] / h / volume[i]
            laplacian[i, i] -= area[i] / h / volume[i]
    mass = np.eye(cells) + coupling * np.outer(np.ones(cells), volume / volume.sum())
    targets = np.asarray(times, dtype=float)

    def integrate(steps: int) -> np.ndarray:
        grid = np.unique(np.concatenate([[0.0], np.geomspace(1e-7, targets.max(), steps), targets]))
        p, out = np.ones(cells), []
        for t0, t1 in zip(grid[:-1], grid[1:]):
            p = np.linalg.solve(mass - (t1 - t0) * laplacian, mass @ p)
            if np.isclose(t1, targets).any():
                out.append(p[0] - (p[1] - p[0]) * centres[0] ** 2 / (centres[1] ** 2 - centres[0] ** 2))
        return np.array(out)

    return 2.0 * integrate(600) - integrate(300)


def _cheng_cryer_centre(times: np.ndarray, nu: float, nu_u: float, skempton: float) -> np.ndarray:
    """Cryer's centre pressure p/p₀ in Cheng's form (Poroelasticity, 2016, §7.10; the form of
    PyLith's Cryer benchmark), written in ν and ν_u: roots of
    tan √x = 6(ν_u − ν)√x / [6(ν_u − ν) − (1 − ν)(1 + ν_u) x], p/q summed with the weights
    18(ν_u − ν)²/(η E_n), η = (1 − 2ν)/(2(1 − ν)), E_n = (1 − ν)²(1 + ν_u)² x − 18(1 + ν)(ν_u − ν)(1 − ν_u);
    p₀ = B q. Its own root search (bisection on (jπ, (j + 1)π) in √x)."""
    a = 6.0 * (nu_u - nu)
    b = (1.0 - nu) * (1.0 + nu_u)

    def f(s: np.ndarray) -> np.ndarray:  # tan s (a − b s²) − a s, no poles
        return np.sin(s) * (a - b * s * s) - a * s * np.cos(s)

    j = np.arange(400, dtype=float)
    lo, hi = np.maximum(j * np.pi, 1e-3), (j + 1.0) * np.pi
    f_lo = f(lo)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        same = np.sign(f(mid)) == np.sign(f_lo)
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    x = (0.5 * (lo + hi)) ** 2
    e_n = b * b * x - 18.0 * (1.0 + nu) * (nu_u - nu) * (1.0 - nu_u)
    eta = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu))
    weight = 18.0 * (nu_u - nu) ** 2 / (eta * e_n) * (np.sqrt(x) / np.sin(np.sqrt(x)) - 1.0)
    return np.sum(weight[None, :] * np.exp(-np.outer(times, x)), axis=1) / skempton


@pytest.mark.parametrize("poisson_ratio, water_bulk_modulus", [(0.0, 2.2e9), (0.3, 2.2e7)])
def test_cryer_closed_form(poisson_ratio: float, water_bulk_modulus: float) -> None:
    from axmpm.cases.consolidation import radial
    from axmpm.cases.consolidation.mandel import MandelMaterial

    material = MandelMaterial(1e7, poisson_ratio, 0.4, water_bulk_modulus, 1000.0, 1e-4)
    eta = radial.sphere_coupling(material)
    assert eta == pytest.approx((1 - poisson_ratio) / (1 - 2 * poisson_ratio) * (1 + material.bulk_modulus
                                                                                / material.biot_modulus))
    xi = radial.roots("sphere", eta, 60)
    assert np.allclose((1 - 0.5 * eta * xi**2) * np.sin(xi), xi * np.cos(xi), atol=1e-9 * xi**2)
    assert np.all(np.diff(xi) > 0) and 0 < xi[0] < np.pi
    times = np.array([0.005, 0.02, 0.06, 0.1, 0.2, 0.5])
    centre = radial.centre_pressure("sphere", times, material)
    # Cheng's form in ν and ν_u, an independent way of writing the same series.
    cheng = _cheng_cryer_centre(times, poisson_ratio, material.undrained_poisson_ratio, material.skempton)
    assert np.allclose(centre, cheng, atol=1e-8)
    # The diffusion equation behind both, integrated numerically.
    coupling = 4 * material.shear_modulus * material.biot_modulus / (
        3 * material.bulk_modulus * (material.bulk_modulus + 4 * material.shear_modulus / 3 + material.biot_modulus))
    assert np.allclose(centre, _radial_reference(coupling, 3, list(times)), atol=2e-3)
    # p₀ at T → 0 (the rise grows as √T, the series' short-time sum), zero on the drained surface,
    # decay at last.
    early = radial.centre_pressure("sphere", [1e-6, 1e-4], material) - 1.0
    assert 0.0 < early[0] < 3e-3 and early[1] / early[0] == pytest.approx(10.0, rel=0.03)
    assert abs(radial.pressure("sphere", 1.0, 0.05, material)[0]) < 1e-9
    assert radial.pressure("sphere", 0.5, 1e-6, material)[0] == pytest.approx(1.0, abs=3e-3)
    assert radial.centre_pressure("sphere", 3.0, material)[0] < 1e-3
    # The series at r → 0 joins the centre's.
    assert radial.pressure("sphere", 1e-6, times[2], material)[0] == pytest.approx(centre[2], abs=1e-8)
    # The Mandel–Cryer effect, larger in the sphere (squeezed from all sides) than in Mandel's plane
    # strain (1.155 at ν = 0); smaller at ν = 0.3 and with soft water.
    peak = radial.centre_pressure("sphere", np.linspace(0.01, 0.3, 300), material).max()
    assert (1.55 < peak < 1.6) if poisson_ratio == 0.0 else (1.0 < peak < 1.5)
    assert radial.initial_pressure("sphere", 1.0, material) == pytest.approx(material.skempton)


@pytest.mark.parametrize("poisson_ratio, water_bulk_modulus", [(0.0, 2.2e9), (0.3, 2.2e7)])
def test_de_leeuw_closed_form(poisson_ratio: float, water_bulk_modulus: float) -> None:
    from scipy.special import j0, j1

    from axmpm.cases.consolidation import radial
    from axmpm.cases.consolidation.mandel import MandelMaterial

    material = MandelMaterial(1e7, poisson_ratio, 0.4, water_bulk_modulus, 1000.0, 1e-4)
    k, g, m_biot = material.bulk_modulus, material.shear_modulus, material.biot_modulus
    m = radial.cylinder_coupling(material)
    assert m == pytest.approx((1 - poisson_ratio) / (2 * (1 - 2 * poisson_ratio)) * (1 + (k + g / 3) / m_biot))
    xi = radial.roots("cylinder", m, 60)
    assert np.allclose(2 * m * xi * j0(xi), j1(xi), atol=1e-10) and np.all(np.diff(xi) > 0)
    times = np.array([0.005, 0.02, 0.06, 0.1, 0.2, 0.5])
    centre = radial.centre_pressure("cylinder", times, material)
    coupling = g * m_biot / ((k + g / 3) * (k + 4 * g / 3 + m_biot))
    assert (1 + coupling) / (4 * coupling) == pytest.approx(m)
    assert np.allclose(centre, _radial_reference(coupling, 2, list(times)), atol=2e-3)
    early = radial.centre_pressure("cylinder", [1e-6, 1e-4], material) - 1.0
    assert 0.0 < early[0] < 3e-3 and early[1] / early[0] == pytest.approx(10.0, rel=0.03)
    assert abs(radial.pressure("cylinder", 1.0, 0.05, material)[0]) < 1e-9
    assert radial.centre_pressure("cylinder", 3.0, material)[0] < 1e-3
    peak = radial.centre_pressure("cylinder", np.linspace(0.01, 0.3, 300), material).max()
    assert (1.25 < peak < 1.3) if poisson_ratio == 0.0 else (1.0 < peak < 1.25)


def test_radial_initial_state_is_undrained_minus_drained() -> None:
    """The perturbation's initial state: total radial and hoop stress zero (the free surface),
    and for the cylinder the effective stress of a strain with ε_z = 0 (the rollers); p₀ the
    undrained pressure under the load q (the strain's volume change times M)."""
    from axmpm.cases.consolidation import radial
    from axmpm.cases.consolidation.mandel import MandelMaterial

    material = MandelMaterial(1e7, 0.3, 0.4, 2.2e7, 1000.0, 1e-4)
    k, g, m = material.bulk_modulus, material.shear_modulus, material.biot_modulus
    lam = k - 2 * g / 3
    q = 1e4
    for shape in radial.SPHERE, radial.CYLINDER:
        p0 = radial.initial_pressure(shape, q, material)
        rr, zz, hoop = radial.initial_effective_stress(shape, q, material)
        assert rr - p0 == pytest.approx(0.0, abs=1e-9 * q) and hoop - p0 == pytest.approx(0.0, abs=1e-9 * q)
        # Undrained under q: strain e per direction (the sphere's all three, the cylinder's r and θ).
        directions = 3 if shape == radial.SPHERE else 2
        e = -q / (directions * lam + 2 * g + directions * m)  # σ_rr = λ tr ε + 2G e − p = −q, p = −M tr ε
        assert p0 == pytest.approx(-m * directions * e, rel=1e-12)
        axial = lam * directions * e + (2 * g * e if shape == radial.SPHERE else 0.0)
        # The drained state under q has σ′_rr = −q; the difference's axial part:
        e_drained = -q / (directions * lam + 2 * g)
        axial_drained = lam * directions * e_drained + (2 * g * e_drained if shape == radial.SPHERE else 0.0)
        assert zz == pytest.approx(axial - axial_drained, rel=1e-12)
    with pytest.raises(ValueError, match="shape"):
        radial.initial_pressure("cube", q, material)


def test_radial_scenarios() -> None:
    """The sphere fills its quarter circle (volume within 1 % of the hemisphere's); both carry the
    perturbation's initial state and no load, and have the centre probe at the origin."""
    from axmpm.cases.consolidation import radial

    material = consolidation.mandel_material(consolidation.RADIAL_CONDUCTIVITY)
    for shape in consolidation.RADIAL_SHAPES:
        data = consolidation.radial_scenario(shape, 10, consolidation.RADIAL_CONDUCTIVITY, as_dict=True)
        scenario = Scenario.from_dict(data)
        body = scenario.bodies[0]
        assert body.saturated.surface_load == 0.0
        assert body.saturated.pore_pressure == pytest.approx(radial.initial_pressure(shape, consolidation.LOAD,
                                                                                      material))
        assert (body.initial_stress.xx, body.initial_stress.yy, body.initial_stress.zz) == pytest.approx(
            radial.initial_effective_stress(shape, consolidation.LOAD, material))
        assert scenario.probes[0].point == (0.0, 0.0)
        assert scenario.simulation.damping == 0.0
    data = consolidation.radial_scenario("sphere", 20, consolidation.RADIAL_CONDUCTIVITY, as_dict=True)
    vertices = np.array(data["bodies"][0]["vertices"])
    assert np.allclose(np.hypot(*vertices[1:].T), 1.0)
    spacing = 0.025
    centres = (np.stack(np.meshgrid(np.arange(40), np.arange(40)), -1).reshape(-1, 2) + 0.5) * spacing
    inside = centres[np.hypot(*centres.T) <= 1.0]
    volume = (inside[:, 0] * spacing**2).sum()  # per radian: Σ r A
    assert volume == pytest.approx(1.0 / 3.0, rel=0.01)


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
