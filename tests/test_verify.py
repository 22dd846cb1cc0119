"""``axmpm verify``: the quick verification (the ``column_1d`` case) through the CLI, and the
enforced checks on fabricated results (they must be able to fail)."""

from __future__ import annotations

import argparse
import copy
import json
from pathlib import Path

import pytest

import axmpm
from axmpm.cases import driver
from axmpm.cases.column_1d import case as verify
from conftest import run_cli

RESULTS, REPORT = "verification.json", "report.md"

CASE_FIELDS = {
    "name", "scheme", "formulation", "mode", "offset", "cells_per_length", "density", "gravity",
    "youngs_modulus", "run_dir", "stress_error", "displacement_error", "max_stress_error", "tolerance", "passed",
}


@pytest.fixture(scope="module")
def quick(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, object]:
    out = tmp_path_factory.mktemp("verify") / "out"
    result = run_cli("verify", "--out", out, "--quick", "--jobs", "2", timeout=600)
    return out, result


def test_quick_exits_zero(quick) -> None:
    out, result = quick
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert "Traceback" not in result.stderr
    assert "checks pass" in result.stdout


def test_quick_json(quick) -> None:
    out, _ = quick
    data = json.loads((out / RESULTS).read_text())
    cases, checks = data["cases"], data["checks"]
    expected = len(verify.schemes()) * len(verify.MODES) * len(verify.LAYOUTS) * len(verify.QUICK_RESOLUTIONS)
    assert len(cases) == expected
    assert {c["scheme"] for c in cases} == set(verify.schemes())
    assert {c["mode"] for c in cases} == {"compression", "tension"}
    assert {c["formulation"] for c in cases} == {"plane_strain", "axisymmetric"}
    for c in cases:
        assert CASE_FIELDS <= set(c), CASE_FIELDS - set(c)
        assert (out / c["run_dir"] / "summary.json").exists()
        if c["formulation"] == "plane_strain":
            assert c["offset"] == 0.0
        if c["status"] == "completed":
            assert c["stress_error"] is not None and c["displacement_error"] is not None
        else:  # a failed run is a result: no errors, not passed, the engine's message kept
            assert c["stress_error"] is None and c["displacement_error"] is None and c["max_stress_error"] is None
            assert c["passed"] is False and c["message"]
    offsets = {c["offset"] for c in cases if c["layout"] == "axisymmetric_offset"}
    widths = {c["cells_along"]: verify.CELLS_ACROSS / c["cells_along"] for c in cases}
    assert all(c["offset"] >= 20 * widths[c["cells_along"]] - 1e-12
               for c in cases if c["layout"] == "axisymmetric_offset"), offsets
    assert checks and all({"name", "measured", "limit", "passed"} <= set(k) for k in checks)
    assert all(k["passed"] for k in checks) and data["passed"] is True
    # the CPDI2 runs are accurate in both modes; the finest run is readable by load_run
    finest = max(verify.QUICK_RESOLUTIONS)
    for mode in verify.MODES:
        c = next(c for c in cases if c["scheme"] == "cpdi2" and c["mode"] == mode
                 and c["layout"] == "plane_strain" and c["cells_along"] == finest)
        assert c["passed"] and c["stress_error"] < 0.03
        run = axmpm.load_run(out / c["run_dir"])
        assert run.summary["status"] == "completed" and run.frames


def test_quick_report_and_figures(quick) -> None:
    out, _ = quick
    report = (out / REPORT).read_text()
    assert "| scheme | mode | formulation |" in report and "Enforced checks" in report
    assert "Original MPM" in report and "uGIMP" in report
    pngs = sorted((out / verify.FIGURES).glob("*.png"))
    assert {p.stem for p in pngs} >= {"convergence", "stress_plane_strain", "stress_axisymmetric_axis",
                                      "stress_axisymmetric_offset"}
    for p in pngs:
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert f"]({verify.FIGURES}/{p.name})" in report


# --------------------------------------------------------------------------- checks on fabricated cases


def fabricated(resolutions=(16, 32)) -> list[dict]:
    """Every case completed, with plausible errors that pass every check."""
    cases = []
    for spec in verify.run_specs(resolutions):
        c = {"case": "column_1d", "run": spec.name, "name": spec.name, **spec.params, **verify.EMPTY_METRICS,
             "run_dir": driver.run_dir_of("column_1d", spec), "status": "not run", "message": ""}
        scale = 16.0 / spec.params["cells_along"]
        c.update(status="completed", stress_error=0.008 * scale, displacement_error=0.001 * scale,
                 max_stress_error=0.02 * scale,
                 plane_strain_difference=None if spec.params["layout"] == "plane_strain" else 1e-6)
        c["passed"] = verify.case_passes(c)
        cases.append(c)
    return cases


