"""The ``axmpm`` command: exit codes, messages without tracebacks, a real end-to-end run."""

from __future__ import annotations

import csv
import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import EXAMPLES, SETTLED_STOP, TINY_TOML, run_cli, settling_block


def assert_input_error(result: subprocess.CompletedProcess[str], *keys: str) -> None:
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr
    for key in keys:
        assert f"error: {key}: " in result.stderr, result.stderr


# --------------------------------------------------------------------------- version


def test_version_names_the_package_the_engine_and_its_instruction_set() -> None:
    from importlib.metadata import version

    from axmpm import _core

    result = run_cli("--version")
    assert result.returncode == 0, result.stderr
    assert result.stdout == f"axmpm {version('axmpm')} (engine {_core.__version__}, {_core.instruction_set()})\n"
    assert _core.instruction_set() in ("avx2", "baseline")


def test_version_reports_the_baseline_when_asked_for() -> None:
    env = dict(os.environ, AXMPM_ISA="baseline")
    result = subprocess.run([sys.executable, "-m", "axmpm.cli", "--version"], capture_output=True, text=True, env=env)
    assert result.returncode == 0, result.stderr
    assert result.stdout.rstrip().endswith(", baseline)")


# --------------------------------------------------------------------------- check / schema


def test_check_valid(tiny_toml: Path) -> None:
    result = run_cli("check", tiny_toml)
    assert result.returncode == 0, result.stderr
    assert "valid" in result.stdout and "200 particles" in result.stdout


def test_check_reports_all_errors(tiny_toml: Path) -> None:
    result = run_cli("check", tiny_toml, "--set", "materials.soil.poisson_ratio=0.7",
                     "--set", "simulation.cfl=0", "--set", "simulation.shape_functon=linear")
    assert_input_error(result, "materials.soil.poisson_ratio", "simulation.cfl", "simulation.shape_functon")
    assert "error: materials.soil.poisson_ratio: must be >= 0 and < 0.5 (got 0.7)" in result.stderr
    assert "did you mean 'shape_function'" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 3


def test_check_refuses_retired_and_experimental_material_keys(tiny_toml: Path) -> None:
    mohr_coulomb = ["--set", 'materials.soil.model="mohr_coulomb"', "--set", "materials.soil.friction_angle=30"]
    result = run_cli("check", tiny_toml, *mohr_coulomb, "--set", "materials.soil.recompaction=true")
    assert_input_error(result, "materials.soil.recompaction")
    assert "error: materials.soil.recompaction: is not a mohr_coulomb parameter (retired; see " \
           "docs/studies/granular-variants.md)" in result.stderr
    result = run_cli("check", tiny_toml, *mohr_coulomb, "--set", "materials.soil.critical_packing_fraction=0.35",
                     "--set", "materials.soil.grain_density=2500")
    assert_input_error(result, "materials.soil.critical_packing_fraction")
    assert "is experimental (measured, not validated): set experimental = true in [materials.soil] to use it" \
        in result.stderr
    result = run_cli("check", tiny_toml, *mohr_coulomb, "--set", "materials.soil.critical_packing_fraction=0.35",
                     "--set", "materials.soil.grain_density=2500", "--set", "materials.soil.experimental=true")
    assert result.returncode == 0, result.stderr


def test_check_cross_errors(tiny_toml: Path) -> None:
    result = run_cli("check", tiny_toml, "--set", "bodies.0.material=sand",
                     "--set", "simulation.formulation=axisymmetric", "--set", "boundaries.left=fixed")
    assert_input_error(result, "bodies.0.material", "boundaries.left")
    assert "always a roller" in result.stderr


def test_check_names_a_bad_xpic_order(tiny_toml: Path) -> None:
    for bad in ("0", "9", "2.5"):
        result = run_cli("check", tiny_toml, "--set", f"simulation.xpic_order={bad}")
        assert_input_error(result, "simulation.xpic_order")
    result = run_cli("check", tiny_toml, "--set", "simulation.xpic_order=3")
    assert_input_error(result, "simulation.xpic_order")
    assert "simulation.experimental = true" in result.stderr
    result = run_cli("check", tiny_toml, "--print", "--set", "simulation.xpic_order=3",
                     "--set", "simulation.experimental=true")
    assert result.returncode == 0, result.stderr
    assert "xpic_order = 3" in result.stdout


