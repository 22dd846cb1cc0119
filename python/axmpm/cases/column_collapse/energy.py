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

__all__ = ["TERMS", "energy_history", "energy_shares", "kinetic_energy_split", "sideways_energy", "plot_energy"]

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


def kinetic_energy_split(frames: Any, gravity: Any) -> dict[str, np.ndarray]:
    """Per output frame: time, the kinetic energy of the sideways (radial, or horizontal in
    plane strain) motion ½ Σ m v_r², that of the vertical motion ½ Σ m v_z², and the potential
    energy released so far Σ m g·(x − X0) (``gravity`` the vector, m/s²), all from the particles (the frames' masses: per
    radian in axisymmetry, per metre in plane strain; only ratios are used).

    Staron & Hinch (2005, JFM 545) explain the runout's power law by the share of the released
    energy that goes into the sideways flow (the column falls, its base turns part of the fall
    into spreading); this split measures that share in a run."""
    g = np.asarray(gravity, dtype=float)
    rows = []
    for f in frames:
        m, v = f.mass, f.v
        rows.append((float(f.time), 0.5 * float((m * v[:, 0] ** 2).sum()), 0.5 * float((m * v[:, 1] ** 2).sum()),
                     float((m * ((f.x - f.X0) @ g)).sum())))
    t, sideways, vertical, released = (np.array(c, dtype=float) for c in zip(*rows)) if rows else [np.zeros(0)] * 4
    return {"time": t, "sideways": sideways, "vertical": vertical, "released": released}


def sideways_energy(run_dir: str | Path) -> dict[str, Any] | None:
    """The peak kinetic energy of the sideways and of the vertical motion as shares of the
    potential energy released by the end of the run (:func:`kinetic_energy_split` over the
    run's frames), and the time of the sideways peak; None without frames or released energy."""
    from ...run.output import load_run

    run = load_run(run_dir)
    if not run.frames:
        return None
    split = kinetic_energy_split(run.frames, run.scenario.simulation.gravity)
    released = split["released"][-1]
    if not released > 0.0:
        return None
    peak = int(np.argmax(split["sideways"]))
    return {"peak_sideways_share": float(split["sideways"][peak] / released),
            "peak_sideways_time": float(split["time"][peak]),
            "released_share_at_peak": float(split["released"][peak] / released),
            "peak_vertical_share": float(split["vertical"].max() / released)}


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
