"""Run folders: what a run writes and how it is read back.

Layout of a run folder::

    scenario.toml            resolved scenario (every default filled in)
    summary.json             status, steps, timings, energies, reactions (the last row's
                             forces, NAME → [fx, fy]) (written at start, updated at end)
    run.lock                 present while a process writes the folder (axmpm.run.lock)
    history.csv              one row per output time: time, steps, dt, energies, wall_seconds,
                             and NAME.force_x, NAME.force_y per constraint that reports a
                             reaction (faces that are not free, walls): the mean force the
                             material exerted on it since the previous row (N; plane strain:
                             per metre; axisymmetric: whole body, axial NAME.force_y only and
                             NAME.radial_force_integral, the radial traction summed round
                             the ring, in place of a force_x); per rigid body also
                             NAME.displacement_x/y (m), NAME.velocity_x/y (m/s) and the force split into
                             NAME.base_force_x/y (contact normals facing down) and
                             NAME.shaft_force_x/y (the rest), and for a body with
                             named parts NAME.PART_force_x/y per part and
                             NAME.rest_force_x/y (above the last); per surcharge
                             NAME.applied_force_y, the force it applies to the material
                             (N, negative: downward); saturated runs also
                             water_outflow (m³ per metre or radian: the water that left
                             through drained faces and free surfaces since the start) and
                             the energies water_kinetic_energy and drag_dissipation; per
                             probe NAME.pore_pressure, NAME.stress_*, NAME.displacement_x/y
                             (axmpm.run.probes)
    particles.pvd            ParaView collection of the frames with their times
    rigid_bodies.pvd         (runs with rigid bodies) ParaView collection of the bodies'
                             outlines at the frames' times, frames/rigid_bodies_NNNNNN.vtu
                             (each body's edges as line cells, cell data ``body``: its index)
    frames/frame_NNNNNN.vtu  particles as VTK points (pyevtk), for ParaView
    frames/frame_NNNNNN.npz  the same data, compact numpy; :func:`load_run` reads these
    checkpoint.npz           latest restart point (engine state at an output time + metadata),
                             see :func:`write_checkpoint`; ``axmpm resume`` continues from it

Every file is written under a temporary name and moved into place with ``os.replace``, so
a reader (or a run killed at any moment) never sees a half-written file; a frame is listed
in ``particles.pvd`` only after both its .npz and .vtu are in place. ``history.csv`` is
rewritten whole (atomically) at every output time. An error while writing names the file
(:func:`writing`); the runner then ends the run as failed and keeps what was complete.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..scenario import Scenario

__all__ = [
    "FrameData",
    "Frame",
    "Run",
    "load_run",
    "is_run_folder",
    "is_completed_run",
    "stress_names",
    "write_frame",
    "write_pvd",
    "write_outlines",
    "outline_entries",
    "BODIES_PVD",
    "write_json",
    "write_json_robustly",
    "writing",
    "output_message",
    "HistoryWriter",
    "Checkpoint",
    "write_checkpoint",
    "read_checkpoint",
    "remove_frames_from",
    "remove_temporary_files",
    "SUMMARY",
    "PROGRAM",
    "CHECKPOINT",
]

PROGRAM = "axmpm"
SUMMARY = "summary.json"
SCENARIO = "scenario.toml"
HISTORY = "history.csv"
PVD = "particles.pvd"
#: The rigid bodies' outlines: ParaView collection and the stem of its per-frame files.
BODIES_PVD = "rigid_bodies.pvd"
BODIES_STEM = "rigid_bodies_"
FRAMES = "frames"
CHECKPOINT = "checkpoint.npz"


def stress_names(formulation: str) -> list[str]:
    """Names of the four stress components, in the engine's order.

    [in-plane normal 1, in-plane normal 2 (vertical), out-of-plane/hoop, in-plane shear].
    """
    if formulation == "axisymmetric":
        return ["stress_rr", "stress_zz", "stress_tt", "stress_rz"]
    return ["stress_xx", "stress_yy", "stress_zz", "stress_xy"]


F_NAMES = ["F11", "F12", "F21", "F22", "F33"]


@dataclass
class FrameData:
    """One snapshot of all particles at an output time (SI units, stress tension positive).

    Every array has one row per particle, in the same particle order in every frame of a run,
    so rows can be compared between frames. The two in-plane directions are (x, y) in plane
    strain and (r, z) in axisymmetry, y/z pointing up.

    Attributes:
        time: the time of the frame (s).
        steps: the steps taken up to it.
        x: (N, 2) current positions (m).
        v: (N, 2) velocities (m/s).
        stress: (N, 4) Cauchy stress (Pa, tension positive) in the order of
            :func:`stress_names`: [xx, yy, zz, xy] in plane strain, [rr, zz, θθ, rz] in
            axisymmetry.
        X0: (N, 2) initial positions (m); :attr:`displacement` is ``x - X0``.
        volume: (N,) current volume (m³ per metre in plane strain, per radian in axisymmetry).
        volume0: (N,) initial volume (same units).
        mass: (N,) mass (kg per metre in plane strain, per radian in axisymmetry).
        material_id: (N,) each particle's material, an index into the run's material names
            sorted alphabetically (``run.scenario.material_names()``).
        F: (N, 5) deformation gradient [F11, F12, F21, F22, F33] (F33: out of plane, the hoop
            stretch r/R in axisymmetry).
        state: (N, S) the materials' internal variables, one column per name in
            ``state_names`` (0 where a particle's material has no such variable).
        state_names: the S column names of ``state``: the union over the run's materials of
            their variables, e.g. ``plastic_shear_strain``, ``plastic_work`` (J per m³ of initial
            volume).
        pore_pressure: (N,) pore water pressure (Pa, compression positive) of a saturated run,
            whose ``stress`` is then the effective stress; empty in a dry run.
        porosity: (N,) porosity n of a saturated run (empty in a dry run).
        water_velocity: (N, 2) the pore water's velocity (m/s) of a saturated run (empty in a
            dry run).
    """

    time: float
    steps: int
    x: NDArray[np.float64]  # (N, 2) current position
    v: NDArray[np.float64]  # (N, 2) velocity
    stress: NDArray[np.float64]  # (N, 4) see stress_names()
    X0: NDArray[np.float64]  # (N, 2) initial position
    volume: NDArray[np.float64]  # (N,) per metre (plane strain) or per radian (axisymmetric)
    volume0: NDArray[np.float64]  # (N,)
    mass: NDArray[np.float64]  # (N,)
    material_id: NDArray[np.int32]  # (N,) index into sorted material names
    F: NDArray[np.float64]  # (N, 5) [F11, F12, F21, F22, F33]
    state: NDArray[np.float64]  # (N, S)
    state_names: list[str] = field(default_factory=list)
    # Saturated runs only (empty otherwise): pore pressure (Pa, compression positive),
    # porosity and the pore water's velocity (m/s); ``stress`` is then the effective stress.
    pore_pressure: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    porosity: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    water_velocity: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)))

    @property
    def displacement(self) -> NDArray[np.float64]:
        """(N, 2) displacement ``x - X0`` (m)."""
        return self.x - self.X0

    def state_of(self, name: str) -> NDArray[np.float64]:
        """(N,) the column of ``state`` called ``name`` (``KeyError`` listing the names if absent)."""
        if name not in self.state_names:
            raise KeyError(f"no state variable {name!r}; this run's are: {', '.join(self.state_names)}")
        return self.state[:, self.state_names.index(name)]

    @classmethod
    def from_simulation(cls, sim: Any) -> "FrameData":
        """Copy the particle state out of an ``axmpm._core.Simulation``."""
        state_names = list(sim.state_names())
        state = np.asarray(sim.state(), dtype=float)
        if state.ndim != 2:
            state = state.reshape(int(sim.num_particles), len(state_names))
        return cls(
            time=float(sim.time),
            steps=int(sim.steps),
            x=np.asarray(sim.positions(), dtype=float),
            v=np.asarray(sim.velocities(), dtype=float),
            stress=np.asarray(sim.stresses(), dtype=float),
            X0=np.asarray(sim.initial_positions(), dtype=float),
            volume=np.asarray(sim.volumes(), dtype=float),
            volume0=np.asarray(sim.initial_volumes(), dtype=float),
            mass=np.asarray(sim.masses(), dtype=float),
            material_id=np.asarray(sim.material_ids(), dtype=np.int32),
            F=np.asarray(sim.deformation_gradients(), dtype=float),
            state=state,
            state_names=state_names,
            **{name: np.asarray(getattr(sim, method)(), dtype=float) for name, method in _WATER_METHODS.items()},
        )


_ARRAYS = ("x", "v", "stress", "X0", "volume", "volume0", "mass", "material_id", "F", "state")
#: The saturated runs' arrays and the engine methods that give them (written when not empty).
_WATER_METHODS = {"pore_pressure": "pore_pressures", "porosity": "porosities", "water_velocity": "water_velocities"}


def frame_stem(index: int) -> str:
    return f"frame_{index:06d}"


def _tmp(path: Path) -> Path:
    return path.with_name(f".{path.name}.tmp{os.getpid()}")


@contextlib.contextmanager
def writing(path: str | Path) -> Any:
    """Any ``OSError`` raised while ``path`` is written (its temporary file included) names
    ``path``: an error from ``write()`` (e.g. ENOSPC) carries no file name of its own."""
    try:
        yield
    except OSError as exc:
        if exc.filename is not None and Path(exc.filename) == Path(path):
            raise
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from exc


def output_message(exc: OSError) -> str:
    """``cannot write FILE: reason`` (the reason alone when the error names no file)."""
    reason = exc.strerror or str(exc)
    return f"cannot write {exc.filename}: {reason}" if exc.filename else f"cannot write the output: {reason}"


def write_json(path: Path, data: dict[str, Any]) -> None:
    """Write JSON atomically."""
    write_text(path, json.dumps(data, indent=2) + "\n")


def write_text(path: Path, text: str) -> None:
    """Write text atomically."""
    tmp = _tmp(path)
    with writing(path):
        try:
            tmp.write_text(text)
            os.replace(tmp, path)
        except OSError:
            with contextlib.suppress(OSError):
                tmp.unlink()
            raise


def write_json_robustly(path: Path, data: dict[str, Any]) -> str:
    """Write JSON wherever it still can be written: atomically; else after removing the run's
    temporary files (which may be what filled the disk); else in place over the old file (its
    blocks are reused). Returns "" on success, else the reason it could not be written."""
    text = json.dumps(data, indent=2) + "\n"
    try:
        write_text(path, text)
        return ""
    except OSError:
        remove_temporary_files(path.parent)
    try:
        write_text(path, text)
        return ""
    except OSError:
        pass
    try:
        with open(path, "r+" if path.exists() else "w") as fh:
            fh.write(text)
            fh.truncate()
        return ""
    except OSError as exc:
        return output_message(OSError(exc.errno, exc.strerror or str(exc), str(path)))


def write_frame(run_dir: Path, index: int, frame: FrameData, formulation: str) -> Path:
    """Write ``frames/frame_NNNNNN.npz`` and ``.vtu`` atomically; return the .vtu path."""
    from pyevtk.hl import pointsToVTK

    frames = run_dir / FRAMES
    frames.mkdir(exist_ok=True)
    stem = frame_stem(index)

    npz = frames / f"{stem}.npz"
    tmp_npz = frames / f".{stem}.tmp{os.getpid()}.npz"
    arrays = {name: getattr(frame, name) for name in _ARRAYS}
    arrays.update({name: getattr(frame, name) for name in _WATER_METHODS if len(getattr(frame, name))})
    with writing(npz):
        np.savez(
            tmp_npz,
            time=np.float64(frame.time),
            steps=np.int64(frame.steps),
            state_names=np.array(frame.state_names, dtype=str),
            formulation=np.array(formulation),
            **arrays,
        )
        os.replace(tmp_npz, npz)

    n = frame.x.shape[0]
    zeros = np.zeros(n)

    def vec(a: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
        return (np.ascontiguousarray(a[:, 0]), np.ascontiguousarray(a[:, 1]), zeros)

    data: dict[str, Any] = {
        "velocity": vec(frame.v),
        "displacement": vec(frame.displacement),
        "initial_position": vec(frame.X0),
    }
    for j, name in enumerate(stress_names(formulation)):
        data[name] = np.ascontiguousarray(frame.stress[:, j])
    data["volume"] = np.ascontiguousarray(frame.volume)
    data["mass"] = np.ascontiguousarray(frame.mass)
    data["material_id"] = np.ascontiguousarray(frame.material_id, dtype=np.int32)
    for j, name in enumerate(F_NAMES):
        data[name] = np.ascontiguousarray(frame.F[:, j])
    for j, name in enumerate(frame.state_names):
        data[f"state_{name}"] = np.ascontiguousarray(frame.state[:, j])
    if len(frame.pore_pressure):
        data["pore_pressure"] = np.ascontiguousarray(frame.pore_pressure)
        data["porosity"] = np.ascontiguousarray(frame.porosity)
        data["water_velocity"] = vec(frame.water_velocity)

    tmp_stem = frames / f".{stem}.tmp{os.getpid()}"
    vtu = frames / f"{stem}.vtu"
    with writing(vtu):
        pointsToVTK(
            str(tmp_stem),
            np.ascontiguousarray(frame.x[:, 0]),
            np.ascontiguousarray(frame.x[:, 1]),
            zeros,
            data=data,  # no fieldData: the time is in particles.pvd, and meshio rejects FieldData
        )
        os.replace(f"{tmp_stem}.vtu", vtu)
    return vtu


def write_pvd(run_dir: Path, entries: Sequence[tuple[float, Path]], name: str = PVD) -> None:
    """(Re)write ``particles.pvd`` (or ``name``) listing ``(time, vtu path)`` entries, atomically."""
    from pyevtk.vtk import VtkGroup

    tmp_stem = run_dir / f".{Path(name).stem}.tmp{os.getpid()}"
    with writing(run_dir / name):
        group = VtkGroup(str(tmp_stem))
        for time, vtu in entries:
            group.addFile(filepath=str(vtu), sim_time=repr(float(time)))
        group.save()
        os.replace(f"{tmp_stem}.pvd", run_dir / name)


def outline_entries(run_dir: Path, frame_entries: Sequence[tuple[float, Path]]) -> list[tuple[float, Path]]:
    """The ``(time, path)`` of the rigid bodies' outline files of the frames ``frame_entries``
    (frame i's outlines: ``frames/rigid_bodies_i.vtu``) that exist."""
    paths = [(t, Path(run_dir) / FRAMES / f"{BODIES_STEM}{i:06d}.vtu") for i, (t, _) in enumerate(frame_entries)]
    return [(t, p) for t, p in paths if p.exists()]


def write_outlines(run_dir: Path, index: int, outlines: Sequence[tuple[str, Sequence[tuple[float, float]]]]) -> Path:
    """Write ``frames/rigid_bodies_NNNNNN.vtu``: each rigid body's outline as its edges, line
    cells from vertex k to k + 1 (cell data ``body``, its index in the scenario), atomically;
    return its path."""
    from pyevtk.hl import unstructuredGridToVTK
    from pyevtk.vtk import VtkLine

    frames = run_dir / FRAMES
    frames.mkdir(exist_ok=True)
    stem = f"{BODIES_STEM}{index:06d}"
    points, connectivity, body = [], [], []
    for i, (_, vertices) in enumerate(outlines):
        first, n = sum(len(p) for p in points), len(vertices)
        points.append(np.asarray(vertices, dtype=float))
        connectivity += [(first + k, first + (k + 1) % n) for k in range(n)]
        body += [i] * n
    xy = np.concatenate(points)
    tmp_stem = frames / f".{stem}.tmp{os.getpid()}"
    vtu = frames / f"{stem}.vtu"
    with writing(vtu):
        unstructuredGridToVTK(
            str(tmp_stem), np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]), np.zeros(len(xy)),
            connectivity=np.array(connectivity, dtype=np.int64).ravel(),
            offsets=np.arange(2, 2 * len(connectivity) + 1, 2, dtype=np.int64),
            cell_types=np.full(len(connectivity), VtkLine.tid, dtype=np.uint8),
            cellData={"body": np.array(body, dtype=np.int32)})
        os.replace(f"{tmp_stem}.vtu", vtu)
    return vtu


