"""Load–settlement of the pile load test (examples/pile_load_test.toml) with its base and shaft
shares, from a finished run folder:

    python examples/pile_load_test.py runs/pile [figure.png]

The pile's force is read from history.csv through ``axmpm.load_run(...).rigid_bodies["pile"]``:
``force`` (the total the sand exerts on the pile, N, the whole ring), ``base_force`` (contact at
faces looking down: the tip) and ``shaft_force`` (the sides); each is the mean over the interval
before its row, so it is plotted at the interval's mid-settlement.

It also prints two textbook estimates from the run's own scenario (``scenario.toml``):

* base: q_b = N_q σ'_v0 at the tip with Berezantzev et al.'s (1961) N_q for the pile's
  embedment ratio L/D, read from their chart (docs/physics.md §8: values and confidence);
* shaft: τ_s = K σ'_v0 tan δ over the embedded length with K = K0 = 1 − sin φ (the β method,
  an at-rest estimate).
"""

from __future__ import annotations

import sys
from pathlib import Path

import tomllib

import numpy as np

import axmpm

#: Berezantzev, Khristoforov & Golubkov (1961) N_q against φ (degrees) for L/D = 5, 10, 20,
#: as read from the chart reproduced in design texts (Tomlinson; Poulos & Davis 1980). The
#: chart is log-linear in φ; these are chart readings, not a formula [low–medium]:
#: docs/physics.md §8.
BEREZANTZEV_NQ = {  # φ: (L/D = 5, 10, 20)
    26.0: (17.4, 13.2, 11.0), 28.0: (25.1, 19.1, 15.8), 30.0: (36.3, 27.5, 22.9),
    32.0: (52.5, 39.8, 33.1), 34.0: (75.9, 57.5, 47.9), 36.0: (110.0, 83.2, 69.2),
}


def berezantzev_nq(friction_angle: float, embedment_ratio: float) -> float:
    """N_q interpolated log-linearly in φ and in log(L/D), clamped to the chart's range."""
    angles = np.array(sorted(BEREZANTZEV_NQ))
    ratios = np.log([5.0, 10.0, 20.0])
    table = np.log(np.array([BEREZANTZEV_NQ[a] for a in angles]))
    phi = float(np.clip(friction_angle, angles[0], angles[-1]))
    by_ratio = [np.interp(phi, angles, table[:, k]) for k in range(3)]
    return float(np.exp(np.interp(np.log(np.clip(embedment_ratio, 5.0, 20.0)), ratios, by_ratio)))


def textbook_estimates(run_dir: Path, body: str = "pile") -> dict[str, float]:
    """Berezantzev base and K0 β-method shaft resistance (N, whole pile) for the run's scenario."""
    scenario = tomllib.loads((run_dir / "scenario.toml").read_text())
    pile = next(b for b in scenario["rigid_bodies"] if b["name"] == body)
    soil = scenario["bodies"][0]
    material = scenario["materials"][soil["material"]]
    gravity = abs(scenario["simulation"]["gravity"][1])
    unit_weight = material["density"] * gravity
    surface, tip, radius = soil["max"][1], pile["min"][1], pile["max"][0]
    embedment = surface - tip
    phi = material["friction_angle"]
    nq = berezantzev_nq(phi, embedment / (2.0 * radius))
    base = nq * unit_weight * embedment * np.pi * radius**2
    k0 = 1.0 - np.sin(np.radians(phi))
    shaft = k0 * pile["friction"] * unit_weight * 0.5 * embedment**2 * 2.0 * np.pi * radius
    return {"nq": nq, "base": base, "shaft": shaft, "embedment_ratio": embedment / (2.0 * radius)}


def load_settlement(run_dir: str | Path) -> dict[str, np.ndarray]:
    pile = axmpm.load_run(run_dir).rigid_bodies["pile"]
    settlement = -pile["displacement"][:, 1]
    mid = 0.5 * (settlement[1:] + settlement[:-1])
    return {"settlement": mid, "total": pile["force"][1:, 1], "base": pile["base_force"][1:, 1],
            "shaft": pile["shaft_force"][1:, 1]}


def main(argv: list[str]) -> int:
    run_dir = Path(argv[1]) if len(argv) > 1 else Path("runs/pile")
    figure = Path(argv[2]) if len(argv) > 2 else run_dir / "load_settlement.png"
    curve = load_settlement(run_dir)
    from axmpm.plotting import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4.5))
    s = 1000.0 * curve["settlement"]
    for key, colour in (("total", "black"), ("base", "tab:red"), ("shaft", "tab:blue")):
        ax.plot(s, curve[key] / 1000.0, color=colour, label=key)
    ax.set_xlabel("settlement (mm)")
    ax.set_ylabel("load (kN, whole pile)")
    ax.grid(alpha=0.3)
    ax.legend()
    save_figure(fig, figure)
    pushed = curve["settlement"] > 0.0
    for target in (0.01, 0.025, 0.05, 0.1):
        near = np.argmin(np.abs(curve["settlement"] - target)) if pushed.any() else None
        if near is not None:
            print(f"settlement {1000 * curve['settlement'][near]:5.1f} mm: total {curve['total'][near] / 1e3:8.1f} kN, "
                  f"base {curve['base'][near] / 1e3:8.1f} kN, shaft {curve['shaft'][near] / 1e3:8.1f} kN")
    est = textbook_estimates(run_dir)
    print(f"Berezantzev (L/D = {est['embedment_ratio']:.0f}, N_q = {est['nq']:.1f}): base {est['base'] / 1e3:.1f} kN; "
          f"measured base at the end {curve['base'][-1] / 1e3:.1f} kN ({curve['base'][-1] / est['base']:.2f} of it)")
    print(f"β method with K0 (at rest): shaft {est['shaft'] / 1e3:.1f} kN; measured shaft at the end "
          f"{curve['shaft'][-1] / 1e3:.1f} kN ({curve['shaft'][-1] / est['shaft']:.2f} of it)")
    print(f"figure: {figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
