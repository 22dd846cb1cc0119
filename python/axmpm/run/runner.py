"""Running a scenario: the engine loop, output at every output time, summary, history and
restart checkpoints.

The engine advances in chunks of at most ``chunk_steps`` steps (``Simulation.advance``
releases the GIL). Ctrl-C (SIGINT) sets a flag that is looked at between chunks: the run
then stops, writes the checkpoint of the last output time, records status ``interrupted``
in ``summary.json`` and re-raises ``KeyboardInterrupt`` (a second Ctrl-C aborts at once).
An engine ``SimulationFailure`` (NaN/inf, a particle leaving the grid, an inverted
Jacobian) ends the run with status ``failed`` and the engine's message; the frames already
written are kept and the checkpoint of the last good output time is written (the engine's
state after a failure is not usable, so the runner keeps the bytes of the last good one).

Checkpoints (``checkpoint.npz``, the latest only) are always at output times, because the
engine resumes bit for bit only when the resumed run stops at the same times: every
``simulation.checkpoint_interval`` rounded up to a whole number of output intervals, and
whenever the run stops. :func:`resume` continues a run folder from its checkpoint.
See docs/robustness.md.
"""

from __future__ import annotations

import contextlib
import json
import math
import shutil
import signal
import sys
import threading
import time as _time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from ..engine import core
from ..errors import EXIT_FAILED, EXIT_OK, RunError
from ..scenario import Scenario
from .lock import LOCK, RunLock
from .output import (
    FRAMES,
    HISTORY,
    PROGRAM,
    SCENARIO,
    SUMMARY,
    Checkpoint,
    FrameData,
    HistoryWriter,
    frame_stem,
    is_run_folder,
    read_checkpoint,
    remove_frames_from,
    remove_temporary_files,
    write_checkpoint,
    write_frame,
    write_json,
    output_message,
    write_json_robustly,
    write_pvd,
    write_outlines,
    outline_entries,
    BODIES_PVD,
    write_text,
)
from .probes import probe_columns

__all__ = ["run", "resume", "report_run", "THREADS_HELP", "THREADS_DEFAULT", "thread_count", "check_output_folder", "prepare_output_folder", "checkpoint_every",
           "DEFAULT_CHUNK_STEPS"]

#: Steps per ``advance`` call: small enough for a responsive Ctrl-C and progress bar.
DEFAULT_CHUNK_STEPS = 200


#: Help of a ``--threads`` option that sets the engine threads of one run.
THREADS_DEFAULT = "0 = every core the problem can use, one per 10,000 particles (default)"
THREADS_HELP = f"engine threads, {THREADS_DEFAULT}"


def thread_count(text: str) -> int:
    """argparse type of ``--threads``: an integer >= 0 (0: the engine chooses, see :data:`THREADS_HELP`)."""
    import argparse

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0 (got {text!r})") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0 (got {value})")
    return value


def reaction_columns(reactions: dict[str, list[float]], axisymmetric: bool) -> dict[str, float]:
    """History columns of the reactions: ``NAME.force_x/y`` (N, mean since the previous row).
    Axisymmetric: the axial ``NAME.force_y`` of the whole ring, and instead of a ``force_x`` the
    ``NAME.radial_force_integral``, 2π times the sum of the radial nodal forces: the integral of
    the radial traction over the surface, not a resultant (a ring's radial resultant is zero)."""
    columns: dict[str, float] = {}
    for name, (fx, fy) in reactions.items():
        if axisymmetric:
            columns.update({f"{name}.force_y": fy, f"{name}.radial_force_integral": fx})
        else:
            columns.update({f"{name}.force_x": fx, f"{name}.force_y": fy})
    return columns