def find(cases, scheme, mode, layout, n):
    return next(c for c in cases if (c["scheme"], c["mode"], c["layout"], c["cells_along"]) == (scheme, mode, layout, n))


def failing(checks) -> list[str]:
    return [c["name"] for c in checks if not c["passed"]]


def test_fabricated_good_results_pass() -> None:
    assert failing(verify.evaluate_checks(fabricated())) == []


def test_cpdi2_stress_error_of_5_percent_fails() -> None:
    cases = fabricated()
    c = find(cases, "cpdi2", "compression", "plane_strain", 32)
    c["stress_error"] = 0.05
    names = failing(verify.evaluate_checks(cases))
    assert any("CPDI2 compression, plane strain, finest grid: stress error" in n for n in names), names
    assert any("decreases with refinement" in n for n in names), names  # 0.8 % → 5 %


def test_cpdi2_displacement_and_cpgimp_fail() -> None:
    cases = fabricated()
    find(cases, "cpdi2", "tension", "axisymmetric_offset", 32)["displacement_error"] = 0.02
    find(cases, "cpgimp", "compression", "axisymmetric_axis", 32)["stress_error"] = 0.04
    names = failing(verify.evaluate_checks(cases))
    assert len(names) == 2, names
    assert "displacement error" in names[0] and "cpGIMP" in names[1]


def test_failed_or_missing_cpdi2_run_fails() -> None:
    cases = fabricated()
    c = find(cases, "cpdi2", "tension", "plane_strain", 32)
    c.update(status="failed", message="particle 0 left the grid", stress_error=None, displacement_error=None,
             max_stress_error=None, passed=False)
    names = failing(verify.evaluate_checks(cases))
    assert any("CPDI2 tension, plane strain, finest grid" in n for n in names)
    assert not verify.evaluate_checks([c for c in fabricated() if c["scheme"] != "cpdi2"])[0]["passed"]


def test_twin_disagreement_fails_and_convergence_needs_decrease() -> None:
    cases = fabricated()
    find(cases, "cpdi2", "tension", "axisymmetric_offset", 16)["plane_strain_difference"] = 0.01
    names = failing(verify.evaluate_checks(cases))
    assert names == ["cpdi2 tension n=16: axisymmetric, inner face 20 widths from the axis vs plane strain"]
    cases = fabricated()
    find(cases, "cpdi2", "compression", "axisymmetric_axis", 32)["stress_error"] = 0.009  # > 0.008 at n = 16
    names = failing(verify.evaluate_checks(cases))
    assert len(names) == 1 and "decreases with refinement" in names[0]


def test_linear_and_ugimp_failures_are_not_enforced() -> None:
    cases = fabricated()
    for c in cases:
        if c["scheme"] in ("linear", "ugimp") and c["mode"] == "tension":
            c.update(status="failed", stress_error=None, displacement_error=None, passed=False)
    assert failing(verify.evaluate_checks(cases)) == []


def test_main_exits_one_when_a_check_fails(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from axmpm.cli import main

    bad = fabricated()
    find(bad, "cpdi2", "compression", "plane_strain", 32)["stress_error"] = 0.05
    monkeypatch.setattr(driver, "run_cases",
                        lambda cases, options, out, **kw: {"column_1d": driver.Results(copy.deepcopy(bad))})
    monkeypatch.setattr(verify, "add_twin_differences", lambda cases, out: None)
    monkeypatch.setattr(verify, "make_figures", lambda results, out: {})
    assert main(["verify", "--out", str(tmp_path / "v"), "--quick", "--jobs", "1"]) == 1
    data = json.loads((tmp_path / "v" / RESULTS).read_text())
    assert data["passed"] is False and data["selected"] == ["column_1d"]
    assert "**FAIL**" in (tmp_path / "v" / REPORT).read_text()


def test_results_do_not_depend_on_jobs(tmp_path: Path) -> None:
    from axmpm.run.parallel import process_pool

    specs = [verify.run_spec("cpdi2", "tension", "plane_strain", 8), verify.run_spec("linear", "tension", "plane_strain", 8),
             verify.run_spec("ugimp", "compression", "axisymmetric_axis", 8)]
    serial = [driver.execute_run("column_1d", s, tmp_path / "a") for s in specs]
    with process_pool(2) as pool:
        pooled = list(pool.map(driver.execute_run, ["column_1d"] * 3, specs, [str(tmp_path / "b")] * 3))
    keys = ("name", "status", "stress_error", "displacement_error", "max_stress_error", "steps", "relative_error")
    assert [[c[k] for k in keys] for c in serial] == [[c[k] for k in keys] for c in pooled]