class HistoryWriter:
    """Rows of ``history.csv``; the columns are fixed by the first row. The file is rewritten
    atomically after every row, so it never ends in a partial line."""

    def __init__(self, path: Path):
        self.path = path
        self.columns: list[str] | None = None
        self.lines: list[str] = []
        #: The values of the rows so far (one list per line after the header), for :meth:`series`.
        self.rows: list[list[float]] = []

    def append(self, row: dict[str, float]) -> None:
        if self.columns is None:
            self.columns = list(row)
            self.lines = [_csv_line(self.columns)]
        values = [float(row.get(c, float("nan"))) for c in self.columns]
        self.rows.append(values)
        self.lines.append(_csv_line([repr(v) for v in values]))
        write_text(self.path, "".join(self.lines))

    def series(self, column: str) -> list[tuple[float, float]]:
        """(time, value) of one column over the rows so far (empty if it is not recorded)."""
        if self.columns is None or column not in self.columns or "time" not in self.columns:
            return []
        t, c = self.columns.index("time"), self.columns.index(column)
        return [(r[t], r[c]) for r in self.rows]

    @classmethod
    def resume(cls, path: Path, until_time: float) -> "HistoryWriter":
        """Continue an existing ``history.csv``, dropping the rows after ``until_time``."""
        writer = cls(path)
        if not path.exists():
            return writer
        with open(path, newline="") as fh:
            rows = list(csv.reader(fh))
        if not rows:
            return writer
        writer.columns = rows[0]
        writer.lines = [_csv_line(writer.columns)]
        try:
            t = writer.columns.index("time")
        except ValueError:
            t = 0
        for r in rows[1:]:
            if len(r) != len(writer.columns):
                continue  # a damaged line (older, non-atomic writers)
            try:
                if float(r[t]) > until_time:
                    continue
            except ValueError:
                continue
            writer.lines.append(_csv_line(r))
            writer.rows.append([_float_or_nan(v) for v in r])
        write_text(path, "".join(writer.lines))
        return writer