def rigid_body_columns(sim: Any, axisymmetric: bool = False) -> dict[str, float]:
    """History columns of the rigid bodies at the current output time: ``NAME.displacement_x/y``
    (m), ``NAME.velocity_x/y`` (m/s: the prescribed one, or a force-driven body's) and the force
    split into parts, ``NAME.PART_force_x/y`` (N, mean since the previous row): ``base`` (contact
    with normals facing down) and ``shaft`` (the rest), and, for a body with ``parts``, each named
    part by height and ``rest``. Each split sums to the ``NAME.force_x/y`` column of the reactions.
    Axisymmetric: the axial parts ``_y`` only (a ring's radial resultant is zero; see
    :func:`reaction_columns`)."""
    columns: dict[str, float] = {}
    parts = dict(sim.rigid_body_parts())
    velocities = {name: (vx, vy) for name, vx, vy in sim.rigid_body_velocities()}
    for name, dx, dy in sim.rigid_body_displacements():
        vx, vy = velocities[name]
        columns.update({f"{name}.displacement_x": float(dx), f"{name}.displacement_y": float(dy)})
        if not axisymmetric:
            columns[f"{name}.velocity_x"] = float(vx)
        columns[f"{name}.velocity_y"] = float(vy)
        for part, fx, fy in parts[name]:
            if not axisymmetric:
                columns[f"{name}.{part}_force_x"] = float(fx)
            columns[f"{name}.{part}_force_y"] = float(fy)
    return columns


def rigid_body_summary(columns: dict[str, float], reactions: dict[str, list[float]]) -> dict[str, Any]:
    """summary.json's ``rigid_bodies``: per body, the last row's displacement, force and its
    parts, ``PART_force`` (``base_force``, ``shaft_force`` and any named parts; axisymmetric:
    radial components 0, a ring's radial resultant)."""
    names = [c[: -len(".displacement_x")] for c in columns if c.endswith(".displacement_x")]
    summary: dict[str, Any] = {}
    for n in names:
        entry: dict[str, Any] = {"displacement": [columns[f"{n}.displacement_x"], columns[f"{n}.displacement_y"]],
                                 "force": reactions.get(n, [float("nan")] * 2)}
        for column in columns:
            if column.startswith(f"{n}.") and column.endswith("_force_y"):
                key = column[len(n) + 1: -len("_y")]
                entry[key] = [columns.get(f"{n}.{key}_x", 0.0), columns[column]]
        summary[n] = entry
    return summary


def check_output_folder(out: Path, overwrite: bool) -> None:
    """Refuse (:class:`RunError`) an ``out`` that is a file, or a non-empty folder that is
    not a previous axmpm run (a folder with axmpm's ``summary.json``) unless ``overwrite``."""
    if out.exists() and not out.is_dir():
        raise RunError(f"--out {out} exists and is not a folder")
    if out.is_dir() and any(p.name != LOCK for p in out.iterdir()):
        if not (is_run_folder(out) or overwrite):
            raise RunError(
                f"--out {out} is a non-empty folder that is not an axmpm run; "
                "choose another folder or pass --overwrite to replace its contents"
            )
        resolved = out.resolve()
        protected = {Path("/").resolve(), Path.home().resolve()}
        if resolved in protected or Path.cwd().resolve().is_relative_to(resolved):
            raise RunError(f"refusing to clear {out}: it is the root, home or current folder")


def prepare_output_folder(out: Path, overwrite: bool) -> None:
    """Make ``out`` an empty folder (but for its lock), after :func:`check_output_folder` allowed it."""
    check_output_folder(out, overwrite)
    if out.is_dir():
        for child in out.iterdir():
            if child.name == LOCK:
                continue
            if child.is_dir() and not child.is_symlink():
                shutil.rmtree(child)
            else:
                child.unlink()
    out.mkdir(parents=True, exist_ok=True)


def _engine_class() -> tuple[Any, type[BaseException]]:
    try:
        _core = core()
    except ImportError as exc:  # pragma: no cover - depends on the build
        raise RunError(str(exc)) from None
    failure = getattr(_core, "SimulationFailure", RuntimeError)
    return _core.Simulation, failure


def _coerce(scenario: Scenario | str | Path | dict[str, Any]) -> Scenario:
    if isinstance(scenario, Scenario):
        return scenario
    if isinstance(scenario, dict):
        return Scenario.from_dict(scenario)
    return Scenario.from_toml(scenario)


def _progress_bar(total: float, enabled: bool | None) -> Any:
    from tqdm import tqdm

    disable = not (sys.stderr.isatty() if enabled is None else enabled)
    return tqdm(
        total=total,
        disable=disable,
        unit="s",
        unit_scale=False,
        bar_format="{l_bar}{bar}| t={n:.4g}/{total:.4g} s [{elapsed}<{remaining}{postfix}]",
        file=sys.stderr,
        leave=True,
    )


