"""What a run will cost, before it runs (``axmpm check``): the engine's time step, the number of
steps to ``end_time``, and the run time from the particle-steps and a throughput measured on
this scenario (the engine built and a few steps timed), so that a user sees before the run that
a stiff material or a fine grid means hours."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

from ..errors import RunError
from .runner import _engine_class

__all__ = ["RunEstimate", "estimate_run", "format_duration"]

#: Wall time spent measuring the throughput (s), and the steps timed at least / at most.
MEASURE_SECONDS = 1.0
MIN_STEPS, MAX_STEPS = 2, 200


def format_duration(seconds: float) -> str:
    if seconds < 60.0:
        return f"{seconds:.3g} s"
    if seconds < 3600.0:
        return f"{seconds / 60.0:.3g} min"
    if seconds < 86400.0:
        return f"{seconds / 3600.0:.3g} h"
    return f"{seconds / 86400.0:.3g} days"


@dataclass(frozen=True)
class RunEstimate:
    time_step: float           # s, the engine's (CFL or fixed)
    steps: int                 # to end_time
    particles: int
    threads: int               # threads the engine ran the timed steps with
    measured_steps: int        # steps timed
    throughput: float          # particle-steps per second measured
    wall_seconds: float        # estimated run time (engine only: output writing not included)
    requested_threads: int = 0  # what was asked for: 0 = all cores

    @property
    def particle_steps(self) -> float:
        return float(self.steps) * self.particles

    def describe(self) -> str:
        """Two lines: the cost in particle-steps, then the run time and the thread count it assumes."""
        plural = "s" if self.threads != 1 else ""
        which = ("the default of `axmpm run`: every core the problem can use, one per 10,000 particles; "
                 "--threads N estimates for N" if self.requested_threads <= 0
                 else f"--threads {self.requested_threads}, as `axmpm run --threads {self.requested_threads}`")
        return (f"time step {self.time_step:.4g} s, {self.steps:,} steps to end_time, {self.particles:,} particles: "
                f"{self.particle_steps:.3g} particle-steps\n"
                f"run time with {self.threads} thread{plural} ({which}): about {format_duration(self.wall_seconds)} "
                f"of run time, from {self.throughput:.3g} particle-steps/s measured over {self.measured_steps} steps "
                f"(output writing not included)")


def estimate_run(scenario: Any, threads: int = 0) -> RunEstimate:
    """Builds the engine for ``scenario``, reads its time step and times a few steps (at most
    about :data:`MEASURE_SECONDS` of wall time)."""
    simulation, failure = _engine_class()
    try:
        sim = simulation(scenario.engine_json(), int(threads))
    except (ValueError, TypeError) as exc:
        raise RunError(f"the engine rejected the scenario: {exc}") from None
    dt = float(sim.dt)
    end = float(scenario.simulation.end_time)
    steps = max(1, math.ceil(end / dt - 1e-9))
    particles = int(sim.num_particles)
    taken = 0
    started = time.perf_counter()
    try:
        while taken < min(MAX_STEPS, steps) and (taken < MIN_STEPS or time.perf_counter() - started < MEASURE_SECONDS):
            taken += int(sim.advance(end, 1))
    except failure:
        pass  # a run that fails early still gives its speed
    elapsed = max(time.perf_counter() - started, 1e-9)
    throughput = taken * particles / elapsed if taken else float("nan")
    wall = steps * particles / throughput if taken else float("nan")
    return RunEstimate(dt, steps, particles, int(sim.threads), taken, throughput, wall, int(threads))
