"""Both rates of the saturated footing (examples/footing_saturated.toml): runs the fast push (the
file as it is) and the slow one (every time RATE_RATIO times longer), then writes the two
load–settlement curves and the excess pore pressure under the footing (one PNG), and prints and
saves (summary.json) the normalised velocity V = v B / c_v of each run and the load and excess
pore pressure at 0.05B of settlement:

    python examples/footing_saturated.py [OUT] [--fraction F] [--ratio R] [--threads N]

OUT defaults to runs/footing_saturated (runs OUT/fast and OUT/slow, figure
OUT/load_settlement.png, OUT/summary.json). ``--fraction F`` runs only the first F of each
run's time (a quick look, or a test); ``--ratio R`` slows the slow run R times instead of
RATE_RATIO (its cost grows with R).

Read from each run's history.csv: the footing's force per metre (``footing.force_y``, the half
footing beside the symmetry plane: q = F_y/(B/2)), each the mean over the interval before its row
and so plotted at the interval's mid-settlement; the probe's pore pressure
(``centre.pore_pressure``) less the hydrostatic ρ_w g (water table − probe's height).
"""

from __future__ import annotations

import argparse
import copy
import json
import sys
import tomllib
from pathlib import Path
from typing import Any

import numpy as np

import axmpm

EXAMPLE = Path(__file__).with_name("footing_saturated.toml")
#: The slow run is the fast one with every time this many times longer (V this many times smaller).
RATE_RATIO = 1000.0
#: g_n in γ_w = ρ_w g_n: the conductivity k is defined under standard gravity (docs/physics.md §10).
STANDARD_GRAVITY = 9.81
#: Settlement (over B) at which the two runs are compared, and the half-width of the window of
#: history rows averaged there (the fast run's load keeps a few per cent of ringing).
COMPARED_AT = 0.05
WINDOW = 0.01


def footing_width(data: dict[str, Any]) -> float:
    """B: twice the half footing beside the symmetry plane x = 0."""
    footing = data["rigid_bodies"][0]
    return 2.0 * (footing["max"][0] - footing["min"][0])


def consolidation_coefficient(data: dict[str, Any]) -> float:
    """c_v = k / (γ_w (1/E_oed + n/K_w)) of the saturated body (docs/physics.md §10)."""
    body = data["bodies"][0]
    water = body["saturated"]
    material = data["materials"][body["material"]]
    e, nu = material["youngs_modulus"], material["poisson_ratio"]
    oedometric = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
    k_w = water.get("water_bulk_modulus", 2.2e9)
    unit_weight = water.get("water_density", 1000.0) * STANDARD_GRAVITY
    return water["hydraulic_conductivity"] / (unit_weight * (1.0 / oedometric + water["porosity"] / k_w))


def push_velocity(data: dict[str, Any]) -> float:
    """The footing's final speed (m/s): the last row of its motion table."""
    return abs(data["rigid_bodies"][0]["motion"][-1][2])


def normalised_velocity(data: dict[str, Any]) -> float:
    """V = v B / c_v."""
    return push_velocity(data) * footing_width(data) / consolidation_coefficient(data)


def slowed(data: dict[str, Any], ratio: float) -> dict[str, Any]:
    """The scenario with every time ``ratio`` times longer and every velocity ``ratio`` times
    smaller: the same settlement history at V/ratio."""
    out = copy.deepcopy(data)
    sim = out["simulation"]
    for key in ("end_time", "output_interval", "history_interval"):
        sim[key] = sim[key] * ratio
    footing = out["rigid_bodies"][0]
    footing["motion"] = [[t * ratio, vx / ratio, vy / ratio] for t, vx, vy in footing["motion"]]
    return out


def shortened(data: dict[str, Any], fraction: float) -> dict[str, Any]:
    """The scenario run to ``fraction`` of its end time."""
    out = copy.deepcopy(data)
    out["simulation"]["end_time"] *= fraction
    return out


def curves(run_dir: Path, data: dict[str, Any]) -> dict[str, np.ndarray]:
    """Settlement s (m), footing pressure q (Pa) at the intervals' mid-settlements, and the
    probe's excess pore pressure (Pa) at the rows' settlements."""
    run = axmpm.load_run(run_dir)
    footing = run.rigid_bodies["footing"]
    settlement = -footing["displacement"][:, 1]
    mid = 0.5 * (settlement[1:] + settlement[:-1])
    pressure = footing["force"][1:, 1] / (0.5 * footing_width(data))
    probe = data["probes"][0]
    water = data["bodies"][0]["saturated"]
    hydrostatic = water.get("water_density", 1000.0) * abs(data["simulation"]["gravity"][1]) * (
        water["water_table"] - probe["point"][1])
    excess = run.history[f"{probe['name']}.pore_pressure"] - hydrostatic
    return {"settlement": settlement, "mid_settlement": mid, "pressure": pressure, "excess": excess}


