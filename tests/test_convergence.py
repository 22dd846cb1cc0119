"""axmpm convergence: Richardson extrapolation and the command end to end."""

import json
import math
import subprocess
import sys

import pytest

from axmpm.study.convergence import constant_ratio, richardson


@pytest.mark.parametrize("order", [1.0, 1.5, 2.0])
def test_richardson_recovers_order_and_limit_of_a_power_law(order):
    limit, c = -0.1, 0.8
    hs = [0.004, 0.002, 0.001, 0.0005]
    values = [limit + c * h**order for h in hs]
    est = richardson(values, 2.0)
    assert est["converging"]
    assert est["order"] == pytest.approx(order, rel=1e-9)
    assert est["extrapolated"] == pytest.approx(limit, abs=1e-12)


def test_richardson_flags_growth_and_oscillation():
    assert richardson([0.43, 0.59, 0.74], 2.0)["converging"] is False  # steps do not shrink
    assert richardson([0.40, 0.50, 0.45], 2.0)["converging"] is False  # sign change
    assert richardson([0.4, 0.5], 2.0)["converging"] is None  # two meshes: no estimate
    assert richardson([0.43, 0.59, 0.60], 2.0)["converging"] is True


def test_richardson_takes_round_off_changes_as_converged():
    est = richardson([1e-16, -2e-17, 3e-17], 2.0)
    assert est["converging"] is True and est["extrapolated"] == pytest.approx(0.0, abs=1e-15)


def test_constant_ratio():
    assert constant_ratio([0.002, 0.001, 0.0005]) == pytest.approx(2.0)
    assert constant_ratio([0.003, 0.002, 0.001]) is None
    assert math.isclose(constant_ratio([0.004, 0.002, 0.001, 0.0005]), 2.0)


def test_command_runs_three_meshes_and_writes_report(tmp_path):
    out = tmp_path / "conv"
    cmd = [sys.executable, "-m", "axmpm", "convergence", "--cases", "a056",
           "--cell-sizes", "0.006,0.003,0.0015", "--set", "end_time=0.04", "--jobs", "1", "--out", str(out)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    data = json.loads((out / "convergence.json").read_text())
    assert data["refinement_ratio"] == pytest.approx(2.0)
    (case,) = data["cases"]
    assert [m["cell_size"] for m in case["meshes"]] == [0.006, 0.003, 0.0015]
    assert [round(m["cells_per_radius"]) for m in case["meshes"]] == [5, 10, 20]
    for key in ("runout_edge", "runout_one_grain", "final_height"):
        assert set(case["richardson"][key]) == {"converging", "order", "extrapolated"}
    assert (out / "convergence.md").read_text().count("| a056 |") == 4
    assert (out / "convergence.png").stat().st_size > 0
    assert (out / "h1.5mm" / "cases" / "column_collapse" / "a056" / "particles.pvd").exists()


@pytest.mark.parametrize("args,text", [
    (["--cell-sizes", "0.002,abc"], "--cell-sizes"),
    (["--cell-sizes", "0.002,-0.001"], "--cell-sizes"),
    (["--cases", "a99"], "unknown case"),
    (["--set", "cell_size=0.001"], "--cell-sizes"),
])
def test_bad_arguments_exit_2_without_traceback(tmp_path, args, text):
    proc = subprocess.run([sys.executable, "-m", "axmpm", "convergence", "--out", str(tmp_path / "x"), *args],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert text in proc.stderr + proc.stdout
    assert "Traceback" not in proc.stderr


def test_completed_meshes_are_reused(tmp_path):
    out = tmp_path / "conv"
    base = [sys.executable, "-m", "axmpm", "convergence", "--cases", "a056", "--set", "end_time=0.02",
            "--jobs", "1", "--out", str(out)]
    first = subprocess.run(base + ["--cell-sizes", "0.006,0.003"], capture_output=True, text=True, timeout=600)
    assert first.returncode == 0, first.stderr
    marker = out / "h6mm" / "cases" / "column_collapse" / "a056" / "summary.json"
    before = marker.stat().st_mtime_ns
    second = subprocess.run(base + ["--cell-sizes", "0.006,0.003,0.0015"], capture_output=True, text=True,
                            timeout=600)
    assert second.returncode == 0, second.stderr
    assert marker.stat().st_mtime_ns == before  # 6 mm not run again
    data = json.loads((out / "convergence.json").read_text())
    assert [m["cell_size"] for m in data["cases"][0]["meshes"]] == [0.006, 0.003, 0.0015]


def test_profile_difference_of_deposits(tmp_path):
    """0 for a deposit against itself, between 0 and 2 for two meshes of the same column,
    refused for columns of different aspect ratio."""
    import axmpm
    from axmpm.cases.column_collapse import collapse_scenario, profile_difference

    dirs = {}
    for name, a, h in (("c6", 0.8, 0.006), ("c3", 0.8, 0.003), ("tall", 1.6, 0.006)):
        dirs[name] = tmp_path / name
        axmpm.run(collapse_scenario(a, cell_size=h, end_time=0.06), dirs[name], threads=1)
    assert profile_difference(dirs["c3"], dirs["c3"]) == 0.0
    d = profile_difference(dirs["c6"], dirs["c3"])
    assert 0.0 < d < 2.0
    assert d == pytest.approx(profile_difference(dirs["c6"], dirs["c3"]), rel=0, abs=0)  # deterministic
    with pytest.raises(ValueError, match="not the same column"):
        profile_difference(dirs["tall"], dirs["c3"])


def test_table_shows_profile_difference():
    """The table prints each mesh's deposit difference to the finest mesh (— if absent)."""
    from axmpm.study.convergence import table

    mesh = {"cell_size": 0.002, "cells_per_radius": 15.0, "aspect_ratio": 0.8, "status": "completed",
            "wall_seconds": 1.0, "profile_difference": 0.132}
    for key in ("runout_one_grain", "runout_edge", "final_height"):
        mesh[key], mesh[key + "_rel_diff"] = 0.9, -0.05
    finest = {**mesh, "cell_size": 0.001, "profile_difference": None}
    none = {"converging": None, "order": None, "extrapolated": None}
    summary = {"cases": [{"name": "a08", "meshes": [mesh, finest],
                          "richardson": {k: none for k in ("runout_one_grain", "runout_edge", "final_height")}}]}
    text = table(summary)
    assert "| 13.2 % |" in text and "| — | 1 |" in text
