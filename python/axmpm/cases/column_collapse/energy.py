"""The energy budget of a collapse run, read from its ``history.csv``.

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

from ...run.output import Run, load_run

__all__ = ["TERMS", "energy_history", "energy_shares", "kinetic_energy_split", "sideways_energy", "lode_parameter",
           "plastic_work_by_lode", "lode_work_shares", "plot_energy"]

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


def _as_run(run: Any) -> Any:
    """A run folder's :class:`~axmpm.run.output.Run`; a Run is passed through, so callers
    that read several frame diagnostics load (and cache) the frames once."""
    return run if isinstance(run, Run) else load_run(run)


def sideways_energy(run: Any) -> dict[str, Any] | None:
    """The peak kinetic energy of the sideways and of the vertical motion as shares of the
    potential energy released by the end of the run (:func:`kinetic_energy_split` over the
    run's frames), and the time of the sideways peak; None without frames or released energy.
    ``run``: a run folder or its loaded Run."""
    run = _as_run(run)
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


def lode_parameter(stress: Any) -> np.ndarray:
    """ξ = (3√3/2) J₃ / J₂^{3/2} of each stress row ``[σ11, σ22, σ33, σ12]`` (σ33 the hoop or
    out-of-plane stress; tension positive), the cosine of three times the Lode angle:
    ξ = −1 in triaxial compression (one principal stress more compressive than the two
    others, which are equal: the state of a compressed cylinder), 0 in pure shear
    (plane-strain-like: the middle principal stress is the mean of the others), +1 in
    triaxial extension. NaN where the deviator is zero (stress-free, or isotropic)."""
    s = np.asarray(stress, dtype=float)
    p = (s[:, 0] + s[:, 1] + s[:, 2]) / 3.0
    d11, d22, d33, d12 = s[:, 0] - p, s[:, 1] - p, s[:, 2] - p, s[:, 3]
    j2 = 0.5 * (d11**2 + d22**2 + d33**2) + d12**2
    j3 = d33 * (d11 * d22 - d12**2)  # det of the deviator (σ33 is a principal stress)
    with np.errstate(invalid="ignore", divide="ignore"):
        xi = 1.5 * np.sqrt(3.0) * j3 / j2**1.5
    xi[~(j2 > 1e-24 * np.maximum(p * p, 1e-300))] = np.nan
    return np.clip(xi, -1.0, 1.0)


#: Lode-parameter bins of :func:`plastic_work_by_lode`: (key, test on ξ).
LODE_BINS: tuple[tuple[str, Any], ...] = (
    ("compression", lambda xi: xi < -0.5),
    ("shear", lambda xi: np.abs(xi) <= 0.5),
    ("extension", lambda xi: xi > 0.5),
    ("stress_free", np.isnan),
)


def plastic_work_by_lode(frames: Any) -> dict[str, Any] | None:
    """How the plastic work of a run splits over the Lode parameter (:func:`lode_parameter`).

    The work each particle dissipates between two output frames (the increase of its
    ``plastic_work`` state, J per reference volume, times V0) is booked at the particle's
    Lode parameter at the later frame: near triaxial compression (ξ < −½), near shear
    (|ξ| ≤ ½), near triaxial extension (ξ > ½), or stress-free at that frame. A pressure-
    dependent yield cone calibrated in shear (Drucker–Prager with √J₂ = μ p) and a Mohr–Coulomb
    pyramid with the same shear strength (sin φ = μ) differ most in triaxial compression, where
    Mohr–Coulomb is stronger (q/p = 6 sin φ / (3 − sin φ) against √3 μ), so the compression
    share says how much the choice of cone can matter for a run. The measure reads the
    returned stress: Drucker–Prager's radial return keeps the Lode parameter of the trial
    stress (the loading's), while Mohr–Coulomb returns that end on an edge of the pyramid land
    on ξ = ±1 exactly, so for Mohr–Coulomb runs the shares say where the returns end, not how
    the material is loaded. None without a ``plastic_work`` state or without plastic work."""
    total = 0.0
    weighted_xi = 0.0
    sums = {key: 0.0 for key, _ in LODE_BINS}
    previous = None
    for f in frames:
        names = list(getattr(f, "state_names", None) or [])
        if "plastic_work" not in names:
            return None
        work = f.state[:, names.index("plastic_work")] * f.volume0
        increment = np.clip(work - (0.0 if previous is None else previous), 0.0, None)
        previous = work
        xi = lode_parameter(f.stress)
        for key, test in LODE_BINS:
            sums[key] += float(increment[test(xi)].sum())
        total += float(increment.sum())
        defined = ~np.isnan(xi)
        weighted_xi += float((increment[defined] * xi[defined]).sum())
    if not total > 0.0:
        return None
    with_stress = total - sums["stress_free"]
    return {"plastic_work": total, "shares": {key: v / total for key, v in sums.items()},
            "mean_lode_parameter": weighted_xi / with_stress if with_stress > 0.0 else None}


def lode_work_shares(run: Any) -> dict[str, Any] | None:
    """:func:`plastic_work_by_lode` over a run's output frames (None without frames);
    ``run``: a run folder or its loaded Run."""
    run = _as_run(run)
    return plastic_work_by_lode(run.frames) if run.frames else None


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
