"""`axmpm sweep` and `axmpm calibrate`: Dask sweeps of tiny scenarios (< 1 s per run).

One in-process cluster (2 single-threaded workers, TCP so that a CLI subprocess can reach
it through --scheduler) serves most tests; one test starts the default LocalCluster of
processes through the CLI.
"""

from __future__ import annotations

import csv
import math
import shutil
from pathlib import Path

import pytest

from conftest import EXAMPLES, run_cli

import distributed  # noqa: F401  (a dependency: a broken install fails here, it is not skipped)

from axmpm.study import calibration as cal  # noqa: E402
from axmpm.study import sweep  # noqa: E402

POISSON = "materials.soil.poisson_ratio"
DT = "simulation.time_step"


@pytest.fixture(scope="module")
def cluster():
    import logging

    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, protocol="tcp",
                      dashboard_address=None, silence_logs=logging.ERROR) as c, Client(c) as client:
        yield c, client


def _rows(path: Path) -> tuple[list[str], list[dict[str, str]]]:
    with open(path, newline="") as fh:
        reader = csv.DictReader(fh)
        return list(reader.fieldnames or []), list(reader)


# --------------------------------------------------------------------------- values, names


def test_parse_values():
    assert sweep.parse_values("1,2,3") == [1, 2, 3]
    assert sweep.parse_values("18:34:4") == [18, 22, 26, 30, 34]
    assert sweep.parse_values("0.1:0.5:0.1") == [0.1, 0.2, 0.3, 0.4, 0.5]  # STOP included
    assert sweep.parse_values("1:2:0.3") == [1.0, 1.3, 1.6, 1.9]
    assert sweep.parse_values("lin:0:1:5") == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert sweep.parse_values("log:1e5:5e7:5") == [1e5, 472871.0, 2236070.0, 10573700.0, 5e7]
    assert sweep.parse_values("[0.1,0.2],[0.3,0.4]") == [[0.1, 0.2], [0.3, 0.4]]
    assert sweep.parse_values("roller,fixed") == ["roller", "fixed"]
    for bad in ("1:2:0", "2:1:1", "log:0:1:3", "lin:0:1:0"):
        with pytest.raises(ValueError):
            sweep.parse_values(bad)
    assert sweep.parse_param("a.b=1,2") == ("a.b", [1, 2])
    with pytest.raises(sweep.ScenarioError):
        sweep.parse_param("a.b")


def test_run_names_are_deterministic_and_safe():
    v = {"materials.sand.friction_angle": 30.0, "materials.sand.youngs_modulus": 316228.0}
    assert sweep.run_name(v) == "materials.sand.friction_angle=30__materials.sand.youngs_modulus=316228"
    odd = sweep.run_name({"a": "x/y"})
    assert "/" not in odd and odd == sweep.run_name({"a": "x/y"}) and odd != sweep.run_name({"a": "x y"})
    assert len(sweep.run_name({"k" * 100: "v" * 200})) <= sweep.MAX_NAME


# --------------------------------------------------------------------------- sweeps


def test_sweep_cli_local_cluster_invalid_value_and_resume(tiny_toml, tmp_path):
    """Default path: a 2-process LocalCluster; an invalid value fails alone; the second call
    skips what completed and reruns nothing (so starts no cluster)."""
    out = tmp_path / "sweep"
    args = ["sweep", tiny_toml, "--param", f"{POISSON}=0.3,0.7", "--param", "materials.soil.density=1000,2000",
            "--set", "simulation.end_time=0.05", "--out", out, "--workers", "2", "--no-progress"]
    r = run_cli(*args)
    assert r.returncode == 3, r.stderr  # some runs failed
    cols, rows = _rows(out / "results.csv")
    assert cols[:5] == ["run", POISSON, "materials.soil.density", "status", "error"]
    for c in ("steps", "end_time", "wall_seconds", "particle_steps_per_second", "kinetic_energy", "gravity_work"):
        assert c in cols
    assert len(rows) == 4
    good = [x for x in rows if float(x[POISSON]) == 0.3]
    bad = [x for x in rows if float(x[POISSON]) == 0.7]
    for x in good:
        assert x["status"] == "completed" and x["error"] == "" and int(x["steps"]) > 0
        assert math.isclose(float(x["end_time"]), 0.05)
        assert (out / "runs" / x["run"] / "summary.json").exists()
    for x in bad:
        assert x["status"] == "failed" and "poisson_ratio" in x["error"] and "< 0.5" in x["error"]
        assert not (out / "runs" / x["run"]).exists()
    assert good[0]["run"] == "materials.soil.poisson_ratio=0.3__materials.soil.density=1000"
    assert "failed" in r.stderr

    stamps = {x["run"]: (out / "runs" / x["run"] / "summary.json").stat().st_mtime_ns for x in good}
    r2 = run_cli(*args)
    assert r2.returncode == 3
    assert "skipped 2 already completed" in r2.stdout
    for name, stamp in stamps.items():  # not rerun
        assert (out / "runs" / name / "summary.json").stat().st_mtime_ns == stamp
    _, rows2 = _rows(out / "results.csv")
    assert [(x["run"], x["status"], x["steps"]) for x in rows2] == [(x["run"], x["status"], x["steps"]) for x in rows]