def near(values: np.ndarray, at: np.ndarray, centre: float, half_width: float) -> float | None:
    """The mean of ``values`` over the rows whose ``at`` lies within ``half_width`` of ``centre``."""
    rows = np.abs(at - centre) <= half_width
    return float(np.mean(values[rows])) if rows.any() else None


def compare(fast: dict[str, np.ndarray], slow: dict[str, np.ndarray], width: float) -> dict[str, Any]:
    """Load and excess pore pressure of each run at COMPARED_AT × B (mean over ±WINDOW × B) and at
    the end of the runs."""
    out: dict[str, Any] = {}
    for name, c in (("fast", fast), ("slow", slow)):
        s, b = COMPARED_AT * width, WINDOW * width
        out[name] = {
            "pressure_at": near(c["pressure"], c["mid_settlement"], s, b),
            "excess_at": near(c["excess"], c["settlement"], s, b),
            "final_settlement": float(c["settlement"][-1]),
            "final_pressure": float(c["pressure"][-1]),
            "final_excess": float(c["excess"][-1]),
            "peak_excess": float(np.max(c["excess"])),
        }
    return out


def plot(fast: dict[str, np.ndarray], slow: dict[str, np.ndarray], labels: dict[str, str], width: float,
         figure: Path) -> None:
    from axmpm.plotting import pyplot, save_figure

    plt = pyplot()
    fig, (load, pore) = plt.subplots(1, 2, figsize=(10, 4.2))
    for name, c, colour in (("fast", fast, "tab:red"), ("slow", slow, "tab:blue")):
        load.plot(c["mid_settlement"] / width, c["pressure"] / 1e3, color=colour, label=labels[name])
        pore.plot(c["settlement"] / width, c["excess"] / 1e3, color=colour, label=labels[name])
    load.set_xlabel("settlement / B")
    load.set_ylabel("footing pressure q (kPa)")
    pore.set_xlabel("settlement / B")
    pore.set_ylabel("excess pore pressure at B/2 under the centre (kPa)")
    for ax in (load, pore):
        ax.axvline(COMPARED_AT, color="grey", lw=0.8, ls=":")
        ax.grid(alpha=0.3)
        ax.legend()
    save_figure(fig, figure)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="runs/footing_saturated")
    parser.add_argument("--fraction", type=float, default=1.0, help="run only this fraction of each run's time")
    parser.add_argument("--ratio", type=float, default=RATE_RATIO, help="how many times slower the slow run is")
    parser.add_argument("--threads", type=int, default=0)
    args = parser.parse_args(argv[1:])
    if not 0.0 < args.fraction <= 1.0:
        print(f"error: --fraction must be in (0, 1] (got {args.fraction})", file=sys.stderr)
        return 2
    if not args.ratio > 1.0:
        print(f"error: --ratio must be > 1 (got {args.ratio})", file=sys.stderr)
        return 2
    out = Path(args.out)
    base = tomllib.loads(EXAMPLE.read_text())
    scenarios = {"fast": base, "slow": slowed(base, args.ratio)}
    results, labels = {}, {}
    for name, data in scenarios.items():
        run_dir = out / name
        axmpm.run(shortened(data, args.fraction), run_dir, threads=args.threads, overwrite=True)
        results[name] = curves(run_dir, data)
        labels[name] = f"{name}: v = {push_velocity(data):.3g} m/s, V = {normalised_velocity(data):.3g}"
    width = footing_width(base)
    figure = out / "load_settlement.png"
    plot(results["fast"], results["slow"], labels, width, figure)
    summary = compare(results["fast"], results["slow"], width)
    for name, data in scenarios.items():
        summary[name].update(velocity=push_velocity(data), normalised_velocity=normalised_velocity(data))
    summary["consolidation_coefficient"] = consolidation_coefficient(base)
    summary["compared_at"] = COMPARED_AT
    (out / "summary.json").write_text(json.dumps(summary, indent=2))
    kpa = lambda x: "  (not reached)" if x is None else f"{x / 1e3:8.1f}"  # noqa: E731
    print(f"c_v = {summary['consolidation_coefficient']:.4g} m²/s, B = {width:g} m")
    for name in ("fast", "slow"):
        r = summary[name]
        print(f"{name}: v = {r['velocity']:.3g} m/s, V = {r['normalised_velocity']:.3g}; at s = {COMPARED_AT}B: "
              f"q {kpa(r['pressure_at'])} kPa, excess pore pressure {kpa(r['excess_at'])} kPa; "
              f"peak excess {r['peak_excess'] / 1e3:.1f} kPa")
    print(f"figure: {figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
