"""Load–settlement of the pile load test (examples/pile_load_test.toml) with its base and shaft
shares, from a finished run folder:

    python examples/pile_load_test.py runs/pile [figure.png]

The pile's force is read from history.csv through ``axmpm.load_run(...).rigid_bodies["pile"]``:
``force`` (the total the sand exerts on the pile, N, the whole ring), ``base_force`` (contact at
faces looking down: the tip) and ``shaft_force`` (the sides); each is the mean over the interval
before its row, so it is plotted at the interval's mid-settlement.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import axmpm


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
    from axmpm.study.plotting import pyplot, save_figure

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
    print(f"figure: {figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