def _at_rest(energies: dict[str, float], time: float, sim_cfg: Any) -> bool:
    """The deposit is at rest: kinetic energy below ``stop_at_rest`` times the work gravity has
    done (the potential energy released), from ``stop_at_rest_after`` on."""
    ratio = sim_cfg.stop_at_rest
    if ratio <= 0.0 or time < sim_cfg.stop_at_rest_after:
        return False
    released = energies.get("gravity_work", 0.0)
    return released > 0.0 and energies.get("kinetic_energy", 0.0) < ratio * released


def _settled(gravity_work: list[tuple[float, float]], time: float, sim_cfg: Any) -> bool:
    """The body has stopped moving down: the work gravity did over the last ``settle_window``
    seconds is, in magnitude, below ``stop_when_settled`` times all the work it has done, from
    ``stop_at_rest_after`` on. ``gravity_work`` holds (time, work) at the output times so
    far, in order. Unlike the kinetic-energy test this ends undamped runs (pure FLIP) whose
    deposit is in place but keeps a small elastic vibration that never decays."""
    ratio = getattr(sim_cfg, "stop_when_settled", 0.0)
    window = getattr(sim_cfg, "settle_window", 0.0)
    if ratio <= 0.0 or time < sim_cfg.stop_at_rest_after or not gravity_work:
        return False
    t_now, w_now = gravity_work[-1]
    earlier = [w for t, w in gravity_work if t <= t_now - window * (1.0 - 1e-9)]
    if not earlier or w_now <= 0.0:
        return False
    return abs(w_now - earlier[-1]) < ratio * w_now


def checkpoint_every(sim_cfg: Any) -> int | None:
    """Output intervals between periodic checkpoints: ``checkpoint_interval`` rounded up to
    a whole number of ``output_interval`` (checkpoints must fall on output times); None when
    no periodic checkpoints are asked for."""
    interval = getattr(sim_cfg, "checkpoint_interval", None)
    if not interval:
        return None
    return max(1, math.ceil(interval / sim_cfg.output_interval - 1e-9))


def _row_times(sim_cfg: Any, k: int) -> list[tuple[float, bool]]:
    """The times to stop at on the way to output ``k``: (time, is the frame) — the history rows
    every ``history_interval`` after output k − 1 (when set), then output k itself."""
    target = _output_time(sim_cfg, k)
    interval = getattr(sim_cfg, "history_interval", None)
    times: list[tuple[float, bool]] = []
    if interval:
        start = _output_time(sim_cfg, k - 1)
        n = math.ceil((target - start) / interval - 1e-9)
        times = [(start + j * interval, False) for j in range(1, n) if start + j * interval < target * (1 - 1e-12)]
    return times + [(target, True)]


def _output_count(sim_cfg: Any) -> int:
    return max(1, math.ceil(sim_cfg.end_time / sim_cfg.output_interval - 1e-9))


def _output_time(sim_cfg: Any, k: int) -> float:
    return min(k * sim_cfg.output_interval, sim_cfg.end_time)


@contextlib.contextmanager
def _sigint_flag() -> Iterator[dict[str, bool]]:
    """While active, the first Ctrl-C only sets ``flag["hit"]`` (the run stops cleanly after
    the current chunk); a second one raises ``KeyboardInterrupt`` at once. Only in the main
    thread and when Python's default SIGINT handler is installed; elsewhere Ctrl-C raises
    ``KeyboardInterrupt`` as usual (also handled)."""
    flag = {"hit": False}
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield flag
        return

    def handler(signum: int, frame: Any) -> None:
        if flag["hit"]:
            raise KeyboardInterrupt
        flag["hit"] = True

    previous = signal.signal(signal.SIGINT, handler)
    try:
        yield flag
    finally:
        signal.signal(signal.SIGINT, previous)


class _NoBar:
    def close(self) -> None:
        pass


