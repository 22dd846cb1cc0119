"""Running a scenario: the engine loop, output at every output time, summary and history.

The engine advances in chunks of at most ``chunk_steps`` steps (``Simulation.advance``
releases the GIL), so Ctrl-C is seen between chunks: the run then records status
``interrupted`` in ``summary.json`` and re-raises ``KeyboardInterrupt``. An engine
``SimulationFailure`` ends the run with status ``failed`` and the engine's message; the
frames already written are kept.
"""

from __future__ import annotations

import math
import os
import shutil
import sys
import time as _time
from pathlib import Path
from typing import Any

from .errors import RunError
from .output import (
    HISTORY,
    PROGRAM,
    SCENARIO,
    SUMMARY,
    FrameData,
    HistoryWriter,
    is_run_folder,
    write_frame,
    write_json,
    write_pvd,
    write_text,
)
from .scenario import Scenario

__all__ = ["run", "check_output_folder", "prepare_output_folder", "DEFAULT_CHUNK_STEPS"]

#: Steps per ``advance`` call: small enough for a responsive Ctrl-C and progress bar.
DEFAULT_CHUNK_STEPS = 200


def check_output_folder(out: Path, overwrite: bool) -> None:
    """Refuse (:class:`RunError`) an ``out`` that is a file, or a non-empty folder that is
    not a previous axmpm run (a folder with axmpm's ``summary.json``) unless ``overwrite``."""
    if out.exists() and not out.is_dir():
        raise RunError(f"--out {out} exists and is not a folder")
    if out.is_dir() and any(out.iterdir()):
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
    """Make ``out`` an empty folder, after :func:`check_output_folder` allowed it."""
    check_output_folder(out, overwrite)
    if out.is_dir():
        for child in out.iterdir():
            if child.is_dir() and not child.is_symlink():
                shutil.rmtree(child)
            else:
                child.unlink()
    out.mkdir(parents=True, exist_ok=True)


def _engine_class() -> tuple[Any, type[BaseException]]:
    try:
        from . import _core  # type: ignore[attr-defined]
    except ImportError as exc:  # pragma: no cover - depends on the build
        raise RunError(f"the compiled engine axmpm._core is not available ({exc}); run `make install`") from None
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


def run(
    scenario: Scenario | str | Path | dict[str, Any],
    out: str | Path,
    threads: int = 0,
    overwrite: bool = False,
    progress: bool | None = None,
    chunk_steps: int = DEFAULT_CHUNK_STEPS,
) -> dict[str, Any]:
    """Run a scenario and write its output folder; return the summary dict.

    ``threads`` = 0 uses all cores (results do not depend on it). ``progress`` None shows
    a progress bar only when stderr is a terminal. Raises :class:`RunError` for a refused
    output folder or a scenario the engine rejects, :class:`~axmpm.errors.ScenarioError`
    for an invalid scenario, ``KeyboardInterrupt`` after recording an interrupted run.
    An engine failure does *not* raise: the summary's ``status`` is ``"failed"``.
    """
    scenario = _coerce(scenario)
    out = Path(out)
    Simulation, SimulationFailure = _engine_class()
    check_output_folder(out, overwrite)  # refuse early, but clear only once the engine accepted

    sim_cfg = scenario.simulation
    formulation = sim_cfg.formulation
    started = _time.perf_counter()
    try:
        sim = Simulation(scenario.engine_json(), int(threads))
    except (ValueError, TypeError) as exc:
        raise RunError(f"the engine rejected the scenario: {exc}") from None
    prepare_output_folder(out, overwrite)

    summary: dict[str, Any] = {
        "program": PROGRAM,
        "status": "running",
        "formulation": formulation,
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
        "frames": 0,
        "message": "",
        "stopped_at_rest": False,
    }
    write_json(out / SUMMARY, summary)
    write_text(out / SCENARIO, scenario.to_toml())
    history = HistoryWriter(out / HISTORY)
    pvd_entries: list[tuple[float, Path]] = []
    engine_seconds = 0.0

    def record() -> None:
        frame = FrameData.from_simulation(sim)
        vtu = write_frame(out, len(pvd_entries), frame, formulation)
        pvd_entries.append((frame.time, vtu))
        write_pvd(out, pvd_entries)
        energies = {k: float(v) for k, v in sim.energies().items()}
        history.append(
            {"time": frame.time, "steps": frame.steps, "dt": float(sim.dt),
             **dict(sorted(energies.items())), "wall_seconds": _time.perf_counter() - started}
        )
        summary["energies"] = energies

    def finish(status: str, message: str = "") -> dict[str, Any]:
        wall = _time.perf_counter() - started
        steps = int(sim.steps)
        summary.update(
            status=status,
            message=message,
            steps=steps,
            end_time=float(sim.time),
            dt=float(sim.dt),
            wall_seconds=wall,
            engine_seconds=engine_seconds,
            particle_steps_per_second=(steps * int(sim.num_particles) / engine_seconds) if engine_seconds > 0 else 0.0,
            frames=len(pvd_entries),
        )
        try:
            summary["energies"] = {k: float(v) for k, v in sim.energies().items()}
        except Exception:  # pragma: no cover - keep the last recorded energies
            pass
        write_json(out / SUMMARY, summary)
        return summary

    end_time, interval = sim_cfg.end_time, sim_cfg.output_interval
    n_outputs = max(1, math.ceil(end_time / interval - 1e-9))
    tolerance = 1e-12 * end_time
    bar = _progress_bar(end_time, progress)
    try:
        record()
        for k in range(1, n_outputs + 1):
            target = min(k * interval, end_time)
            while sim.time < target - tolerance:
                t0 = _time.perf_counter()
                try:
                    taken = sim.advance(target, max_steps=int(chunk_steps))
                except SimulationFailure as exc:
                    engine_seconds += _time.perf_counter() - t0
                    bar.close()
                    return finish("failed", str(exc) or type(exc).__name__)
                dt_wall = _time.perf_counter() - t0
                engine_seconds += dt_wall
                if taken == 0 and sim.time < target - tolerance:
                    bar.close()
                    return finish("failed", f"the engine made no progress at t = {sim.time:g} s")
                bar.update(float(sim.time) - bar.n)
                if dt_wall > 0:
                    bar.set_postfix_str(f"{taken / dt_wall:.0f} steps/s", refresh=False)
            record()
            if _at_rest(summary["energies"], float(sim.time), sim_cfg):
                summary["stopped_at_rest"] = True
                break
    except KeyboardInterrupt:
        bar.close()
        finish("interrupted", "interrupted by the user (Ctrl-C)")
        raise
    except Exception as exc:  # a bug or I/O error: record it, then let it propagate
        bar.close()
        finish("failed", f"{type(exc).__name__}: {exc}")
        raise
    bar.close()
    return finish("completed")


def default_threads() -> int:
    """Cores available to this process."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - non-Linux
        return os.cpu_count() or 1
