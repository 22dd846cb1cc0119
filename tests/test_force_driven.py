"""A force-driven footing (``mass`` and ``force`` on a rigid body, docs/physics.md §8) on the
weightless Tresca layer of the footing case at its coarsest mesh (B/h = 10, smooth strip, half
model): under a constant load of 0.8 q_ult it settles and stops; under 1.1 q_ult it keeps
sinking. q_ult = N_c s_u B with the exact N_c = 2 + π (Prandtl).

The load is ramped in over 0.2 s and then held; the soil has Cundall local damping 0.05 so that
the elastic ringing of the layer dies out and "stops" can be judged (undamped, the 0.8 q_ult
footing rings about its rest position at ±0.02 m/s and ±0.4 mm for good). A few seconds each.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

from axmpm.cases.footing.scenario import WIDTH, loaded_footing_scenario
from axmpm.run.runner import run
from axmpm.scenario import Scenario


def _history(run_dir: Path) -> dict[str, list[float]]:
    with open(run_dir / "history.csv") as f:
        rows = list(csv.DictReader(f))
    return {key: [float(r[key]) for r in rows] for key in ("time", "footing.displacement_y", "footing.velocity_y")}


def _run_loaded(tmp_path: Path, load_fraction: float, duration: float) -> dict[str, list[float]]:
    data = loaded_footing_scenario("plane_strain", "smooth", 10, load_fraction, duration).model_dump(
        mode="json", exclude_none=True)
    data["simulation"]["damping"] = 0.05
    out = tmp_path / f"load_{load_fraction}"
    run(Scenario.from_dict(data), out, threads=1)
    return _history(out)


def _settlement_between(history: dict[str, list[float]], t0: float, t1: float) -> float:
    """Settlement (m, positive down) from time t0 to t1 (history rows nearest to them)."""
    times = history["time"]
    i0 = min(range(len(times)), key=lambda i: abs(times[i] - t0))
    i1 = min(range(len(times)), key=lambda i: abs(times[i] - t1))
    d = history["footing.displacement_y"]
    return d[i0] - d[i1]


def test_a_footing_under_0_8_q_ult_settles_and_stops_and_under_1_1_q_ult_keeps_sinking(tmp_path: Path) -> None:
    held = _run_loaded(tmp_path, 0.8, 1.0)
    settlement = -held["footing.displacement_y"][-1]
    # Measured 0.0103 B (elastic: E = 3 MPa); a contact that let the footing in would go on.
    assert 0.0 < settlement < 0.02 * WIDTH, f"settlement {settlement / WIDTH:.4f} B"
    # It stops: over the last half of the run it moves by less than 1 % of its settlement
    # (measured 2·10⁻⁵ m) and its velocity is below 0.01 m/s (measured 0.003 m/s, the noise of
    # the step: a_ext Δt with a_ext = F/M = 86 m/s² and Δt = 2.4·10⁻⁴ s).
    late = _settlement_between(held, 0.5, 1.0)
    assert abs(late) < 0.01 * settlement, f"moved {late:.2e} m after t = 0.5 s"
    assert abs(held["footing.velocity_y"][-1]) < 0.01
    sinking = _run_loaded(tmp_path, 1.1, 0.6)
    # Still sinking at the end: 0.12 B by 0.6 s (measured), by more than 0.02 B in the last 0.1 s,
    # faster than 0.1 m/s.
    assert -sinking["footing.displacement_y"][-1] > 0.08 * WIDTH
    assert _settlement_between(sinking, 0.5, 0.6) > 0.02 * WIDTH
    assert sinking["footing.velocity_y"][-1] < -0.1


def test_the_loaded_footing_carries_its_share_of_q_ult() -> None:
    """The circle: 0.5 × 6.05 s_u (rough) over π B²/4, a concrete disc of 0.2 m (2400 kg/m³)."""
    body = loaded_footing_scenario("axisymmetric", "rough", 10, 0.5, 0.1).rigid_bodies[0]
    assert body.motion is None and body.velocity is None
    assert body.mass == pytest.approx(2400.0 * 0.2 * math.pi / 4.0, rel=1e-12)
    assert body.force[-1][2] == pytest.approx(-0.5 * 6.05 * 10e3 * math.pi / 4.0, rel=1e-12)