def _float_or_nan(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return float("nan")


def _csv_line(values: Sequence[str]) -> str:
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow(values)
    return buf.getvalue()


# --------------------------------------------------------------------------- checkpoints


@dataclass
class Checkpoint:
    """A restart point: the engine's ``Simulation.to_bytes()`` at an output time, plus what
    the front end needs to continue the run folder from there."""

    engine: bytes
    time: float  # s, an output time
    steps: int
    output_index: int  # k: the checkpoint is at output time min(k * output_interval, end_time)
    frame_times: list[float]  # times of the frames 0 .. len-1 written up to and including it
    wall_seconds: float = 0.0  # wall and engine time spent up to the checkpoint
    engine_seconds: float = 0.0
    energies: dict[str, float] = field(default_factory=dict)

    @property
    def frames(self) -> int:
        return len(self.frame_times)

    def meta(self) -> dict[str, Any]:
        return {
            "time": self.time,
            "steps": self.steps,
            "output_index": self.output_index,
            "frames": self.frames,
            "file": CHECKPOINT,
        }


def write_checkpoint(run_dir: Path, ckpt: Checkpoint) -> Path:
    """Write ``checkpoint.npz`` atomically (replacing the previous one); return its path."""
    path = Path(run_dir) / CHECKPOINT
    tmp = path.with_name(f".checkpoint.tmp{os.getpid()}.npz")
    meta = {
        "program": PROGRAM,
        "time": ckpt.time,
        "steps": ckpt.steps,
        "output_index": ckpt.output_index,
        "frame_times": [float(t) for t in ckpt.frame_times],
        "wall_seconds": ckpt.wall_seconds,
        "engine_seconds": ckpt.engine_seconds,
        "energies": ckpt.energies,
    }
    with writing(path):
        np.savez(tmp, engine=np.frombuffer(bytes(ckpt.engine), dtype=np.uint8), meta=np.array(json.dumps(meta)))
        os.replace(tmp, path)
    return path


def read_checkpoint(run_dir: Path) -> Checkpoint:
    """Read ``checkpoint.npz``; ``FileNotFoundError`` if there is none, ``ValueError`` if it
    is not a readable axmpm checkpoint."""
    path = Path(run_dir) / CHECKPOINT
    if not path.exists():
        raise FileNotFoundError(str(path))
    try:
        with np.load(path) as z:
            engine = z["engine"].tobytes()
            meta = json.loads(str(z["meta"]))
        if meta.get("program") != PROGRAM:
            raise ValueError("not written by axmpm")
        return Checkpoint(
            engine=engine,
            time=float(meta["time"]),
            steps=int(meta["steps"]),
            output_index=int(meta["output_index"]),
            frame_times=[float(t) for t in meta["frame_times"]],
            wall_seconds=float(meta.get("wall_seconds", 0.0)),
            engine_seconds=float(meta.get("engine_seconds", 0.0)),
            energies={str(k): float(v) for k, v in meta.get("energies", {}).items()},
        )
    except (OSError, KeyError, TypeError, ValueError) as exc:
        raise ValueError(f"{path} is not a readable axmpm checkpoint ({exc})") from None


def remove_frames_from(run_dir: Path, first: int) -> None:
    """Delete frames ``first``, ``first + 1``, ... (written after a checkpoint)."""
    frames = Path(run_dir) / FRAMES
    if not frames.is_dir():
        return
    for prefix in ("frame_", BODIES_STEM):
        for p in frames.glob(f"{prefix}*.*"):
            stem = p.name.split(".", 1)[0]
            try:
                index = int(stem.removeprefix(prefix))
            except ValueError:
                continue
            if index >= first and p.suffix in (".npz", ".vtu"):
                p.unlink()


def remove_temporary_files(run_dir: Path) -> None:
    """Delete ``.NAME.tmpPID*`` files a killed process may have left behind."""
    run_dir = Path(run_dir)
    for folder in (run_dir, run_dir / FRAMES):
        if folder.is_dir():
            for p in folder.glob(".*.tmp*"):
                if p.is_file():
                    p.unlink()


# --------------------------------------------------------------------------- reading


def is_completed_run(run_dir: Path, resolved: dict[str, Any]) -> bool:
    """``run_dir`` holds a completed run of exactly the ``resolved`` scenario (``to_dict()``)."""
    try:
        summary = json.loads((Path(run_dir) / SUMMARY).read_text())
        if summary.get("program") != PROGRAM or summary.get("status") != "completed":
            return False
        return Scenario.from_toml(Path(run_dir) / SCENARIO).to_dict() == resolved
    except Exception:
        return False


def is_run_folder(path: Path) -> bool:
    """True when ``path`` holds a ``summary.json`` written by axmpm."""
    try:
        data = json.loads((Path(path) / SUMMARY).read_text())
    except (OSError, ValueError):
        return False
    return isinstance(data, dict) and data.get("program") == PROGRAM


class Frame:
    """A frame of a run on disk (``frames/frame_NNNNNN.npz``), read on first access.

    It has the attributes of :class:`FrameData`: ``time``, ``steps``, ``x``, ``v``,
    ``stress``, ``X0``, ``displacement``, ``volume``, ``volume0``, ``mass``, ``material_id``,
    ``F``, ``state``, ``state_names``, in a saturated run ``pore_pressure``, ``porosity`` and
    ``water_velocity``, and :meth:`~FrameData.state_of` (``help(FrameData)`` gives their shapes
    and units), and ``path``, the .npz file.
    """

    def __init__(self, path: Path):
        self.path = Path(path)

    def __dir__(self) -> list[str]:
        return sorted({*super().__dir__(), *(f.name for f in fields(FrameData)), "displacement", "state_of"})

    @cached_property
    def _data(self) -> FrameData:
        with np.load(self.path) as z:
            return FrameData(
                time=float(z["time"]),
                steps=int(z["steps"]),
                state_names=[str(s) for s in z["state_names"]],
                **{name: z[name] for name in _ARRAYS},
                **{name: z[name] for name in _WATER_METHODS if name in z.files},
            )

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_") or name == "path":
            raise AttributeError(name)
        return getattr(self._data, name)

    def __repr__(self) -> str:
        return f"Frame({self.path.name})"


class Run:
    """A run folder read back (see :func:`load_run`).

    Attributes:
        path: the run folder.
        summary: summary.json as a dict (``status``: completed, failed, interrupted or running;
            ``steps``, ``end_time``, ``wall_seconds``, the energies, ...).
        frames: the :class:`Frame` of every output time, in time order (``last``: the final
            one; ``times``: their times, s).
        scenario: the resolved :class:`~axmpm.scenario.Scenario` the run was made with.
        history: history.csv as column name → (T,) array, one value per row (``time``,
            ``steps``, ``dt``, the energies, ``NAME.force_x``/``_y``, ...).
        reactions: per constraint that reports a reaction, its force at every history row.
        rigid_bodies: per rigid body, its displacement and forces at every history row.
    """

    def __init__(self, path: str | Path):
        self.path = Path(path)
        if not (self.path / SUMMARY).exists():
            raise FileNotFoundError(f"{self.path} is not an axmpm run folder (no {SUMMARY})")
        self.summary: dict[str, Any] = json.loads((self.path / SUMMARY).read_text())
        self.frames: list[Frame] = [Frame(p) for p in sorted((self.path / FRAMES).glob("frame_*.npz"))]

    @cached_property
    def scenario(self) -> Scenario:
        """The resolved scenario of the run (its scenario.toml, every default filled in)."""
        return Scenario.from_toml(self.path / SCENARIO)

    @cached_property
    def history(self) -> dict[str, NDArray[np.float64]]:
        """history.csv as column name → (T,) array, one value per row (empty if there is none)."""
        path = self.path / HISTORY
        if not path.exists():
            return {}
        with open(path, newline="") as fh:
            rows = list(csv.reader(fh))
        if not rows:
            return {}
        header, body = rows[0], rows[1:]
        values = np.array([[float(v) for v in r] for r in body], dtype=float).reshape(len(body), len(header))
        return {name: values[:, j] for j, name in enumerate(header)}

    @property
    def reactions(self) -> dict[str, NDArray[np.float64]]:
        """Per constraint that reports a reaction, its force at every history row: name → (T, 2)
        array [force_x, force_y] (N, the mean since the previous row; axisymmetric: whole body,
        force_x = 0, the radial resultant of a ring; its radial traction integral is the history
        column ``NAME.radial_force_integral``)."""
        history = self.history
        names = [c[: -len(".force_y")] for c in history if c.endswith(".force_y")]
        return {n: np.stack([history.get(f"{n}.force_x", np.zeros_like(history[f"{n}.force_y"])),
                             history[f"{n}.force_y"]], axis=1)
                for n in names}

    @property
    def rigid_bodies(self) -> dict[str, dict[str, NDArray[np.float64]]]:
        """Per rigid body, at every history row: ``displacement``, ``force``, ``base_force``,
        ``shaft_force`` and, for a body with named parts, ``PART_force`` for each part and
        ``rest_force``, as (T, 2) arrays [x, y] (m; N, the mean since the previous row, whole
        body; base: contact with normals facing down, shaft: the rest)."""
        history = self.history
        names = [c[: -len(".displacement_x")] for c in history if c.endswith(".displacement_x")]
        out: dict[str, dict[str, NDArray[np.float64]]] = {}
        for n in names:
            keys = ["displacement", "force"] + [c[len(n) + 1: -len("_y")] for c in history
                                                if c.startswith(f"{n}.") and c.endswith("_force_y")]
            # Axisymmetric forces have no _x column: a ring's radial resultant is zero.
            pair = {key: np.stack([history.get(f"{n}.{key}_x", np.zeros_like(history[f"{n}.{key}_y"])),
                                   history[f"{n}.{key}_y"]], axis=1)
                    for key in keys if f"{n}.{key}_y" in history}
            out[n] = pair
        return out

    @property
    def times(self) -> NDArray[np.float64]:
        """The time of every frame (s)."""
        return np.array([f.time for f in self.frames])

    @property
    def last(self) -> Frame:
        """The final frame."""
        return self.frames[-1]

    def __repr__(self) -> str:
        return f"Run({str(self.path)!r}, status={self.summary.get('status')!r}, frames={len(self.frames)})"


def load_run(path: str | Path) -> Run:
    """Read a run folder written by :func:`axmpm.run` (or ``axmpm run``) and return a
    :class:`Run`: ``summary`` (dict), ``scenario``, ``history`` (column → array per history
    row), ``reactions`` and ``rigid_bodies`` (name → forces and displacements per row), and
    ``frames`` (the particles at every output time; each :class:`Frame` has ``x``, ``v``,
    ``stress``, ``displacement``, ``material_id``, ``state``, ``state_names``, ... with shapes
    and units in ``help(axmpm.run.output.FrameData)``). Frames are read from disk on first use.

    Example, a load–settlement curve and the plastic strain at the end::

        run = axmpm.load_run("runs/footing")
        body = run.rigid_bodies["footing"]
        settlement, load = -body["displacement"][:, 1], body["force"][:, 1]
        strain = run.last.state_of("plastic_shear_strain")

    ``FileNotFoundError`` if ``path`` is not a run folder (no summary.json).
    """
    return Run(path)