def test_check_refuses_xpic_for_a_saturated_run() -> None:
    example = EXAMPLES / "footing_saturated.toml"
    result = run_cli("check", example, "--set", "simulation.xpic_order=2", "--set", "simulation.experimental=true")
    assert_input_error(result, "simulation.xpic_order")
    assert "saturated" in result.stderr


def test_check_prints_resolved(tiny_toml: Path) -> None:
    result = run_cli("check", tiny_toml, "--print", "--set", "simulation.damping=0.2")
    assert result.returncode == 0
    assert "damping = 0.2" in result.stdout and "flip_fraction = 0.99" in result.stdout


def test_check_says_which_thread_count_its_estimate_assumes(tiny_toml: Path) -> None:
    result = run_cli("check", tiny_toml, "--threads", "1")
    assert result.returncode == 0, result.stderr
    assert "run time with 1 thread (--threads 1, as `axmpm run --threads 1`): about " in result.stdout
    result = run_cli("check", tiny_toml)
    assert result.returncode == 0, result.stderr
    assert "thread (the default of `axmpm run`: every core the problem can use" in result.stdout


def test_the_estimate_names_the_threads_it_was_measured_with() -> None:
    from axmpm.run.estimate import RunEstimate

    default = RunEstimate(1e-4, 1000, 20_000, threads=2, measured_steps=10, throughput=1e6, wall_seconds=20.0)
    assert "run time with 2 threads (the default of `axmpm run`" in default.describe()
    assert "about 20 s of run time" in default.describe()
    asked = RunEstimate(1e-4, 1000, 20_000, threads=3, measured_steps=10, throughput=1e6, wall_seconds=20.0,
                        requested_threads=3)
    assert "run time with 3 threads (--threads 3, as `axmpm run --threads 3`)" in asked.describe()


@pytest.mark.parametrize("command", ["check", "run"])
def test_a_negative_thread_count_is_refused(command: str, tiny_toml: Path, tmp_path: Path) -> None:
    out = ["--out", str(tmp_path / "out")] if command == "run" else []
    result = run_cli(command, tiny_toml, *out, "--threads", "-1")
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "argument --threads: must be an integer >= 0 (got -1)" in result.stderr


def test_check_missing_file(tmp_path: Path) -> None:
    result = run_cli("check", tmp_path / "absent.toml")
    assert_input_error(result)
    assert "not found" in result.stderr


def test_check_toml_syntax_error(tmp_path: Path) -> None:
    path = tmp_path / "broken.toml"
    path.write_text(TINY_TOML.replace("end_time = 0.1", "end_time = 0.1 s"))
    result = run_cli("check", path)
    assert_input_error(result)
    assert "line 4" in result.stderr  # end_time is on line 4


def test_check_bad_override_syntax(tiny_toml: Path) -> None:
    result = run_cli("check", tiny_toml, "--set", "bodies.3.min=[0,0]")
    assert_input_error(result, "bodies.3.min")


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_check_examples(path: Path) -> None:
    assert run_cli("check", path).returncode == 0


def test_schema_is_json() -> None:
    result = run_cli("schema")
    assert result.returncode == 0
    schema = json.loads(result.stdout)
    assert "simulation" in schema["properties"]


