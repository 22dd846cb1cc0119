"""Run output read back by load_run and, independently, by meshio."""

from __future__ import annotations

import json
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest

import axmpm
from axmpm.errors import RunError
from axmpm.run.output import stress_names

from conftest import TINY_TOML


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("runs")
    scenario = axmpm.Scenario.from_toml(_write(folder / "tiny.toml", TINY_TOML))
    summary = axmpm.run(scenario, folder / "run", threads=1, progress=False)
    assert summary["status"] == "completed"
    return folder / "run"


def _write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def test_load_run(tiny_run: Path) -> None:
    run = axmpm.load_run(tiny_run)
    assert run.summary["status"] == "completed"
    assert run.scenario.simulation.formulation == "plane_strain"
    assert len(run.frames) == 5
    np.testing.assert_allclose(run.times, [0, 0.025, 0.05, 0.075, 0.1], rtol=1e-12, atol=1e-15)
    n = run.summary["particles"]
    last = run.frames[-1]
    assert last.x.shape == (n, 2) and last.v.shape == (n, 2) and last.X0.shape == (n, 2)
    assert last.stress.shape == (n, 4) and last.F.shape == (n, 5)
    assert last.volume.shape == last.mass.shape == last.material_id.shape == (n,)
    first = run.frames[0]
    np.testing.assert_array_equal(first.x, first.X0)  # frame 0 is the initial state
    assert np.all(last.displacement[:, 1] <= 1e-12)  # settling under gravity
    assert np.mean(last.stress[:, 1]) < 0  # compression is negative
    assert run.history["time"][-1] == pytest.approx(0.1)
    assert len(run.history["kinetic_energy"]) == 5
    # mass is conserved and equals rho * area (plane strain: per metre)
    assert last.mass.sum() == pytest.approx(1000.0 * 0.05 * 0.1, rel=1e-12)