class _Driver:
    """The output loop shared by :func:`run` and :func:`resume`."""

    def __init__(self, sim: Any, failure_type: type[BaseException], scenario: Scenario, out: Path,
                 summary: dict[str, Any], history: HistoryWriter, pvd_entries: list[tuple[float, Path]],
                 *, progress: bool | None, chunk_steps: int, checkpoints: bool,
                 wall_offset: float = 0.0, engine_seconds: float = 0.0):
        self.sim = sim
        self.failure_type = failure_type
        self.scenario = scenario
        self.sim_cfg = scenario.simulation
        self.out = out
        self.summary = summary
        self.history = history
        self.pvd_entries = pvd_entries
        self.progress = progress
        self.chunk_steps = int(chunk_steps)
        self.checkpoints = checkpoints
        self.started = _time.perf_counter()
        self.wall_offset = wall_offset
        self.engine_seconds = engine_seconds
        self.last_good: Checkpoint | None = None

    def wall(self) -> float:
        return self.wall_offset + (_time.perf_counter() - self.started)

    # -- pieces -------------------------------------------------------------------------

    def record_history(self, time: float, steps: int, frame: FrameData | None = None) -> None:
        """A history row at the current time: energies, reactions (mean forces since the
        previous row), rigid bodies, probes (from ``frame`` when given, the particles' state now)."""
        sim = self.sim
        energies = {k: float(v) for k, v in sim.energies().items()}
        axisymmetric = self.sim_cfg.formulation == "axisymmetric"
        reactions = {name: [float(fx), float(fy)] for name, fx, fy in sim.reactions()}
        rigid = rigid_body_columns(sim, axisymmetric)
        surcharges = {f"{name}.applied_force_y": float(fy) for name, _, fy in sim.surcharge_forces()}
        outflow = sim.water_outflow()
        water = {} if outflow is None else {"water_outflow": float(outflow)}
        probes: dict[str, float] = {}
        if self.scenario.probes:
            probes = probe_columns(self.scenario.probes, frame or FrameData.from_simulation(sim),
                                   self.sim_cfg.formulation, self.scenario.grid.cell_size)
        self.history.append(
            {"time": time, "steps": steps, "dt": float(sim.dt),
             **dict(sorted(energies.items())), **water, "wall_seconds": self.wall(),
             **reaction_columns(reactions, axisymmetric),
             **rigid, **surcharges, **probes}
        )
        if axisymmetric:
            # The radial resultant of a ring is zero; the radial sum is reported apart.
            reactions = {name: [0.0, f[1]] for name, f in reactions.items()}
        self.summary["energies"] = energies
        self.summary["reactions"] = reactions
        if rigid:
            self.summary["rigid_bodies"] = rigid_body_summary(rigid, reactions)

    def record(self) -> None:
        """Frame, pvd and history row at the current (output) time."""
        sim, out = self.sim, self.out
        frame = FrameData.from_simulation(sim)
        index = len(self.pvd_entries)
        try:
            vtu = write_frame(out, index, frame, self.sim_cfg.formulation)
            outlines = sim.rigid_body_outlines()
            if outlines:
                write_outlines(out, index, outlines)
                write_pvd(out, outline_entries(out, [*self.pvd_entries, (frame.time, vtu)]), BODIES_PVD)
            write_pvd(out, [*self.pvd_entries, (frame.time, vtu)])
        except OSError:
            with contextlib.suppress(OSError):
                remove_frames_from(out, index)  # an incomplete frame is not kept
            raise
        self.pvd_entries.append((frame.time, vtu))  # complete: its files and the pvd entry
        self.record_history(frame.time, frame.steps, frame)

    def snapshot(self, k: int) -> None:
        """Keep the engine state of output ``k`` in memory: the last good restart point."""
        if not self.checkpoints:
            return
        sim = self.sim
        self.last_good = Checkpoint(
            engine=bytes(sim.to_bytes()),
            time=float(sim.time),
            steps=int(sim.steps),
            output_index=k,
            frame_times=[t for t, _ in self.pvd_entries],
            wall_seconds=self.wall(),
            engine_seconds=self.engine_seconds,
            energies=dict(self.summary.get("energies", {})),
        )

    def save_checkpoint(self) -> None:
        """Write the last good restart point to ``checkpoint.npz`` (if any)."""
        if self.last_good is None:
            return
        write_checkpoint(self.out, self.last_good)
        self.summary["checkpoint"] = self.last_good.meta()

    def finish(self, status: str, message: str = "", failure: str | None = None) -> dict[str, Any]:
        """Record the end of the run in summary.json; ``failure`` says what failed ("engine": the
        simulation, "output": writing the run folder, "error": anything else)."""
        sim, summary = self.sim, self.summary
        steps = int(sim.steps)
        engine_seconds = self.engine_seconds
        summary.update(
            status=status,
            message=message,
            steps=steps,
            end_time=float(sim.time),
            dt=float(sim.dt),
            wall_seconds=self.wall(),
            engine_seconds=engine_seconds,
            particle_steps_per_second=(steps * int(sim.num_particles) / engine_seconds) if engine_seconds > 0 else 0.0,
            frames=len(self.pvd_entries),
        )
        if failure is not None:
            summary["failure"] = failure
        if status == "failed" and self.pvd_entries:
            summary["last_good_time"] = float(self.pvd_entries[-1][0])
            summary["last_good_frame"] = len(self.pvd_entries) - 1
        if status != "failed":
            try:
                summary["energies"] = {k: float(v) for k, v in sim.energies().items()}
            except Exception:  # pragma: no cover - keep the last recorded energies
                pass
        if status == "completed":
            write_json(self.out / SUMMARY, summary)
        else:  # the output may be what failed: write the summary wherever it still can be
            problem = write_json_robustly(self.out / SUMMARY, summary)
            if problem:
                summary["summary_not_written"] = problem
        return summary

    # -- the loop -----------------------------------------------------------------------

    def drive(self, start_k: int) -> dict[str, Any]:
        """Advance from output ``start_k`` (already recorded) to the end."""
        sim, sim_cfg = self.sim, self.sim_cfg
        end_time = sim_cfg.end_time
        n_outputs = _output_count(sim_cfg)
        every = checkpoint_every(sim_cfg)
        tolerance = 1e-12 * end_time
        bar: Any = _NoBar()
        try:
            bar = _progress_bar(end_time, self.progress)
            bar.update(float(sim.time))
            with _sigint_flag() as flag:
                for k in range(start_k + 1, n_outputs + 1):
                    # History rows between two frames (history_interval), then the frame.
                    for target, frame in _row_times(sim_cfg, k):
                        while sim.time < target - tolerance:
                            if flag["hit"]:
                                raise KeyboardInterrupt
                            t0 = _time.perf_counter()
                            try:
                                taken = sim.advance(target, max_steps=self.chunk_steps)
                            except self.failure_type as exc:
                                self.engine_seconds += _time.perf_counter() - t0
                                bar.close()
                                return self.fail(str(exc) or type(exc).__name__)
                            dt_wall = _time.perf_counter() - t0
                            self.engine_seconds += dt_wall
                            if taken == 0 and sim.time < target - tolerance:
                                bar.close()
                                return self.fail(f"the engine made no progress at t = {sim.time:g} s")
                            bar.update(float(sim.time) - bar.n)
                            if dt_wall > 0:
                                bar.set_postfix_str(f"{taken / dt_wall:.0f} steps/s", refresh=False)
                        if not frame:
                            self.record_history(float(sim.time), int(sim.steps))
                    self.record()
                    self.snapshot(k)
                    if (_at_rest(self.summary["energies"], float(sim.time), sim_cfg)
                            or _settled(self.history.series("gravity_work"), float(sim.time), sim_cfg)):
                        self.summary["stopped_at_rest"] = True
                        break
                    if flag["hit"]:
                        raise KeyboardInterrupt
                    if every is not None and k % every == 0 and k < n_outputs:
                        self.save_checkpoint()
                        write_json(self.out / SUMMARY, self.summary)
        except KeyboardInterrupt:
            bar.close()
            self.save_checkpoint()
            self.finish("interrupted", "interrupted by the user (Ctrl-C)")
            ckpt = self.summary.get("checkpoint")
            where = f"; checkpoint at t = {ckpt['time']:.6g} s" if ckpt else ""
            print(f"interrupted at t = {float(sim.time):.6g} s{where}; continue with: axmpm resume {self.out}",
                  file=sys.stderr)
            raise
        except OSError as exc:  # writing the output failed: a failed run, what was complete is kept
            bar.close()
            return self.fail_output(exc)
        except Exception as exc:  # a bug: record it, then let it propagate
            bar.close()
            with contextlib.suppress(Exception):
                self.save_checkpoint()
            self.finish("failed", f"{type(exc).__name__}: {exc}", failure="error")
            raise
        bar.close()
        try:
            self.save_checkpoint()
            return self.finish("completed")
        except OSError as exc:
            return self.fail_output(exc)

    def fail(self, message: str) -> dict[str, Any]:
        """The engine failed: keep the last good output time's checkpoint, record the reason."""
        try:
            self.save_checkpoint()  # the last good output time; the engine's current state is bad
        except OSError as exc:
            message += f"; {output_message(exc)}"
        return self.finish("failed", message, failure="engine")

    def fail_output(self, exc: OSError) -> dict[str, Any]:
        """Writing the output failed (disk full, folder removed, ...): the run failed. The files
        already complete stay (atomic writes), temporary files go, the checkpoint of the last
        output time is written if it still can be, and the summary records the file and reason."""
        remove_temporary_files(self.out)
        with contextlib.suppress(OSError):
            self.save_checkpoint()
        return self.finish("failed", output_message(exc), failure="output")