def test_run_rejects_invalid_scenario(tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    result = run_cli("run", tiny_toml, "--out", out, "--set", "grid.cell_size=-1")
    assert_input_error(result, "grid.cell_size")
    assert not out.exists()


# --------------------------------------------------------------------------- runs


def test_run_end_to_end(tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    started = time.perf_counter()
    result = run_cli("run", tiny_toml, "--out", out, "--threads", "2")
    assert result.returncode == 0, result.stderr
    assert time.perf_counter() - started < 20
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "completed"
    assert summary["particles"] == 200 and summary["steps"] > 0
    assert summary["end_time"] == pytest.approx(0.1, rel=1e-12)
    assert summary["particle_steps_per_second"] > 0
    assert summary["formulation"] == "plane_strain" and summary["shape_function"] == "linear"
    assert {"kinetic_energy", "gravity_work"} <= set(summary["energies"])
    # frames at 0, 0.025, 0.05, 0.075, 0.1
    assert len(list((out / "frames").glob("frame_*.vtu"))) == 5
    assert len(list((out / "frames").glob("frame_*.npz"))) == 5
    pvd = (out / "particles.pvd").read_text()
    assert pvd.count("<DataSet") == 5 and 'file="frames/frame_000004.vtu"' in pvd
    with open(out / "history.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [float(r["time"]) for r in rows] == pytest.approx([0, 0.025, 0.05, 0.075, 0.1])
    assert {"time", "steps", "dt", "kinetic_energy", "gravity_work"} <= set(rows[0])
    assert float(rows[-1]["gravity_work"]) > 0  # the block settled downwards
    # the resolved scenario is written and valid
    assert "flip_fraction = 0.99" in (out / "scenario.toml").read_text()
    assert run_cli("check", out / "scenario.toml").returncode == 0
    # no temporary files left behind
    assert not [p for p in out.rglob("*") if ".tmp" in p.name]


def test_run_replaces_a_previous_run(tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    assert run_cli("run", tiny_toml, "--out", out).returncode == 0
    result = run_cli("run", tiny_toml, "--out", out, "--set", "simulation.end_time=0.05")
    assert result.returncode == 0, result.stderr
    assert len(list((out / "frames").glob("*.vtu"))) == 3  # old frames are gone


def test_run_refuses_a_non_empty_folder(tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "thesis"
    out.mkdir()
    (out / "chapter1.tex").write_text("precious")
    (out / "figures").mkdir()
    (out / "figures" / "a.png").write_bytes(b"\x89PNG")
    before = sorted((p.relative_to(out), p.stat().st_mtime_ns) for p in out.rglob("*"))
    result = run_cli("run", tiny_toml, "--out", out)
    assert_input_error(result)
    assert "--overwrite" in result.stderr
    after = sorted((p.relative_to(out), p.stat().st_mtime_ns) for p in out.rglob("*"))
    assert after == before
    assert (out / "chapter1.tex").read_text() == "precious"


def test_run_overwrite_clears_the_folder(tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "scratch"
    out.mkdir()
    (out / "junk.txt").write_text("x")
    result = run_cli("run", tiny_toml, "--out", out, "--overwrite")
    assert result.returncode == 0, result.stderr
    assert not (out / "junk.txt").exists()
    assert json.loads((out / "summary.json").read_text())["status"] == "completed"


def test_run_failure_exit_3(tiny_toml: Path, tmp_path: Path) -> None:
    # A time step 30x the stable one makes the state invalid within a few steps.
    out = tmp_path / "boom"
    result = run_cli("run", tiny_toml, "--out", out, "--set", "simulation.time_step=0.01")
    assert result.returncode == 3, result.stdout + result.stderr
    assert "Traceback" not in result.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "failed" and summary["message"]
    assert summary["message"] in result.stderr
    assert (out / "frames" / "frame_000000.vtu").exists()  # frames already written are kept


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_run_interrupt_exit_130(tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "long"
    proc = subprocess.Popen(
        [sys.executable, "-m", "axmpm.cli", "run", str(tiny_toml), "--out", str(out),
         "--set", "simulation.end_time=1000", "--set", "simulation.output_interval=100"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        # a shell running us in the background may ignore SIGINT; give the child the default
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        summary_path = out / "summary.json"
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:  # wait until the run is stepping
            if summary_path.exists() and (out / "frames" / "frame_000000.npz").exists():
                break
            time.sleep(0.05)
        time.sleep(0.5)
        proc.send_signal(signal.SIGINT)
        _, stderr = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr
    summary = json.loads(summary_path.read_text())
    assert summary["status"] == "interrupted"
    assert 0 < summary["steps"] and 0 < summary["end_time"] < 1000


def test_demo(tmp_path: Path) -> None:
    out = tmp_path / "demo"
    result = run_cli("demo", "--column", "--out", out)
    assert result.returncode == 0, result.stderr
    assert "particle-steps/s" in result.stdout
    assert "vertical stress error vs exact" in result.stdout
    assert json.loads((out / "summary.json").read_text())["status"] == "completed"


def test_run_stops_once_at_rest(tmp_path):
    """A block dropped onto a fixed base with strong damping comes to rest well before
    end_time; with stop_at_rest the run ends there, status completed."""
    import axmpm

    scenario = settling_block(end_time=50.0, stop_at_rest=1e-4)
    summary = axmpm.run(scenario, tmp_path / "rest")
    assert summary["status"] == "completed"
    assert summary["stopped_at_rest"] is True
    assert 0.5 <= summary["end_time"] < 50.0
    e = summary["energies"]
    assert e["kinetic_energy"] < 1e-4 * e["gravity_work"]


def test_settled_rule_on_series():
    """stop_when_settled compares the work of gravity over the last settle_window with the
    total: a curve that has flattened is settled, one still rising or bouncing is not."""
    from types import SimpleNamespace

    from axmpm.run.runner import _settled

    cfg = SimpleNamespace(stop_when_settled=1e-3, settle_window=0.1, stop_at_rest_after=0.2)
    times = [0.02 * k for k in range(31)]
    flat = [(t, 1.0 - math.exp(-t / 0.02)) for t in times]  # settled long before 0.6 s
    rising = [(t, t) for t in times]
    bouncing = [(t, 1.0 + 0.2 * math.sin(2 * math.pi * t / 0.14)) for t in times]
    assert _settled(flat, 0.6, cfg)
    assert not _settled(flat, 0.1, cfg)  # before stop_at_rest_after
    assert not _settled(flat[:4], 0.06, SimpleNamespace(**(cfg.__dict__ | {"stop_at_rest_after": 0.0})))  # no window yet
    assert not _settled(rising, 0.6, cfg)
    assert not _settled(bouncing, 0.6, cfg)
    assert not _settled(flat, 0.6, SimpleNamespace(**(cfg.__dict__ | {"stop_when_settled": 0.0})))  # off


def test_run_stops_once_settled(tmp_path):
    """With the kinetic-energy test off, stop_when_settled ends a damped block dropped on a
    fixed base once it no longer moves down; without it the run goes to end_time."""
    import axmpm

    scenario = settling_block(**SETTLED_STOP)
    summary = axmpm.run(scenario, tmp_path / "settled")
    assert summary["status"] == "completed" and summary["stopped_at_rest"] is True
    assert 1.0 <= summary["end_time"] < 20.0  # at least one settle_window of history
    import numpy as np

    h = np.genfromtxt(tmp_path / "settled" / "history.csv", delimiter=",", names=True)
    i = np.searchsorted(h["time"], h["time"][-1] - 1.0 - 1e-9)
    assert abs(h["gravity_work"][-1] - h["gravity_work"][i]) < 1e-4 * h["gravity_work"][-1]
    scenario["simulation"]["stop_when_settled"] = 0.0
    scenario["simulation"]["end_time"] = 4.0
    full = axmpm.run(scenario, tmp_path / "full")
    assert full["stopped_at_rest"] is False and full["end_time"] == pytest.approx(4.0)


# --------------------------------------------------------------------------- bench


def test_bench_linear_elastic_runs_the_elastic_column() -> None:
    result = run_cli("bench", "--material", "linear_elastic", "--cell-size", "0.005", "--steps", "2",
                     "--warmup", "0", "--schemes", "linear", "--formulations", "plane_strain",
                     "--threads", "1", "--json")
    assert result.returncode == 0, result.stderr
    (record,) = json.loads(result.stdout)["results"]
    assert record["material"] == "linear_elastic" and record["steps"] == 2
    # 20 × 25 cells of 5 mm, 2 × 2 particles per cell.
    assert record["particles"] == 2000


def test_bench_rejects_an_unknown_material() -> None:
    result = run_cli("bench", "--material", "granite", "--steps", "1")
    assert result.returncode == 2 and "granite" in result.stderr


def test_validate_names_a_bad_builder_parameter_without_a_traceback(tmp_path: Path) -> None:
    # Builder parameters (bare --set keys) are checked before anything runs: exit 2, the key named.
    for item, key in [("material_model=druker", "material_model"),
                      ("friction_coefficient=2", "friction_coefficient"),
                      ("gate_speed=-1", "gate_speed")]:
        extra = ["--set", "material_model=drucker_prager"] if key == "friction_coefficient" else []
        result = run_cli("validate", "--case", "column_collapse", "--aspect-ratios", "0.5", "--cell-size", "0.004",
                         "--set", item, *extra, "--out", tmp_path / key)
        assert_input_error(result, key)
        assert not (tmp_path / key / "cases").exists()
