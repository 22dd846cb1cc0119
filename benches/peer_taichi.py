"""Peer benchmark: the step of ``axmpm bench --material linear_elastic`` written in Taichi.

Same particles (taken from the axmpm simulation: positions, masses, volumes, geostatic
stresses), same grid, same time step and the same step: MUSL with bilinear ("linear") shape
functions, FLIP 0.99, hypoelastic linear elasticity with the Jaumann rate, a roller on the left
face and Coulomb friction (0.466) on the bottom, plane strain, double precision. The two engines
run one after the other, one thread each, repeated; the script prints particle-steps per second
of each and their ratio. Not a dependency of axmpm: install Taichi with the ``bench`` extra
(``pip install -e '.[bench]'``), then

    python benches/peer_taichi.py [--cell-size 0.001] [--steps 200] [--warmup 10] [--repeats 3]

Taichi scatters with atomic adds (its own parallel model); with one thread that is a plain add.

Instructions per particle-step of each engine, free of the machine's load (needs valgrind):

    python benches/peer_taichi.py --count-instructions [--steps 50]

runs each engine alone (``--only``) under ``valgrind --tool=callgrind`` twice, for 10 and for
10 + ``--steps`` steps, and divides the difference of the two instruction counts by the extra
particle-steps: start-up, Taichi's compilation and the warm-up cancel out.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

# --check: largest position difference (m) and stress difference (of the largest stress) that
# count as round-off between the two implementations of the same step.
CHECK_POSITION_TOLERANCE = 1e-12
CHECK_STRESS_TOLERANCE = 1e-10


def axmpm_case(cell_size: float):
    """The axmpm simulation of the bench case (plane strain, linear, linear elastic)."""
    from axmpm import _core
    from axmpm.bench import bench_scenario
    from axmpm.scenario import Scenario

    scenario = Scenario.from_dict(bench_scenario("plane_strain", "linear", cell_size, "linear_elastic"))
    return scenario, _core.Simulation(scenario.engine_json(), 1)


def measure_axmpm(cell_size: float, steps: int, warmup: int) -> float:
    from axmpm.bench import measure

    r = measure("plane_strain", "linear", 1, steps, warmup, cell_size, "linear_elastic")
    return r["particle_steps_per_second"]


class TaichiMPM:
    """The same MUSL step in Taichi, on the particles of an axmpm simulation."""

    def __init__(self, sim, scenario_dict: dict) -> None:
        import taichi as ti

        ti.init(arch=ti.cpu, cpu_max_num_threads=1, default_fp=ti.f64, offline_cache=True)
        self.ti = ti
        grid = scenario_dict["grid"]
        material = scenario_dict["materials"]["sand"]
        sim_cfg = scenario_dict["simulation"]
        h = float(grid["cell_size"])
        nx, ny = sim.grid_shape
        n = int(sim.num_particles)
        e, nu, rho = material["youngs_modulus"], material["poisson_ratio"], material["density"]
        lam = e * nu / ((1 + nu) * (1 - 2 * nu))
        mu = e / (2 * (1 + nu))
        dt = float(sim.dt)
        flip = float(sim_cfg["flip_fraction"])
        gravity = tuple(float(g) for g in sim_cfg["gravity"])
        friction = 0.466
        self.n = n

        f64 = ti.f64
        x = ti.Vector.field(2, f64, n)
        v = ti.Vector.field(2, f64, n)
        dx = ti.Vector.field(2, f64, n)
        mass = ti.field(f64, n)
        vol0 = ti.field(f64, n)
        vol = ti.field(f64, n)
        defgrad = ti.Matrix.field(2, 2, f64, n)
        stress = ti.Vector.field(4, f64, n)  # xx, yy, zz, xy
        gm = ti.field(f64, (nx, ny))
        gp = ti.Vector.field(2, f64, (nx, ny))
        gf = ti.Vector.field(2, f64, (nx, ny))
        gv = ti.Vector.field(2, f64, (nx, ny))
        gv_new = ti.Vector.field(2, f64, (nx, ny))
        # Bottom nodes pressed into the base in v⁺: they keep zero normal velocity in the
        # re-map (axmpm's contact state of the step, docs/physics.md §8).
        held = ti.field(ti.i32, nx)

        x.from_numpy(np.asarray(sim.positions()))
        v.from_numpy(np.asarray(sim.velocities()))
        mass.from_numpy(np.asarray(sim.masses()))
        vol0.from_numpy(np.asarray(sim.volumes()))
        vol.from_numpy(np.asarray(sim.volumes()))
        stress.from_numpy(np.asarray(sim.stresses()))
        defgrad.from_numpy(np.tile(np.eye(2), (n, 1, 1)))
        ih = 1.0 / h
        # One thread: serial particle loops let Taichi demote its atomic adds to plain adds
        # (the fastest it scatters on one core).
        SERIAL = True
        origin = tuple(float(o) for o in grid["origin"])

        @ti.func
        def constrain(vel, i, j):
            # Left face: roller; bottom face: Coulomb friction (normal stop, tangential reduced).
            out = vel
            if i == 0:
                out[0] = 0.0
            if j == 0 and out[1] < 0.0:
                dvn = -out[1]
                out[1] = 0.0
                t = out[0]
                out[0] = ti.math.sign(t) * ti.max(ti.abs(t) - friction * dvn, 0.0)
            return out

        @ti.func
        def cell_of(xp):
            l = (xp - ti.Vector(origin)) * ih
            c = ti.floor(l, ti.i32)
            return c, l - c

        @ti.kernel
        def p2g():
            for i, j in gm:
                gm[i, j] = 0.0
                gp[i, j] = ti.Vector([0.0, 0.0])
                gf[i, j] = ti.Vector([0.0, 0.0])
            ti.loop_config(serialize=SERIAL)
            for p in range(n):
                c, fr = cell_of(x[p])
                s = stress[p]
                for a, b in ti.static(ti.ndrange(2, 2)):
                    wx = fr[0] if a == 1 else 1.0 - fr[0]
                    wy = fr[1] if b == 1 else 1.0 - fr[1]
                    w = wx * wy
                    gx = (ih if a == 1 else -ih) * wy
                    gy = wx * (ih if b == 1 else -ih)
                    node = (c[0] + a, c[1] + b)
                    gm[node] += w * mass[p]
                    gp[node] += w * mass[p] * v[p]
                    gf[node] += -vol[p] * ti.Vector([s[0] * gx + s[3] * gy, s[3] * gx + s[1] * gy]) \
                        + w * mass[p] * ti.Vector(gravity)

        @ti.kernel
        def grid_update():
            for i, j in gm:
                m = gm[i, j]
                if m > 0.0:
                    v0 = gp[i, j] / m
                    gv[i, j] = constrain(v0, i, j)
                    trial = v0 + dt * gf[i, j] / m
                    if j == 0:
                        held[i] = 1 if trial[1] < 0.0 else 0
                    gv_new[i, j] = constrain(trial, i, j)
                else:
                    gv[i, j] = ti.Vector([0.0, 0.0])
                    gv_new[i, j] = ti.Vector([0.0, 0.0])

        @ti.kernel
        def g2p_and_remap():
            for i, j in gm:
                gp[i, j] = ti.Vector([0.0, 0.0])
            ti.loop_config(serialize=SERIAL)
            for p in range(n):
                c, fr = cell_of(x[p])
                vg = ti.Vector([0.0, 0.0])
                dv = ti.Vector([0.0, 0.0])
                for a, b in ti.static(ti.ndrange(2, 2)):
                    w = (fr[0] if a == 1 else 1.0 - fr[0]) * (fr[1] if b == 1 else 1.0 - fr[1])
                    node = (c[0] + a, c[1] + b)
                    vg += w * gv_new[node]
                    dv += w * (gv_new[node] - gv[node])
                vn = flip * (v[p] + dv) + (1.0 - flip) * vg
                v[p] = vn
                dx[p] = dt * vg
                for a, b in ti.static(ti.ndrange(2, 2)):
                    w = (fr[0] if a == 1 else 1.0 - fr[0]) * (fr[1] if b == 1 else 1.0 - fr[1])
                    gp[c[0] + a, c[1] + b] += w * mass[p] * vn

        @ti.kernel
        def remap_velocity():
            for i, j in gm:
                m = gm[i, j]
                out = ti.Vector([0.0, 0.0])
                if m > 0.0:
                    out = constrain(gp[i, j] / m, i, j)
                    if j == 0 and held[i] == 1:
                        out[1] = 0.0
                gv[i, j] = out

        @ti.kernel
        def update_particles():
            ti.loop_config(serialize=SERIAL)
            for p in range(n):
                c, fr = cell_of(x[p])
                vel_grad = ti.Matrix.zero(f64, 2, 2)
                for a, b in ti.static(ti.ndrange(2, 2)):
                    wx = fr[0] if a == 1 else 1.0 - fr[0]
                    wy = fr[1] if b == 1 else 1.0 - fr[1]
                    g = ti.Vector([(ih if a == 1 else -ih) * wy, wx * (ih if b == 1 else -ih)])
                    vel_grad += gv[c[0] + a, c[1] + b].outer_product(g)
                defgrad[p] = (ti.Matrix.identity(f64, 2) + dt * vel_grad) @ defgrad[p]
                vol[p] = vol0[p] * defgrad[p].determinant()
                d = 0.5 * (vel_grad + vel_grad.transpose())
                w12 = 0.5 * (vel_grad[0, 1] - vel_grad[1, 0])
                s = stress[p]
                tr = (d[0, 0] + d[1, 1]) * dt
                # Jaumann rotation W σ − σ W of the in-plane stress (W = [[0, w12], [−w12, 0]]).
                rot_xx = 2.0 * w12 * s[3] * dt
                rot_xy = w12 * (s[1] - s[0]) * dt
                stress[p] = ti.Vector([
                    s[0] + lam * tr + 2.0 * mu * d[0, 0] * dt + rot_xx,
                    s[1] + lam * tr + 2.0 * mu * d[1, 1] * dt - rot_xx,
                    s[2] + lam * tr,
                    s[3] + 2.0 * mu * d[0, 1] * dt + rot_xy,
                ])
                x[p] += dx[p]

        self.kernels = (p2g, grid_update, g2p_and_remap, remap_velocity, update_particles)
        self.positions, self.stresses = x, stress

    def step(self) -> None:
        for k in self.kernels:
            k()

    def run(self, steps: int) -> float:
        """Seconds for `steps` steps."""
        self.ti.sync()
        start = time.perf_counter()
        for _ in range(steps):
            self.step()
        self.ti.sync()
        return time.perf_counter() - start


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--cell-size", type=float, default=0.001, help="m (default 1 mm: 50,000 particles)")
    p.add_argument("--steps", type=int, default=None,
                   help="timed steps (default 200; with --count-instructions the extra steps, default 50)")
    p.add_argument("--warmup", type=int, default=10)
    p.add_argument("--repeats", type=int, default=9,
                   help="alternated runs of each engine (default 9: the ratio of one pair varies by "
                        "±20 %% on a shared VM, so the summary gives the median, the mean with its "
                        "standard error, and the ratio of each engine's best run)")
    p.add_argument("--check", action="store_true",
                   help="first compare the two engines' displacements and stresses after --steps steps")
    p.add_argument("--only", choices=("axmpm", "taichi"),
                   help="run this engine alone (after the warm-up) and print its particle-steps per second")
    p.add_argument("--count-instructions", action="store_true",
                   help="instructions per particle-step of each engine, with callgrind (see above)")
    args = p.parse_args()
    if args.count_instructions:
        return count_instructions(args.cell_size, 50 if args.steps is None else args.steps)
    if args.steps is None:
        args.steps = 200
    if args.only == "axmpm":
        # `measure_axmpm` builds its own simulation: nothing below is needed.
        print(f"axmpm {measure_axmpm(args.cell_size, args.steps, args.warmup):.6e} particle-steps/s")
        return 0

    from axmpm.bench import bench_scenario

    scenario_dict = bench_scenario("plane_strain", "linear", args.cell_size, "linear_elastic")
    scenario, sim = axmpm_case(args.cell_size)
    # The resolved scenario (defaults filled in), for the parameters the Taichi step needs.
    import json

    resolved = json.loads(scenario.engine_json())
    resolved["materials"] = scenario_dict["materials"]
    peer = TaichiMPM(sim, resolved)
    n = peer.n
    if args.only == "taichi":
        peer.run(args.warmup)
        print(f"Taichi {args.steps * n / peer.run(args.steps):.6e} particle-steps/s")
        return 0
    if args.check:
        # Same step, same particles: the two results agree to the order of round-off growth.
        x0 = np.asarray(sim.positions()).copy()
        peer.run(args.steps)
        sim.advance(1e9, args.steps)
        moved = np.abs(np.asarray(sim.positions()) - x0).max()
        dx = np.abs(peer.positions.to_numpy() - np.asarray(sim.positions())).max()
        ds = np.abs(peer.stresses.to_numpy() - np.asarray(sim.stresses())).max()
        scale = np.abs(np.asarray(sim.stresses())).max()
        print(f"check after {args.steps} steps: largest displacement {moved:.3e} m, largest position "
              f"difference {dx:.3e} m, largest stress difference {ds / scale:.2e} of the largest stress")
        # Round-off differences stay near 1e-17 m and 1e-15 of the stress after 300 steps; a
        # difference in the step itself (a changed boundary rule, say) shows as 1e-8 m and 1e-2
        # within 50 steps. The timing below means nothing unless the two steps agree.
        if not same_step(dx, ds, scale):
            print(f"check failed: the two engines do not run the same step (tolerances "
                  f"{CHECK_POSITION_TOLERANCE:g} m, {CHECK_STRESS_TOLERANCE:g} of the largest stress)")
            return 1
        scenario, sim = axmpm_case(args.cell_size)
        peer = TaichiMPM(sim, resolved)
    peer.run(args.warmup)  # compiles the kernels
    import taichi as ti

    print(f"plane strain, linear shape functions, linear elastic, MUSL, FLIP 0.99, f64, 1 thread, "
          f"{n} particles, {args.steps} steps (Taichi {ti.__version__})")
    ours_runs, theirs_runs = [], []
    for r in range(args.repeats):
        ours = measure_axmpm(args.cell_size, args.steps, args.warmup)
        theirs = args.steps * n / peer.run(args.steps)
        ours_runs.append(ours)
        theirs_runs.append(theirs)
        print(f"run {r + 1}: axmpm {ours / 1e6:6.2f} M particle-steps/s, Taichi {theirs / 1e6:6.2f} M "
              f"particle-steps/s, ratio axmpm/Taichi {ours / theirs:.2f}", flush=True)
    print(summary(ours_runs, theirs_runs))
    return 0


def same_step(position_difference: float, stress_difference: float, stress_scale: float) -> bool:
    """Whether `--check`'s largest differences (m; Pa against the largest stress, Pa) are
    round-off of one step rather than two different steps (NaN counts as different)."""
    return (position_difference <= CHECK_POSITION_TOLERANCE
            and stress_difference <= CHECK_STRESS_TOLERANCE * stress_scale)


def collected_instructions(valgrind_output: str) -> int:
    """The instruction count callgrind reports (``==pid== Collected : N``)."""
    import re

    counts = re.findall(r"Collected\s*:\s*([0-9,]+)", valgrind_output)
    if not counts:
        raise ValueError("no 'Collected :' line in the valgrind output")
    return int(counts[-1].replace(",", ""))


def per_particle_step(short: int, long: int, extra_steps: int, particles: int) -> float:
    """Instructions per particle-step from two counts of the same run that differ by
    `extra_steps` steps of `particles` particles (everything else cancels)."""
    if extra_steps <= 0 or particles <= 0:
        raise ValueError("extra_steps and particles must be positive")
    return (long - short) / (extra_steps * particles)


def count_instructions(cell_size: float, steps: int) -> int:
    """Each engine alone under callgrind, for 10 and 10 + `steps` steps (see the module doc)."""
    import shutil
    import subprocess
    import sys

    if shutil.which("valgrind") is None:
        print("--count-instructions needs valgrind on the PATH", file=sys.stderr)
        return 2
    _, sim = axmpm_case(cell_size)
    n = int(sim.num_particles)
    base = 10
    result = {}
    for engine in ("axmpm", "taichi"):
        counts = []
        for s in (base, base + steps):
            command = ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", sys.executable,
                       __file__, "--only", engine, "--steps", str(s), "--warmup", "2",
                       "--cell-size", str(cell_size)]
            run = subprocess.run(command, capture_output=True, text=True)
            if run.returncode != 0:
                print(run.stderr[-2000:], file=sys.stderr)
                return 1
            counts.append(collected_instructions(run.stderr))
        result[engine] = per_particle_step(counts[0], counts[1], steps, n)
        print(f"{engine}: {result[engine]:.1f} instructions per particle-step "
              f"({counts[0]:,} at {base} steps, {counts[1]:,} at {base + steps}; {n} particles)", flush=True)
    print(f"instructions Taichi/axmpm: {result['taichi'] / result['axmpm']:.2f}")
    return 0


def summary(ours: list[float], theirs: list[float]) -> str:
    """The ratio axmpm/Taichi over alternated runs: its range and median, its mean with the
    standard error of the mean (the spread of single pairs on a shared machine, ÷ √n), and
    the ratio of each engine's fastest run (the run least disturbed by other load)."""
    import statistics

    ratios = [a / b for a, b in zip(ours, theirs)]
    text = (f"ratio axmpm/Taichi: {min(ratios):.2f}–{max(ratios):.2f} "
            f"(median {statistics.median(ratios):.2f}")
    if len(ratios) > 1:
        error = statistics.stdev(ratios) / math.sqrt(len(ratios))
        text += f", mean {statistics.fmean(ratios):.2f} ± {error:.2f}"
    return text + f", best against best {max(ours) / max(theirs):.2f}; pairs: {len(ratios)})"


if __name__ == "__main__":
    raise SystemExit(main())
