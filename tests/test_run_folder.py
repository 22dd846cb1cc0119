"""Run folders: one writer at a time (``run.lock``), and an I/O failure during a run is a failed
run (exit 3) that names the file and keeps what was complete."""

from __future__ import annotations

import errno
import json
import os
import socket
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from axmpm.cli import main
from axmpm.run.lock import LOCK, RunLock, holder_of
from axmpm.run.output import load_run
from conftest import TINY_TOML

ENOSPC = OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def cli(capsys: pytest.CaptureFixture[str], *args: object) -> tuple[int, str, str]:
    code = main([str(a) for a in args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def dead_pid() -> int:
    """The pid of a process that has exited."""
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


# --------------------------------------------------------------------------- lock


def test_lock_is_exclusive_names_its_holder_and_is_released(tmp_path: Path) -> None:
    folder = tmp_path / "run"
    with RunLock(folder, "axmpm test") as lock:
        assert lock.held and (folder / LOCK).exists()
        holder = holder_of(folder)
        assert holder["pid"] == os.getpid() and holder["host"] == socket.gethostname()
        with pytest.raises(Exception, match=f"pid {os.getpid()} on {socket.gethostname()}"):
            RunLock(folder).acquire()
    assert not (folder / LOCK).exists()
    RunLock(folder).acquire().release()  # free again


def test_second_writer_refused_with_exit_2(capsys, tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    assert cli(capsys, "run", tiny_toml, "--out", out, "--threads", 1)[0] == 0
    summary = json.loads((out / "summary.json").read_text())
    (out / "summary.json").write_text(json.dumps({**summary, "status": "interrupted"}))  # resumable
    with RunLock(out, "axmpm run"):
        for args in (("run", tiny_toml, "--out", out, "--overwrite"), ("resume", out)):
            code, _, err = cli(capsys, *args)
            assert code == 2, err
            assert f"is being written by pid {os.getpid()} on {socket.gethostname()}" in err
            assert "Traceback" not in err and len(err.strip().splitlines()) == 1
        assert load_run(out).summary["status"] == "interrupted"  # untouched
    assert cli(capsys, "resume", out, "--threads", 1)[0] == 0
    assert cli(capsys, "run", tiny_toml, "--out", out, "--overwrite", "--threads", 1)[0] == 0
    assert not (out / LOCK).exists()


def test_stale_lock_of_a_dead_process_is_taken_over(capsys, tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    out.mkdir()
    (out / LOCK).write_text(json.dumps({"pid": dead_pid(), "host": socket.gethostname(), "command": "axmpm run"}))
    code, _, err = cli(capsys, "run", tiny_toml, "--out", out, "--threads", 1)
    assert code == 0, err
    assert load_run(out).summary["status"] == "completed" and not (out / LOCK).exists()


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX")
def test_concurrent_overwrite_of_a_running_folder_is_refused(tiny_toml: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    proc = subprocess.Popen([sys.executable, "-m", "axmpm.cli", "run", str(tiny_toml), "--out", str(out),
                             "--threads", "1", "--set", "simulation.end_time=1000"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        for _ in range(600):
            if holder_of(out) and (out / "summary.json").exists():
                break
            proc.poll()
            assert proc.returncode is None, proc.communicate()
            import time

            time.sleep(0.05)
        second = subprocess.run([sys.executable, "-m", "axmpm.cli", "run", str(tiny_toml), "--out", str(out),
                                 "--overwrite"], capture_output=True, text=True, timeout=120)
        assert second.returncode == 2, second.stderr
        assert f"pid {proc.pid} on {socket.gethostname()} (axmpm run)" in second.stderr
    finally:
        proc.kill()
        proc.communicate(timeout=30)
    assert json.loads((out / "summary.json").read_text())["status"] == "running"  # killed: not ours to change


# --------------------------------------------------------------------------- I/O failures


def test_disk_full_while_writing_a_frame_is_a_failed_run(capsys, monkeypatch, tiny_toml: Path, tmp_path: Path) -> None:
    """ENOSPC from inside a frame write (a write() error names no file): the run fails with exit 3
    naming the frame, summary.json records it, frame 0 (complete) is kept, the incomplete one not."""
    import pyevtk.hl

    original = pyevtk.hl.pointsToVTK
    calls = {"n": 0}

    def full_disk(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 2:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return original(*args, **kwargs)

    monkeypatch.setattr(pyevtk.hl, "pointsToVTK", full_disk)
    out = tmp_path / "run"
    code, stdout, err = cli(capsys, "run", tiny_toml, "--out", out, "--threads", 1)
    assert code == 3, err
    frame1 = out / "frames" / "frame_000001.vtu"
    assert f"error: writing the output failed: cannot write {frame1}: No space left on device" in err
    assert "Traceback" not in err and stdout.startswith("failed:")
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "failed" and summary["failure"] == "output"
    assert summary["message"] == f"cannot write {frame1}: No space left on device"
    assert summary["frames"] == 1 and summary["last_good_frame"] == 0
    run = load_run(out)
    assert len(run.frames) == 1 and run.frames[0].time == 0.0
    assert sorted(p.name for p in (out / "frames").iterdir()) == ["frame_000000.npz", "frame_000000.vtu"]
    assert not list(out.glob(".*tmp*")) and not (out / LOCK).exists()
    assert cli(capsys, "resume", out, "--threads", 1)[0] == 0  # from the checkpoint at t = 0
    assert load_run(out).summary["status"] == "completed"


def test_summary_is_written_in_place_when_no_new_file_fits(capsys, monkeypatch, tiny_toml: Path,
                                                           tmp_path: Path) -> None:
    """Once the disk is full no temporary file can be created: the failure is still recorded,
    over the old summary.json."""
    import axmpm.run.output as output

    real = output.write_text
    state = {"full": False}

    def write_text(path, text):
        if path.name == "history.csv" and text.count("\n") == 3:  # header + rows of t = 0 and 0.025
            state["full"] = True
        if state["full"]:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        return real(path, text)

    monkeypatch.setattr(output, "write_text", write_text)
    out = tmp_path / "run"
    code, _, err = cli(capsys, "run", tiny_toml, "--out", out, "--threads", 1)
    assert code == 3 and f"cannot write {out / 'history.csv'}: No space left on device" in err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "failed" and "history.csv: No space left on device" in summary["message"]
    assert summary["frames"] == 2  # the frame files and pvd entry of t = 0.025 were complete


# --------------------------------------------------------------------------- reactions


@pytest.mark.parametrize("formulation", ["plane_strain", "axisymmetric"])
def test_reactions_of_a_block_at_rest_carry_its_weight(tmp_path: Path, formulation: str) -> None:
    """history.csv has NAME.force_x/force_y per reporting constraint, summary.json the last
    values, load_run the series: a block at rest on a fixed base presses it with its weight (per
    metre in plane strain, the whole body in axisymmetry) within 0.5 %; a free face reports
    nothing."""
    import math

    import axmpm
    from conftest import settling_block

    # as the engine's test: no damping, gravity ramped in over 0.3 s, the mean over [0.5, 1.5] s
    data = settling_block(formulation=formulation, end_time=1.5, output_interval=0.5, damping=0.0,
                          gravity_ramp_time=0.3)
    data["boundaries"]["left"] = "roller"
    if formulation == "axisymmetric":
        data["bodies"][0].update(min=[0.0, 0.0], max=[0.2, 0.2])
    out = tmp_path / formulation
    summary = axmpm.run(data, out, threads=1, progress=False)
    assert summary["status"] == "completed"
    run = load_run(out)
    # free faces report nothing; in axisymmetry the left face is the axis, which reports nothing
    assert set(run.reactions) == ({"left", "bottom"} if formulation == "plane_strain" else {"bottom"})
    if formulation == "plane_strain":
        assert {"bottom.force_x", "bottom.force_y"} <= set(run.history)
    else:  # a ring: the axial force and the radial traction integral, no radial "resultant"
        assert {"bottom.force_y", "bottom.radial_force_integral"} <= set(run.history)
        assert "bottom.force_x" not in run.history
    rho, g = 1000.0, 10.0
    weight = rho * g * 0.2 * 0.2 * (math.pi * 0.2 if formulation == "axisymmetric" else 1.0)
    assert run.history["time"].tolist() == [0.0, 0.5, 1.0, 1.5]
    fx, fy = run.reactions["bottom"][-2:].mean(axis=0)
    assert fy == pytest.approx(-weight, rel=5e-3)
    if formulation == "plane_strain":
        assert abs(fx) < 5e-3 * weight
    else:
        assert fx == 0.0  # the radial resultant of a ring
    assert run.reactions["bottom"][0].tolist() == [0.0, 0.0]  # t = 0: nothing elapsed
    assert summary["reactions"]["bottom"] == run.reactions["bottom"][-1].tolist()


def test_an_axisymmetric_rigid_body_reports_its_axial_force_and_the_radial_traction_integral(
        tmp_path: Path) -> None:
    """A ring has no radial resultant: an axisymmetric run writes the axial force (whole ring)
    and, under its own name, the radial traction integral; no ``_x`` force columns, and the
    readers give force_x = 0."""
    import axmpm
    from test_rigid_bodies import footing

    data = footing(formulation="axisymmetric")
    summary = axmpm.run(data, tmp_path / "run", threads=1, progress=False)
    assert summary["status"] == "completed"
    run = load_run(tmp_path / "run")
    history = set(run.history)
    assert {"footing.force_y", "footing.radial_force_integral", "footing.base_force_y",
            "footing.shaft_force_y", "footing.displacement_x", "footing.displacement_y"} <= history
    assert not {"footing.force_x", "footing.base_force_x", "footing.shaft_force_x"} & history
    body = run.rigid_bodies["footing"]
    assert body["force"][-1, 1] > 0.0  # the clay pushes the footing up
    assert body["force"][:, 0].tolist() == [0.0] * len(run.history["time"])
    # The rough base drags the clay outwards beneath it: the clay's radial traction on the
    # footing is outward-pointing (+r) — a nonzero integral, though the resultant is zero.
    assert run.history["footing.radial_force_integral"][-1] != 0.0
    assert summary["reactions"]["footing"][0] == 0.0
    assert summary["rigid_bodies"]["footing"]["force"][0] == 0.0