def test_blow_up_isolated_and_retried(cluster, tiny_toml, tmp_path):
    """An engine failure is one failed row with the engine's message; resume retries it."""
    _, client = cluster
    out = tmp_path / "blow"
    params = {DT: [0.0, 0.002]}
    kw = dict(client=client, log=None, progress=False)
    first = sweep.run_sweep(tiny_toml, params, out, ["simulation.end_time=0.05"], **kw)
    ok, blown = first.rows
    assert ok["status"] == "completed" and blown["status"] == "failed"
    assert "deformation gradient" in blown["error"]
    assert (first.completed, first.failed) == (1, 1)
    second = sweep.run_sweep(tiny_toml, params, out, ["simulation.end_time=0.05"], **kw)
    assert (second.submitted, second.skipped) == (1, 1)


def test_sweep_scheduler_option(cluster, tiny_toml, tmp_path):
    """--scheduler: the runs go to an existing cluster (started here)."""
    c, _ = cluster
    out = tmp_path / "sched"
    r = run_cli("sweep", tiny_toml, "--param", "materials.soil.youngs_modulus=log:1e5:1e6:2",
                "--set", "simulation.end_time=0.05", "--out", out, "--scheduler", c.scheduler_address)
    assert r.returncode == 0, r.stderr
    assert "2 completed, 0 failed" in r.stdout
    _, rows = _rows(out / "results.csv")
    assert [x["status"] for x in rows] == ["completed", "completed"]
    assert [float(x["materials.soil.youngs_modulus"]) for x in rows] == [1e5, 1e6]
    # a stiffer soil needs more (shorter) steps
    assert int(rows[1]["steps"]) > int(rows[0]["steps"])


def test_resume_runs_only_missing_or_changed(cluster, tiny_toml, tmp_path):
    _, client = cluster
    out = tmp_path / "resume"
    params = {"materials.soil.density": [1000.0, 1500.0, 2000.0]}
    kw = dict(client=client, log=None, progress=False)
    first = sweep.run_sweep(tiny_toml, params, out, ["simulation.end_time=0.05"], **kw)
    assert (first.submitted, first.skipped, first.completed) == (3, 0, 3)
    names = [r["run"] for r in first.rows]
    shutil.rmtree(out / "runs" / names[1])
    second = sweep.run_sweep(tiny_toml, params, out, ["simulation.end_time=0.05"], **kw)
    assert (second.submitted, second.skipped, second.completed) == (1, 2, 3)
    # a changed --set changes the resolved scenario: every run is redone
    third = sweep.run_sweep(tiny_toml, params, out, ["simulation.end_time=0.04"], **kw)
    assert (third.submitted, third.skipped) == (3, 0)
    rows = sweep.read_results(out / "results.csv")
    assert [r["end_time"] for r in rows] == pytest.approx([0.04] * 3)


def test_sweep_cli_input_errors(tiny_toml, tmp_path, capsys):
    from axmpm.cli import main

    assert main(["sweep", str(tiny_toml), "--param", "a.b=1:2:0", "--out", str(tmp_path / "x")]) == 2
    assert "a.b" in capsys.readouterr().err
    assert main(["sweep", str(tiny_toml), "--param", "a.b=1", "--param", "a.b=2", "--out", str(tmp_path / "x")]) == 2
    assert "more than once" in capsys.readouterr().err


# --------------------------------------------------------------------------- calibrate


def _fake(E, phi, rs, hs, a=0.56, status="completed"):
    return {"materials.sand.youngs_modulus": E, "materials.sand.friction_angle": phi, "status": status,
            "aspect_ratio": a, "runout_normalised": rs, "final_height_normalised": hs}


def test_misfit_and_best_pick():
    # Lube 2004 at a = 0.56: R* = 1.24 a = 0.6944, H* = a = 0.56
    assert cal.misfit(0.6944, 0.56, 0.6944, 0.56) == 0.0
    assert cal.misfit(0.6944 * 1.2, 0.56 * 0.9, 0.6944, 0.56) == pytest.approx(math.sqrt((0.04 + 0.01) / 2))
    assert cal.misfit(0.5, 0.3, 0.5, None) == 0.0  # runout only where the law has no height
    assert math.isnan(cal.misfit(None, None, 0.5, 0.5))
    lr, lh = cal.law_prediction(0.56)
    assert (lr, lh) == pytest.approx((1.24 * 0.56, 0.56))

    rows = []
    for E in (1e5, 1e6, 1e7):
        for phi in (20.0, 25.0, 30.0):
            # runout falls with phi and E; best near (1e6, 25)
            rs = 0.6944 * (1 + 0.05 * (phi - 25) / 5 * -1 * 4 + 0.1 * math.log10(E / 1e6) * -1)
            rows.append(_fake(E, phi, rs, 0.56))
    rows.append(_fake(1e8, 25.0, None, None, status="failed"))
    scored = cal.score_rows(rows)
    assert math.isnan(scored[-1]["misfit"])
    best = cal.pick_best(scored)
    assert (best["materials.sand.youngs_modulus"], best["materials.sand.friction_angle"]) == (1e6, 25.0)
    assert best["misfit"] == pytest.approx(0.0, abs=1e-12)
    s = cal.sensitivity(scored, best, "materials.sand.youngs_modulus", "materials.sand.friction_angle")
    assert len(s["neighbours"]) == 8 and s["on_edge"] == []
    assert s["neighbour_min"] > 0 and s["neighbour_spread"] == pytest.approx(s["neighbour_max"])
    # ties: the first row wins; all failed: nothing picked
    tie = cal.score_rows([_fake(1, 20, 0.7, 0.56), _fake(2, 20, 0.7, 0.56)])
    assert cal.pick_best(tie)["materials.sand.youngs_modulus"] == 1
    assert cal.pick_best(cal.score_rows([_fake(1, 20, None, None, status="failed")])) is None


