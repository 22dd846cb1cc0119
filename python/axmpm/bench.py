"""``axmpm bench``: engine throughput in particle-steps per second.

The benchmark is fixed so that figures are comparable between machines and commits: the
column-collapse geometry (a Mohr–Coulomb cylinder released from its wall on a rough base)
scaled up to at least 200,000 particles, run for every interpolation scheme in both
formulations, with one thread and with all cores. Each measurement takes ``warmup`` steps
first (not timed), then times ``steps`` steps inside the engine, and reports the time split
between the phases of the step as the engine measures them. ``--material linear_elastic``
swaps the Mohr–Coulomb sand for linear elasticity with the same density and stiffness (the
case ``benches/peer_taichi.py`` reproduces in Taichi).
"""

from __future__ import annotations

import argparse
import json
import platform
import time
from typing import Any

from .catalogue import formulations as engine_formulations, interpolation_schemes
from .engine import core
from .errors import RunError
from .run.parallel import available_cores
from .scenario import Scenario

NAME = "bench"

#: The bench materials: the Mohr–Coulomb sand, or the same density and stiffness without
#: plasticity (the case of the peer benchmark, benches/peer_taichi.py).
MATERIALS = ("mohr_coulomb", "linear_elastic")



def schemes() -> tuple[str, ...]:
    """Every interpolation scheme of the engine (axmpm.catalogue)."""
    return interpolation_schemes()


def formulations() -> tuple[str, ...]:
    """Every formulation of the engine, axisymmetric first."""
    return tuple(sorted(engine_formulations()))


def bench_scenario(formulation: str, scheme: str, cell_size: float = 0.0005,
                   material: str = "mohr_coulomb") -> dict[str, Any]:
    """Column collapse scaled up: radius 0.1 m, height 0.125 m, 2×2 particles per cell.

    With the default 0.5 mm cells this is 200 × 250 cells × 4 = 200,000 particles on a
    0.4 m × 0.15 m grid (241,101 nodes). The confining wall at r = R is removed at t = 0,
    so the measured steps are the start of a real collapse (plastic flow at the toe).
    With ``material="linear_elastic"`` the column is elastic (E = 1 MPa, ν = 0.3, 1550 kg/m³).
    """
    radius, height = 0.1, 0.125
    sand: dict[str, Any] = {"model": material, "density": 1550.0, "youngs_modulus": 1.0e6, "poisson_ratio": 0.3}
    if material == "mohr_coulomb":
        sand.update({"friction_angle": 25.0, "dilation_angle": 0.0})
    return {
        "simulation": {
            "formulation": formulation,
            "shape_function": scheme,
            "end_time": 1.0,
            "output_interval": 1.0,
            "gravity": [0.0, -9.81],
            "cfl": 0.4,
            "update_scheme": "musl",
            "flip_fraction": 0.99,
        },
        "grid": {"origin": [0.0, 0.0], "extent": [0.4, 0.15], "cell_size": cell_size},
        "materials": {"sand": sand},
        "bodies": [
            {
                "material": "sand",
                "min": [0.0, 0.0],
                "max": [radius, height],
                "particles_per_cell": 2,
                "initial_stress": "geostatic",
            }
        ],
        "boundaries": {
            "left": "roller",
            "bottom": {"condition": "friction", "coefficient": 0.466},
        },
    }


def measure(formulation: str, scheme: str, threads: int, steps: int, warmup: int,
            cell_size: float = 0.0005, material: str = "mohr_coulomb") -> dict[str, Any]:
    """One measurement: build, take ``warmup`` steps, time ``steps`` steps."""
    scenario = Scenario.from_dict(bench_scenario(formulation, scheme, cell_size, material))
    sim = core().Simulation(scenario.engine_json(), threads)
    sim.advance(1e9, warmup)
    before = sim.timings()
    start = time.perf_counter()
    taken = sim.advance(1e9, steps)
    seconds = time.perf_counter() - start
    after = sim.timings()
    split = {k: after[k] - before[k] for k in after}
    n = int(sim.num_particles)
    return {
        "scheme": scheme,
        "formulation": formulation,
        "material": material,
        "threads": int(sim.threads),
        "particles": n,
        "nodes": int(sim.num_nodes),
        "steps": int(taken),
        "seconds": seconds,
        "particle_steps_per_second": taken * n / seconds,
        "bytes_per_particle": int(sim.bytes_per_particle),
        "time_split": {k: v / seconds for k, v in split.items()},
    }


def machine() -> dict[str, Any]:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass

    return {"cpu": cpu, "cores": available_cores(), "python": platform.python_version(),
            "system": platform.system()}


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(NAME, help="measure engine throughput (particle-steps per second)")
    p.add_argument("--threads", type=int, action="append", default=None,
                   help="thread count to measure (repeatable; default: 1 and all cores)")
    p.add_argument("--schemes", default=None, help="comma-separated schemes (default: all)")
    p.add_argument("--formulations", default=None, help="comma-separated formulations (default: both)")
    p.add_argument("--steps", type=int, default=100, help="timed steps per measurement (default 100)")
    p.add_argument("--warmup", type=int, default=10, help="untimed steps first (default 10)")
    p.add_argument("--cell-size", type=float, default=0.0005,
                   help="m; the default 0.5 mm gives 200,000 particles")
    p.add_argument("--material", choices=MATERIALS, default="mohr_coulomb",
                   help="the column's material (default mohr_coulomb; linear_elastic: same density and "
                        "stiffness, the case of benches/peer_taichi.py)")
    p.add_argument("--json", action="store_true", help='print {"results": [...]} as JSON')


def _validated_list(text: str, allowed: tuple[str, ...], name: str) -> list[str]:
    items = [t.strip() for t in text.split(",") if t.strip()]
    bad = [t for t in items if t not in allowed]
    if bad or not items:
        raise RunError(f"--{name}: {', '.join(bad) or '(empty)'} not in {', '.join(allowed)}")
    return items


def main(args: argparse.Namespace) -> int:
    all_schemes, all_formulations = schemes(), formulations()
    chosen_schemes = _validated_list(args.schemes or ",".join(all_schemes), all_schemes, "schemes")
    chosen_formulations = _validated_list(args.formulations or ",".join(all_formulations), all_formulations,
                                          "formulations")

    cores = available_cores()
    threads = args.threads or sorted({1, cores})
    if any(t < 1 for t in threads):
        raise RunError("--threads must be >= 1")
    if args.steps < 1 or args.warmup < 0 or not args.cell_size > 0:
        raise RunError("--steps must be >= 1, --warmup >= 0 and --cell-size > 0")
    results = []
    for formulation in chosen_formulations:
        for scheme in chosen_schemes:
            for t in threads:
                r = measure(formulation, scheme, t, args.steps, args.warmup, args.cell_size, args.material)
                results.append(r)
                if not args.json:
                    split = ", ".join(f"{k.replace('_', ' ')} {100 * v:.0f}%" for k, v in r["time_split"].items())
                    print(f"{formulation:13s} {scheme:7s} threads={r['threads']} particles={r['particles']} "
                          f"{r['particle_steps_per_second'] / 1e6:6.2f} M particle-steps/s "
                          f"{r['bytes_per_particle']} B/particle  ({split})", flush=True)
    if args.json:
        print(json.dumps({"machine": machine(), "results": results}, indent=2))
    return 0