def run(
    scenario: Scenario | str | Path | dict[str, Any],
    out: str | Path,
    threads: int = 0,
    overwrite: bool = False,
    progress: bool | None = None,
    chunk_steps: int = DEFAULT_CHUNK_STEPS,
    *,
    checkpoints: bool = True,
) -> dict[str, Any]:
    """Run a scenario and write its output folder; return the summary dict.

    ``threads`` = 0 uses all cores (results do not depend on it). ``progress`` None shows
    a progress bar only when stderr is a terminal. Raises :class:`RunError` for a refused
    output folder or a scenario the engine rejects, :class:`~axmpm.errors.ScenarioError`
    for an invalid scenario, ``KeyboardInterrupt`` after recording an interrupted run
    (status ``interrupted``, checkpoint written). An engine failure does *not* raise: the
    summary's ``status`` is ``"failed"``, its ``message`` the engine's reason.

    ``checkpoints`` False skips restart checkpoints entirely (no ``checkpoint.npz``, no
    in-memory copy of the engine state at every output time), e.g. for benchmarks.
    """
    scenario = _coerce(scenario)
    out = Path(out)
    Simulation, SimulationFailure = _engine_class()
    check_output_folder(out, overwrite)  # refuse early, but clear only once the engine accepted

    sim_cfg = scenario.simulation
    try:
        sim = Simulation(scenario.engine_json(), int(threads))
    except (ValueError, TypeError) as exc:
        raise RunError(f"the engine rejected the scenario: {exc}") from None
    with RunLock(out, "axmpm run"):  # one writer per folder; refuses naming the holder
        prepare_output_folder(out, overwrite)
        summary: dict[str, Any] = {
            "program": PROGRAM,
            "status": "running",
            "formulation": sim_cfg.formulation,
            "shape_function": sim_cfg.shape_function,
            "particles": int(sim.num_particles),
            "nodes": int(sim.num_nodes),
            "grid_shape": list(sim.grid_shape),
            "threads": int(getattr(sim, "threads", threads)),
            "steps": 0,
            "end_time": 0.0,
            "target_end_time": sim_cfg.end_time,
            "dt": float(sim.dt),
            "wall_seconds": 0.0,
            "engine_seconds": 0.0,
            "particle_steps_per_second": 0.0,
            "energies": {},
            "reactions": {},
            "frames": 0,
            "message": "",
            "stopped_at_rest": False,
            "checkpoint": None,
            "resumed": 0,
        }
        driver = _Driver(sim, SimulationFailure, scenario, out, summary, HistoryWriter(out / HISTORY), [],
                         progress=progress, chunk_steps=chunk_steps, checkpoints=checkpoints)
        try:
            write_json(out / SUMMARY, summary)
            write_text(out / SCENARIO, scenario.to_toml())
            driver.record()
            driver.snapshot(0)
        except KeyboardInterrupt:
            driver.save_checkpoint()
            driver.finish("interrupted", "interrupted by the user (Ctrl-C)")
            raise
        except OSError as exc:
            return driver.fail_output(exc)
        except Exception as exc:
            driver.finish("failed", f"{type(exc).__name__}: {exc}", failure="error")
            raise
        return driver.drive(0)


