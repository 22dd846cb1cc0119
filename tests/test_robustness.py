"""Issue #5, robustness: bad input exits 2 without a traceback; failed, interrupted and
killed runs keep a checkpoint at an output time; ``axmpm resume`` completes them bit for bit;
every output file is written atomically. See docs/robustness.md."""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
import pytest

import axmpm.run.runner as runner
from axmpm.cli import main
from axmpm.run.output import CHECKPOINT, HistoryWriter, load_run, read_checkpoint, write_json, write_text
from axmpm.run.runner import checkpoint_every, resume, run
from axmpm.scenario import Scenario, ScenarioError, apply_overrides

from conftest import SETTLED_STOP, TINY_TOML, settling_block

STATE = ("x", "v", "stress", "F", "volume", "state")


def base() -> dict:
    return tomllib.loads(TINY_TOML)


def cli(capsys: pytest.CaptureFixture[str], *args: object) -> tuple[int, str, str]:
    """``axmpm ARGS`` in-process: (exit code, stdout, stderr)."""
    code = main([str(a) for a in args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def assert_same_final_state(a: Path, b: Path) -> None:
    ra, rb = load_run(a), load_run(b)
    assert ra.last.time == rb.last.time and ra.last.steps == rb.last.steps
    for name in STATE:
        assert np.array_equal(getattr(ra.last, name), getattr(rb.last, name)), name


def run_interrupted(monkeypatch: pytest.MonkeyPatch, data: dict, out: Path, after_records: int) -> None:
    """Run ``data`` into ``out`` and send SIGINT after its ``after_records``-th output (the
    first is t = 0): the run stops cleanly with status interrupted (KeyboardInterrupt)."""
    original = runner._Driver.record
    calls = {"n": 0}

    def record(self):
        original(self)
        calls["n"] += 1
        if calls["n"] == after_records:
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(runner._Driver, "record", record)
    # A process started in the background by a non-interactive shell (as CI may be) inherits
    # SIGINT ignored; restore Python's own handler, as an interactive session has it.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            run(data, out, threads=1)
    finally:
        signal.signal(signal.SIGINT, previous)
        monkeypatch.setattr(runner._Driver, "record", original)


# --------------------------------------------------------------------------- bad input → exit 2

BAD_INPUT = [
    ("materials.soil.youngs_modulus=0", "materials.soil.youngs_modulus", "must be > 0"),
    ("materials.soil.youngs_modulus=-1e6", "materials.soil.youngs_modulus", "must be > 0"),
    ("materials.soil.poisson_ratio=0.5", "materials.soil.poisson_ratio", "< 0.5"),
    ("materials.soil.poisson_ratio=-0.1", "materials.soil.poisson_ratio", ">= 0"),
    ("materials.soil.density=0", "materials.soil.density", "must be > 0"),
    ("grid.cell_size=0", "grid.cell_size", "must be > 0"),
    ("bodies.0.particles_per_cell=0", "bodies.0.particles_per_cell", ">= 1"),
    ("bodies.0.particles_per_cell=9", "bodies.0.particles_per_cell", "<= 8"),
    ("bodies.0.particles_per_cell=2.5", "bodies.0.particles_per_cell", "integer"),
    ("simulation.output_interval=0", "simulation.output_interval", "must be > 0"),
    ("simulation.end_time=-1", "simulation.end_time", "must be > 0"),
    ("simulation.end_time='long'", "simulation.end_time", "valid number"),
    ("simulation.end_time=nan", "simulation.end_time", "finite"),
    ("simulation.checkpoint_interval=0", "simulation.checkpoint_interval", "must be > 0"),
    ("simulation.output_interval=1e-9", "simulation.output_interval", "output frames"),
    ("bodies.0.max=[0.05, 0.3]", "bodies.0.max.1", "inside the grid"),
    ("bodies.0.min=[-0.01, 0.0]", "bodies.0.min.0", "inside the grid"),
    ("bodies.0.material='sand'", "bodies.0.material", "unknown material"),
    ("bodies.0.allow_overlap='yes'", "bodies.0.allow_overlap", "boolean"),
    ("grid.extent=[1e300, 0.2]", "grid.extent.0", "cells"),
    ("simulation.shape_functon='linear'", "simulation.shape_functon", "did you mean 'shape_function'"),
    ("simulaton.end_time=1", "simulaton", "did you mean 'simulation'"),
    ("materials.soil.densty=1000", "materials.soil.densty", "did you mean 'density'"),
    ("boundaries.bottom.coeficient=0.5", "boundaries.bottom.coeficient", "did you mean 'coefficient'"),
    ("bodies.0.particles_per_cel=2", "bodies.0.particles_per_cel", "did you mean 'particles_per_cell'"),
    ("boundries.left='roller'", "boundries", "did you mean 'boundaries'"),
]

MC = ["materials.soil.model='mohr_coulomb'", "materials.soil.friction_angle=30"]
BAD_MOHR_COULOMB = [
    ("materials.soil.friction_angle=0", "materials.soil.friction_angle", "> 0"),
    ("materials.soil.friction_angle=90", "materials.soil.friction_angle", "< 90"),
    ("materials.soil.dilation_angle=31", "materials.soil.dilation_angle", "<= friction_angle"),
    ("materials.soil.dilation_angle=-1", "materials.soil.dilation_angle", ">= 0"),
    ("materials.soil.cohesion=-5", "materials.soil.cohesion", ">= 0"),
]


@pytest.mark.parametrize(("override", "key", "text"), BAD_INPUT + [(o, k, t) for o, k, t in BAD_MOHR_COULOMB])
def test_bad_input_exits_2_naming_the_key(capsys, tiny_toml: Path, override: str, key: str, text: str) -> None:
    extra = [] if (override, key, text) in BAD_INPUT else [a for m in MC for a in ("--set", m)]
    code, _, err = cli(capsys, "check", tiny_toml, *extra, "--set", override)
    assert code == 2, err
    assert "Traceback" not in err
    line = next((ln for ln in err.splitlines() if ln.startswith(f"error: {key}: ")), None)
    assert line is not None, err
    assert text in line, line


def test_bad_input_for_run_exits_2_and_writes_nothing(capsys, tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    code, _, err = cli(capsys, "run", tiny_toml, "--out", out, "--set", "materials.soil.poisson_ratio=0.5")
    assert code == 2 and "Traceback" not in err and "materials.soil.poisson_ratio" in err
    assert not out.exists()


def overlapping() -> dict:
    return apply_overrides(base(), ["bodies.1={material='soil', min=[0.0, 0.05], max=[0.05, 0.15]}"])


def test_overlapping_bodies_are_refused() -> None:
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(overlapping())
    assert info.value.keys == ["bodies.1"]
    assert "overlaps bodies.0 ('block')" in info.value.render() and "allow_overlap" in info.value.render()


@pytest.mark.parametrize("which", [0, 1])
def test_allow_overlap_on_either_body_permits_it(which: int) -> None:
    s = Scenario.from_dict(apply_overrides(overlapping(), [f"bodies.{which}.allow_overlap=true"]))
    assert s.bodies[which].allow_overlap and not s.bodies[1 - which].allow_overlap


def test_touching_bodies_do_not_overlap() -> None:
    data = apply_overrides(base(), ["bodies.1={material='soil', min=[0.05, 0.0], max=[0.1, 0.1]}",
                                    "bodies.2={material='soil', min=[0.0, 0.1], max=[0.05, 0.15]}"])
    assert len(Scenario.from_dict(data).bodies) == 3


def test_new_keys_default_and_round_trip() -> None:
    s = Scenario.from_dict(base())
    assert s.simulation.checkpoint_interval is None and s.bodies[0].allow_overlap is False
    again = Scenario.from_dict(tomllib.loads(s.to_toml()))
    assert again == s


def test_axisymmetric_grid_must_start_on_the_axis(capsys, tiny_toml: Path) -> None:
    code, _, err = cli(capsys, "check", tiny_toml, "--set", "simulation.formulation='axisymmetric'",
                       "--set", "grid.origin=[0.01, 0.0]", "--set", "bodies.0.min=[0.01, 0.0]")
    assert code == 2 and "error: grid.origin.0: axisymmetric grids start on the axis" in err


def test_check_reports_field_and_cross_errors_at_once(capsys, tiny_toml: Path) -> None:
    # a field error (poisson_ratio) together with cross errors (material reference, overlap,
    # body outside the grid) that used to wait until every field was valid
    code, _, err = cli(capsys, "check", tiny_toml, "--set", "materials.soil.poisson_ratio=0.7",
                       "--set", "bodies.0.material='sandd'",
                       "--set", "bodies.1={material='soil', min=[0.0, 0.0], max=[0.05, 0.3]}",
                       "--set", "simulation.cfl=0")
    assert code == 2 and "Traceback" not in err
    keys = [ln.removeprefix("error: ").split(": ")[0] for ln in err.strip().splitlines()]
    assert set(keys) == {"materials.soil.poisson_ratio", "simulation.cfl", "bodies.0.material",
                         "bodies.1.max.1", "bodies.1"}, err
    assert len(keys) == 5


def test_cross_errors_skip_parts_with_field_errors() -> None:
    # bodies.0 is invalid itself: no cross error is reported for it on top of its field error
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(apply_overrides(base(), ["bodies.0.max=[0.05, 'x']", "bodies.0.material='nope'"]))
    assert info.value.keys == ["bodies.0.max.1"]


def test_missing_material_section_reported_once() -> None:
    data = base()
    del data["materials"]
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(data)
    assert info.value.keys == ["materials"]


def test_toml_syntax_error_names_the_line(capsys, tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(TINY_TOML.replace('name = "block"', 'name = "block'))
    code, _, err = cli(capsys, "check", path)
    assert code == 2 and "Traceback" not in err and "line 19" in err


def test_toml_with_dates_and_deep_nesting(capsys, tmp_path: Path) -> None:
    path = tmp_path / "odd.toml"
    path.write_text(TINY_TOML.replace("end_time = 0.1", "end_time = 1979-05-27"))
    code, _, err = cli(capsys, "check", path, "--set", "simulation.cfl=0.5")
    assert code == 2 and "error: simulation.end_time: " in err
    path.write_text("a = " + "[" * 5000 + "]" * 5000)
    code, _, err = cli(capsys, "check", path)
    assert code == 2 and "nested too deeply" in err


def test_schema_is_valid_json_listing_the_sections(capsys) -> None:
    code, out, _ = cli(capsys, "schema")
    assert code == 0
    schema = json.loads(out)
    assert {"simulation", "grid", "materials", "bodies", "boundaries", "walls"} <= set(schema["properties"])
    assert set(schema["required"]) == {"simulation", "grid", "materials", "bodies"}
    defs = schema["$defs"]
    assert "checkpoint_interval" in defs["Simulation"]["properties"]
    shapes = schema["properties"]["bodies"]["items"]["discriminator"]["mapping"]  # one def per region shape
    assert set(shapes) == {"rectangle", "polygon"}
    body = shapes["rectangle"].rsplit("/", 1)[-1]
    assert defs[body]["properties"]["allow_overlap"]["default"] is False
    assert defs[body]["properties"]["shape"]["default"] == "rectangle"
    assert "vertices" in defs[shapes["polygon"].rsplit("/", 1)[-1]]["properties"]
    assert "rigid_bodies" in schema["properties"]


def test_out_folder_refused_unless_overwrite(capsys, tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "notes"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    code, _, err = cli(capsys, "run", tiny_toml, "--out", out, "--threads", 1)
    assert code == 2 and "--overwrite" in err and (out / "keep.txt").read_text() == "mine"
    code, _, err = cli(capsys, "run", tiny_toml, "--out", out, "--threads", 1, "--overwrite")
    assert code == 0, err
    assert not (out / "keep.txt").exists()


# --------------------------------------------------------------------------- checkpoints


@pytest.mark.parametrize(("interval", "every"), [(None, None), (0.025, 1), (0.03, 2), (0.05, 2), (0.0501, 3)])
def test_checkpoint_interval_rounds_up_to_output_intervals(interval, every) -> None:
    data = base() if interval is None else apply_overrides(base(), [f"simulation.checkpoint_interval={interval}"])
    assert checkpoint_every(Scenario.from_dict(data).simulation) == every


def spy_checkpoints(monkeypatch) -> list[tuple[float, bytes]]:
    """Record (time, file bytes) of every checkpoint written."""
    saved: list[tuple[float, bytes]] = []
    original = runner.write_checkpoint

    def spy(run_dir, ckpt):
        path = original(run_dir, ckpt)
        saved.append((ckpt.time, path.read_bytes()))
        return path

    monkeypatch.setattr(runner, "write_checkpoint", spy)
    return saved


def test_periodic_checkpoints_are_at_output_times(monkeypatch, tmp_path: Path) -> None:
    saved = spy_checkpoints(monkeypatch)
    data = apply_overrides(base(), ["simulation.checkpoint_interval=0.03"])  # -> every 2 outputs
    summary = run(data, tmp_path / "r", threads=1)
    assert summary["status"] == "completed"
    assert [t for t, _ in saved] == [0.05, 0.1]  # periodic at 0.05, then at the stop (0.1)
    assert summary["checkpoint"]["time"] == 0.1 and summary["checkpoint"]["frames"] == 5
    assert read_checkpoint(tmp_path / "r").time == 0.1


def test_no_checkpoints_when_disabled(tmp_path: Path) -> None:
    summary = run(base(), tmp_path / "r", threads=1, checkpoints=False)
    assert summary["status"] == "completed" and summary["checkpoint"] is None
    assert not (tmp_path / "r" / CHECKPOINT).exists()


def test_failure_keeps_last_good_frame_and_checkpoint(capsys, tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "boom"
    # a time step far above the stable one: NaN or particles leaving the grid within the run
    code, _, err = cli(capsys, "run", tiny_toml, "--out", out, "--threads", 1,
                       "--set", "simulation.time_step=0.002", "--set", "simulation.output_interval=0.01")
    assert code == 3, err
    assert "Traceback" not in err and "error: simulation failed: " in err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "failed" and summary["message"] and summary["message"] in err
    r = load_run(out)
    assert len(r.frames) >= 2  # it failed after a few good output times
    ckpt = read_checkpoint(out)
    assert ckpt.time == r.last.time == summary["last_good_time"] == summary["checkpoint"]["time"]
    assert summary["last_good_frame"] == len(r.frames) - 1 == ckpt.frames - 1
    assert summary["end_time"] > ckpt.time  # the engine went on past it before failing
    # the checkpoint holds the good state of the last frame, not the broken one
    from axmpm._core import Simulation

    sim = Simulation.from_bytes(ckpt.engine, 1)
    assert np.array_equal(sim.positions(), r.last.x) and np.isfinite(sim.stresses()).all()
    # resuming a failed run replays the same failure: exit 3 again, same message
    code, _, err2 = cli(capsys, "resume", out, "--threads", 1)
    assert code == 3 and summary["message"] in err2
    assert len(load_run(out).frames) == len(r.frames)


def test_resume_after_kill_from_periodic_checkpoint(monkeypatch, tmp_path: Path) -> None:
    """A run killed after a periodic checkpoint (frames and history rows after it on disk,
    one of them damaged) is completed by resume, bit for bit."""
    saved = spy_checkpoints(monkeypatch)
    data = apply_overrides(base(), ["simulation.checkpoint_interval=0.03"])
    full = tmp_path / "full"
    run(data, full, threads=1)
    killed = tmp_path / "killed"
    run(data, killed, threads=1)
    assert saved[2][0] == 0.05
    (killed / CHECKPOINT).write_bytes(saved[2][1])  # as it was when the process died
    summary = json.loads((killed / "summary.json").read_text())
    summary.update(status="running")
    (killed / "summary.json").write_text(json.dumps(summary))
    (killed / "frames" / "frame_000004.npz").write_bytes(b"half a frame")
    (killed / "frames" / ".frame_000004.tmp999.npz").write_bytes(b"junk")

    summary = resume(killed, threads=1)
    assert summary["status"] == "completed" and summary["resumed"] == 1 and summary["frames"] == 5
    assert_same_final_state(full, killed)
    with open(killed / "history.csv") as fh:
        times = [float(r["time"]) for r in csv.DictReader(fh)]
    assert times == pytest.approx([0, 0.025, 0.05, 0.075, 0.1])  # no duplicated rows
    assert (killed / "particles.pvd").read_text().count("<DataSet") == 5
    assert not [p for p in killed.rglob("*") if ".tmp" in p.name]


def test_interrupt_in_process_then_resume(monkeypatch, tmp_path: Path) -> None:
    """SIGINT during a run: it finishes the chunk, stops, keeps the checkpoint of the last
    output time, status interrupted; resume completes it bit for bit."""
    full = tmp_path / "full"
    run(base(), full, threads=1)

    out = tmp_path / "cut"
    run_interrupted(monkeypatch, base(), out, after_records=2)  # after the frame at t = 0.025
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted" and summary["checkpoint"]["time"] == 0.025
    assert read_checkpoint(out).time == 0.025 and len(load_run(out).frames) == 2
    assert resume(out, threads=1)["status"] == "completed"
    assert_same_final_state(full, out)
    # the reactions of the resumed rows too (the engine's accumulators restart at the checkpoint)
    a, b = load_run(full), load_run(out)
    assert set(a.reactions) == set(b.reactions) == {"left", "bottom"}
    for name in a.reactions:
        np.testing.assert_array_equal(a.reactions[name], b.reactions[name])
    assert a.summary["reactions"] == b.summary["reactions"]


def test_resume_refusals(capsys, tmp_path: Path) -> None:
    code, _, err = cli(capsys, "resume", tmp_path / "absent")
    assert code == 2 and "not a folder" in err
    (tmp_path / "plain").mkdir()
    code, _, err = cli(capsys, "resume", tmp_path / "plain")
    assert code == 2 and "not an axmpm run folder" in err
    out = tmp_path / "r"
    run(base(), out, threads=1)
    code, stdout, _ = cli(capsys, "resume", out)
    assert code == 0 and "nothing to resume" in stdout
    summary = json.loads((out / "summary.json").read_text())
    summary["status"] = "interrupted"
    (out / "summary.json").write_text(json.dumps(summary))
    (out / CHECKPOINT).write_bytes(b"garbage")
    code, _, err = cli(capsys, "resume", out)
    assert code == 2 and "not a readable axmpm checkpoint" in err and "Traceback" not in err
    (out / CHECKPOINT).unlink()
    code, _, err = cli(capsys, "resume", out)
    assert code == 2 and "no checkpoint" in err


# --------------------------------------------------------------------------- atomic writes


def test_writes_are_atomic(monkeypatch, tmp_path: Path) -> None:
    """A write interrupted before its rename leaves the previous file whole."""
    summary = tmp_path / "summary.json"
    write_json(summary, {"a": 1})
    history = HistoryWriter(tmp_path / "history.csv")
    history.append({"time": 0.0, "x": 1.0})

    def boom(src, dst):
        raise KeyboardInterrupt  # as if the process died between writing and renaming

    monkeypatch.setattr(os, "replace", boom)
    for action in (lambda: write_json(summary, {"a": 2}), lambda: write_text(summary, "{"),
                   lambda: history.append({"time": 1.0, "x": 2.0})):
        with pytest.raises(KeyboardInterrupt):
            action()
    monkeypatch.undo()
    assert json.loads(summary.read_text()) == {"a": 1}
    assert (tmp_path / "history.csv").read_text() == "time,x\n0.0,1.0\n"


# --------------------------------------------------------------------------- subprocesses

LONG = ["--set", "simulation.end_time=10", "--set", "simulation.output_interval=0.5"]


def start(*args: object) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "axmpm.cli", *map(str, args)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env=dict(os.environ, MPLBACKEND="Agg"),
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def wait_for_frames(out: Path, n: int, proc: subprocess.Popen[str], timeout: float = 60) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and proc.poll() is None:
        if (out / "frames" / f"frame_{n - 1:06d}.npz").exists():
            return
        time.sleep(0.02)
    raise AssertionError(f"no frame {n - 1} (exit {proc.poll()})")


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The uninterrupted long run (~4 s)."""
    out = tmp_path_factory.mktemp("reference") / "run"
    data = apply_overrides(base(), [v for v in LONG if v != "--set"])
    assert run(data, out, threads=1)["status"] == "completed"
    return out


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_sigint_exit_130_then_resume_bit_for_bit(reference: Path, tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    proc = start("run", tiny_toml, "--out", out, "--threads", 1, *LONG)
    try:
        wait_for_frames(out, 3, proc)
        proc.send_signal(signal.SIGINT)
        _, stderr = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr and "axmpm resume" in stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    ckpt = read_checkpoint(out)
    frames = load_run(out).frames
    assert ckpt.time == frames[-1].time == summary["checkpoint"]["time"] and ckpt.time < 10
    assert ckpt.time in [0.5 * k for k in range(21)]  # an output time

    result = subprocess.run([sys.executable, "-m", "axmpm.cli", "resume", str(out), "--threads", "1"],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "completed" and summary["resumed"] == 1 and summary["frames"] == 21
    assert_same_final_state(reference, out)
    assert len(load_run(out).history["time"]) == 21


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_sigkill_leaves_only_complete_files_then_resume(reference: Path, tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    proc = start("run", tiny_toml, "--out", out, "--threads", 1, *LONG,
                 "--set", "simulation.checkpoint_interval=1.0")
    try:
        wait_for_frames(out, 6, proc)
        time.sleep(0.13)  # somewhere in the middle of stepping or writing
        proc.kill()
        proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    # everything on disk is complete
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "running"
    pvd = (out / "particles.pvd").read_text()
    listed = pvd.count("<DataSet")
    for i in range(listed):
        assert (out / "frames" / f"frame_{i:06d}.vtu").exists()
        with np.load(out / "frames" / f"frame_{i:06d}.npz") as z:
            assert z["x"].shape == (200, 2)
    with open(out / "history.csv") as fh:
        rows = list(csv.reader(fh))
    assert all(len(r) == len(rows[0]) for r in rows)
    ckpt = read_checkpoint(out)
    assert ckpt.time in (1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0)  # every 2 outputs

    assert resume(out, threads=1)["status"] == "completed"
    assert_same_final_state(reference, out)
    assert load_run(out).history["time"] == pytest.approx([0.5 * k for k in range(21)])


def test_error_lines_escape_control_characters(capsys, tmp_path: Path) -> None:
    """A TOML key may hold any character: each problem still prints on one line."""
    path = tmp_path / "odd.toml"
    path.write_text('"bad\\nkey\\u001e" = 1\n' + TINY_TOML)
    code, _, err = cli(capsys, "check", path)
    assert code == 2
    assert err == "error: bad\\nkey\\x1e: unknown key\n"


def test_settled_stop_survives_resume(monkeypatch, tmp_path: Path) -> None:
    """stop_when_settled reads the work of gravity over earlier output times from the history,
    so a run interrupted before it settles and resumed stops at the same output time, with
    the same final state, as one that ran through."""
    data = settling_block(**SETTLED_STOP)
    full = tmp_path / "full"
    done = run(data, full, threads=1)
    assert done["stopped_at_rest"] is True and done["end_time"] >= 1.0
    out = tmp_path / "cut"
    run_interrupted(monkeypatch, data, out, after_records=3)  # t = 0.5, before a window has passed
    resumed = resume(out, threads=1)
    assert resumed["stopped_at_rest"] is True
    assert resumed["end_time"] == done["end_time"] and resumed["steps"] == done["steps"]
    assert_same_final_state(full, out)
