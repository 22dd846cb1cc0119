"""The energy budget of a collapse run (issue 15), read from its ``history.csv``.

The engine accumulates every term on its own (``Simulation.energies``, docs/physics.md §1):
``gravity_work`` (potential energy released), ``kinetic_energy``, ``elastic_energy`` (stored,
linear elastic complementary energy of the stresses), ``plastic_work`` (Σ J σ:Δε^p V0 of the
stress returns), ``boundary_friction_dissipation`` and ``boundary_normal_dissipation`` (the
kinetic energy the faces' and walls' corrections of v⁺ remove: tangential = Coulomb friction
at the base, normal = the inelastic impact on it), and ``energy_residual`` = released − all
the others: what the scheme loses (numerical dissipation; negative = energy created).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["TERMS", "energy_history", "energy_shares", "plot_energy"]

#: Budget terms (history.csv column, label), the sinks of the released potential energy.
TERMS: tuple[tuple[str, str], ...] = (
    ("kinetic_energy", "kinetic"),
    ("elastic_energy", "stored elastic"),
    ("plastic_work", "plastic (frictional) dissipation"),
    ("boundary_friction_dissipation", "base friction dissipation"),
    ("boundary_normal_dissipation", "base impact (normal) dissipation"),
    ("energy_residual", "residual (numerical)"),
)


def energy_history(run_dir: str | Path) -> dict[str, np.ndarray]:
    """time and the budget columns of a run's history.csv (missing columns: NaN)."""
    import csv

    with open(Path(run_dir) / "history.csv", newline="") as f:
        rows = list(csv.DictReader(f))

    def col(name: str) -> np.ndarray:
        return np.array([float(r[name]) if r.get(name) not in (None, "") else np.nan for r in rows])

    out = {"time": col("time"), "gravity_work": col("gravity_work")}
    for key, _ in TERMS:
        out[key] = col(key)
    return out


def energy_shares(run_dir: str | Path) -> dict[str, Any] | None:
    """At the last history row: the released energy (J) and each term's share of it; None when
    the run has no history or no energy columns."""
    try:
        h = energy_history(run_dir)
    except (OSError, KeyError, ValueError):
        return None
    if h["time"].size == 0 or not np.isfinite(h["plastic_work"][-1]):
        return None
    released = float(h["gravity_work"][-1])
    shares = {key: (float(h[key][-1]) / released if released > 0 else None) for key, _ in TERMS}
    return {"time": float(h["time"][-1]), "released": released, "shares": shares}


def plot_energy(runs: list[tuple[str, Path]], path: Path) -> None:
    """One panel per run: each term over time as a fraction of the final released energy."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(runs), figsize=(4.6 * len(runs), 3.6), squeeze=False)
    for ax, (title, run_dir) in zip(axes[0], runs):
        h = energy_history(run_dir)
        scale = h["gravity_work"][-1] if h["gravity_work"][-1] > 0 else 1.0
        ax.plot(h["time"], h["gravity_work"] / scale, "k-", lw=1.5, label="potential released")
        for key, label in TERMS:
            ax.plot(h["time"], h[key] / scale, lw=1.1, label=label, ls=":" if key == "energy_residual" else "-")
        ax.set_xlabel("t (s)")
        ax.set_title(title, fontsize=9)
        ax.grid(True, alpha=0.3)
    axes[0][0].set_ylabel("energy / final released")
    axes[0][-1].legend(fontsize=7, loc="center right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