def resume(
    out: str | Path,
    threads: int = 0,
    progress: bool | None = None,
    chunk_steps: int = DEFAULT_CHUNK_STEPS,
) -> dict[str, Any]:
    """Continue the run in folder ``out`` from its checkpoint; return the summary dict.

    Frames and history rows written after the checkpoint are dropped and written again;
    the result is bit for bit the one of an uninterrupted run (same ``chunk_steps``).
    A completed run is left alone (its summary is returned). Raises :class:`RunError` when
    ``out`` is not a run folder or has no usable checkpoint, ``KeyboardInterrupt`` as
    :func:`run` does.
    """
    out = Path(out)
    if not out.is_dir():
        raise RunError(f"{out} is not a folder")
    if not is_run_folder(out):
        raise RunError(f"{out} is not an axmpm run folder (no readable {SUMMARY})")
    if _status(out) == "completed":
        return json.loads((out / SUMMARY).read_text())
    with RunLock(out, "axmpm resume"):  # one writer per folder; refuses naming the holder
        return _resume_locked(out, threads, progress, chunk_steps)


def _status(out: Path) -> str | None:
    try:
        return json.loads((out / SUMMARY).read_text()).get("status")
    except (OSError, ValueError, AttributeError):
        return None


def _resume_locked(out: Path, threads: int, progress: bool | None, chunk_steps: int) -> dict[str, Any]:
    summary: dict[str, Any] = json.loads((out / SUMMARY).read_text())
    if summary.get("status") == "completed":  # completed by the writer that held the lock
        return summary
    try:
        ckpt = read_checkpoint(out)
    except FileNotFoundError:
        raise RunError(f"{out} has no checkpoint to resume from (the run stopped before its first "
                       "output time, or checkpoints were off); run it again instead") from None
    except ValueError as exc:
        raise RunError(str(exc)) from None
    scenario = Scenario.from_toml(out / SCENARIO)
    Simulation, SimulationFailure = _engine_class()
    try:
        sim = Simulation.from_bytes(ckpt.engine, int(threads))
    except (ValueError, TypeError, RuntimeError) as exc:
        raise RunError(f"the checkpoint in {out} cannot be restored: {exc}") from None
    if float(sim.time) != ckpt.time or int(sim.steps) != ckpt.steps:
        raise RunError(f"the checkpoint in {out} is inconsistent (engine t = {sim.time}, recorded {ckpt.time})")

    remove_temporary_files(out)
    remove_frames_from(out, ckpt.frames)
    pvd_entries = [(t, out / FRAMES / f"{frame_stem(i)}.vtu") for i, t in enumerate(ckpt.frame_times)]
    missing = [str(p) for _, p in pvd_entries if not p.exists()]
    if missing:
        raise RunError(f"{out} lacks frames written before its checkpoint: {', '.join(missing[:3])}")
    write_pvd(out, pvd_entries)
    if bodies := outline_entries(out, pvd_entries):
        write_pvd(out, bodies, BODIES_PVD)
    history = HistoryWriter.resume(out / HISTORY, ckpt.time)

    summary.update(status="running", message="", resumed=int(summary.get("resumed", 0)) + 1,
                   threads=int(getattr(sim, "threads", threads)), energies=dict(ckpt.energies),
                   stopped_at_rest=False, checkpoint=ckpt.meta())
    for key in ("last_good_time", "last_good_frame", "failure", "summary_not_written"):
        summary.pop(key, None)
    write_json(out / SUMMARY, summary)
    driver = _Driver(sim, SimulationFailure, scenario, out, summary, history, pvd_entries,
                     progress=progress, chunk_steps=chunk_steps, checkpoints=True,
                     wall_offset=ckpt.wall_seconds, engine_seconds=ckpt.engine_seconds)
    driver.last_good = ckpt
    return driver.drive(ckpt.output_index)


def report_run(summary: dict[str, Any], out: Path) -> int:
    """Print the outcome of a run (one line; a failure's reason on stderr) and return the exit
    code of ``axmpm run``: :data:`~axmpm.errors.EXIT_OK` or :data:`~axmpm.errors.EXIT_FAILED`."""
    status = summary["status"]
    print(f"{status}: {summary['steps']} steps to t = {summary['end_time']:.6g} s, "
          f"{summary['particles']} particles, {summary['wall_seconds']:.2f} s wall, "
          f"{summary['particle_steps_per_second']:.3g} particle-steps/s; output in {out}")
    if status == "failed":
        what = {"output": "writing the output failed", "error": "the run failed"}.get(
            summary.get("failure", ""), "simulation failed")
        print(f"error: {what}: {summary['message']}", file=sys.stderr)
        if summary.get("summary_not_written"):
            print(f"error: summary.json not updated: {summary['summary_not_written']}", file=sys.stderr)
        return EXIT_FAILED
    return EXIT_OK