def test_meshio_reads_the_same_particles(tiny_run: Path) -> None:
    run = axmpm.load_run(tiny_run)
    names = stress_names("plane_strain")
    for index, frame in enumerate(run.frames):
        mesh = meshio.read(tiny_run / "frames" / f"frame_{index:06d}.vtu")
        np.testing.assert_allclose(mesh.points[:, :2], frame.x, rtol=0, atol=1e-12)
        for j, name in enumerate(names):
            np.testing.assert_allclose(np.ravel(mesh.point_data[name]), frame.stress[:, j], rtol=0, atol=1e-12)
        np.testing.assert_allclose(mesh.point_data["velocity"][:, :2], frame.v, rtol=0, atol=1e-12)
        np.testing.assert_allclose(mesh.point_data["displacement"][:, :2], frame.x - frame.X0, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(np.ravel(mesh.point_data["material_id"]), frame.material_id)
        np.testing.assert_allclose(np.ravel(mesh.point_data["F22"]), frame.F[:, 3], rtol=0, atol=1e-12)


def test_pvd_lists_frames_with_times(tiny_run: Path) -> None:
    root = ET.parse(tiny_run / "particles.pvd").getroot()
    sets = root.findall("./Collection/DataSet")
    times = [float(d.get("timestep")) for d in sets]
    np.testing.assert_allclose(times, axmpm.load_run(tiny_run).times, rtol=1e-15)
    for d in sets:
        assert (tiny_run / d.get("file")).exists()


def test_summary_fields(tiny_run: Path) -> None:
    summary = json.loads((tiny_run / "summary.json").read_text())
    for key in ("status", "steps", "particles", "end_time", "wall_seconds", "particle_steps_per_second",
                "energies", "formulation", "shape_function", "message"):
        assert key in summary


def test_axisymmetric_stress_names(tmp_path: Path) -> None:
    scenario = axmpm.Scenario.from_dict(
        axmpm.apply_overrides(
            tomllib.loads(TINY_TOML),
            ["simulation.formulation=axisymmetric", "simulation.end_time=0.01", "simulation.output_interval=0.01"],
        )
    )
    axmpm.run(scenario, tmp_path / "ax", progress=False)
    mesh = meshio.read(tmp_path / "ax" / "frames" / "frame_000001.vtu")
    frame = axmpm.load_run(tmp_path / "ax").frames[-1]
    for j, name in enumerate(["stress_rr", "stress_zz", "stress_tt", "stress_rz"]):
        np.testing.assert_allclose(np.ravel(mesh.point_data[name]), frame.stress[:, j], rtol=0, atol=1e-12)
    # axisymmetric masses are per radian: m = rho * A * R
    np.testing.assert_allclose(frame.mass, 1000.0 * (0.01 * 0.01 / 4) * frame.X0[:, 0], rtol=1e-12)


def test_run_refuses_non_run_folder_api(tmp_path: Path) -> None:
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep")
    with pytest.raises(RunError, match="not an axmpm run"):
        axmpm.run(axmpm.Scenario.from_dict(tomllib.loads(TINY_TOML)), out, progress=False)
    assert (out / "notes.txt").read_text() == "keep"


def test_results_do_not_depend_on_threads(tmp_path: Path) -> None:
    data = tomllib.loads(TINY_TOML)
    data = axmpm.apply_overrides(data, ["grid.cell_size=0.005", "simulation.end_time=0.02",
                                        "simulation.output_interval=0.02"])
    scenario = axmpm.Scenario.from_dict(data)
    frames = []
    for threads in (1, 2):
        axmpm.run(scenario, tmp_path / f"t{threads}", threads=threads, progress=False)
        frames.append(axmpm.load_run(tmp_path / f"t{threads}").frames[-1])
    for name in ("x", "v", "stress", "F", "volume"):
        np.testing.assert_array_equal(getattr(frames[0], name), getattr(frames[1], name), err_msg=name)


def test_import_is_light() -> None:
    import subprocess
    import sys

    code = "import sys, axmpm; print(sorted(m for m in sys.modules if m.split('.')[0] in ('matplotlib', 'pyevtk', 'tqdm') or m == 'axmpm._core'))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_help_documents_what_load_run_returns_and_every_frame_attribute() -> None:
    import dataclasses
    import pydoc

    from axmpm.run.output import Frame, FrameData, Run

    text = pydoc.render_doc(axmpm.load_run, renderer=pydoc.plaintext)
    assert "return a\n    :class:`Run`" in text and "rigid_bodies" in text and "state_names" in text
    for cls in (FrameData, Frame):
        doc = cls.__doc__ or ""
        missing = [f.name for f in dataclasses.fields(FrameData) if f"``{f.name}``" not in doc and f"{f.name}:" not in doc]
        assert not missing, f"{cls.__name__} does not document {missing}"
    for name in ("path", "summary", "frames", "scenario", "history", "reactions", "rigid_bodies"):
        assert f"{name}:" in (Run.__doc__ or ""), name


def test_state_of_names_the_column_and_lists_the_names() -> None:
    from axmpm.run.output import FrameData

    n = 3
    frame = FrameData(time=0.0, steps=0, x=np.zeros((n, 2)), v=np.zeros((n, 2)), stress=np.zeros((n, 4)),
                      X0=np.zeros((n, 2)), volume=np.ones(n), volume0=np.ones(n), mass=np.ones(n),
                      material_id=np.zeros(n, dtype=np.int32), F=np.zeros((n, 5)),
                      state=np.array([[1.0, 10.0], [2.0, 20.0], [3.0, 30.0]]),
                      state_names=["plastic_shear_strain", "plastic_work"])
    np.testing.assert_array_equal(frame.state_of("plastic_work"), [10.0, 20.0, 30.0])
    with pytest.raises(KeyError, match="this run's are: plastic_shear_strain, plastic_work"):
        frame.state_of("plastic_strain")


def test_a_frame_on_disk_lists_its_attributes(tiny_run: Path) -> None:
    frame = axmpm.load_run(tiny_run).last
    assert {"stress", "state", "state_names", "material_id", "displacement", "state_of"} <= set(dir(frame))


def test_rigid_bodies_are_written_for_paraview_at_every_frame(tmp_path: Path) -> None:
    """A run with a rigid body writes rigid_bodies.pvd beside particles.pvd, one outline file
    per frame at the frame's time; meshio reads each as the body's edges, a closed outline whose
    vertices are the body's moved by its displacement at that time (the history's)."""
    from axmpm.run.output import load_run
    from test_rigid_bodies import footing

    out = tmp_path / "run"
    axmpm.run(footing(), out, threads=1, progress=False)
    run = load_run(out)
    entries = ET.parse(out / "rigid_bodies.pvd").getroot().iter("DataSet")
    times_files = [(float(e.get("timestep")), out / e.get("file")) for e in entries]
    assert [t for t, _ in times_files] == pytest.approx(run.times.tolist(), abs=0)
    base = np.array([[0.0, 0.6], [0.25, 0.6], [0.25, 0.7], [0.0, 0.7]])
    history = run.history
    for (t, path), frame in zip(times_files, run.frames, strict=True):
        mesh = meshio.read(path)
        row = int(np.argmin(abs(history["time"] - t)))
        shift = np.array([history["footing.displacement_x"][row], history["footing.displacement_y"][row]])
        edges = mesh.points[mesh.cells_dict["line"]][:, :, :2]  # (4, 2, 2): from, to
        assert np.allclose(edges[:, 0], base + shift, rtol=0, atol=1e-12), (t, edges)
        assert np.allclose(edges[:, 1], np.roll(base, -1, axis=0) + shift, rtol=0, atol=1e-12)  # closed
        assert mesh.cell_data["body"][0].ravel().tolist() == [0, 0, 0, 0]