def test_snap_overrides_keep_scenario_valid(tmp_path):
    import axmpm.cases.column_collapse as collapse
    from axmpm.scenario import Scenario, apply_overrides

    data = collapse.collapse_scenario(0.56, as_dict=True)
    s = Scenario.from_dict(apply_overrides(data, cal.snap_overrides(data, 0.006)))
    assert s.grid.cell_size == 0.006 and s.bodies[0].max[0] == pytest.approx(0.03)


def test_swept_friction_angle_moves_k0_and_every_base_coefficient():
    """The builder's base is a friction wall (walls.0) above a friction bottom face; both
    follow tan φ, the removable side wall (roller) does not."""
    import axmpm.cases.column_collapse as collapse
    data = collapse.collapse_scenario(0.56, material_model="mohr_coulomb", as_dict=True)
    bodies, keys = cal._linked(data, "sand", {})
    assert bodies == [0]
    assert keys == ["boundaries.bottom.coefficient", "walls.0.coefficient"]
    vals = cal._phi_values(30.0, "sand", bodies, keys)
    mu = math.tan(math.radians(30.0))
    assert vals["walls.0.coefficient"] == pytest.approx(mu) and vals["boundaries.bottom.coefficient"] == pytest.approx(mu)
    assert vals["bodies.0.k0"] == pytest.approx(1 - math.sin(math.radians(30.0)))
    assert cal._linked(data, "sand", {"link_base_friction": False})[1] == []


def _collapse_config(tmp_path: Path) -> Path:
    """A config on the examples, or on scenarios built by collapse_scenario if missing."""
    names = ["column_collapse_a056.toml", "column_collapse_a08.toml", "column_collapse_a54.toml"]
    if all((EXAMPLES / n).exists() for n in names):
        paths = [EXAMPLES / n for n in names]
    else:
        import tomli_w

        import axmpm.cases.column_collapse as collapse
        paths = []
        for n, a in zip(names, (0.56, 0.8, 5.4)):
            p = tmp_path / n
            p.write_text(tomli_w.dumps(collapse.collapse_scenario(a, material_model="mohr_coulomb", as_dict=True)))
            paths.append(p)
    cfg = tmp_path / "calibrate.toml"
    cfg.write_text(f'scenario = "{paths[0]}"\npredict = ["{paths[1]}", "{paths[2]}"]\n'
                   '[quick]\nyoungs_modulus = [1e5, 3e5]\nfriction_angle = [20.0, 30.0]\nend_time = 0.2\n')
    return cfg


def test_calibrate_quick_smoke(cluster, tmp_path):
    _, client = cluster
    out = tmp_path / "cal"
    result = cal.calibrate(out, _collapse_config(tmp_path), quick=True, client=client, log=None, progress=False)
    assert len(result.scored) == 4
    assert result.best is not None and math.isfinite(result.best["misfit"])
    assert [p["status"] for p in result.predictions] == ["completed", "completed"]
    for p in result.predictions:
        assert p["runout_error"] is not None
    report = (out / "report.md").read_text()
    for text in ("Chosen values", "Sensitivity", "Blind prediction", "misfit.png", "comparison.png", "Quick mode"):
        assert text in report
    assert (out / "misfit.png").stat().st_size > 0 and (out / "comparison.png").stat().st_size > 0
    assert (out / "calibration" / "results.csv").exists() and (out / "prediction" / "results.csv").exists()


def test_shipped_1mm_calibration_config_resolves_and_stays_on_grid():
    """examples/calibration/1mm.toml: its scenarios exist, and with its overrides every
    scenario is valid on the 1 mm grid (bodies and walls on grid lines)."""
    from axmpm.scenario import Scenario, apply_overrides

    cfg = cal.load_config(EXAMPLES / "calibration" / "1mm.toml")
    assert cfg["set"] == ["grid.cell_size=0.001"]
    for path in [cfg["scenario"], *cfg["predict"]]:
        assert Path(path).exists()
        data = Scenario.from_toml(path).to_dict()
        s = Scenario.from_dict(apply_overrides(data, cfg["set"]))
        assert s.grid.cell_size == 0.001
