"""Granular column collapse: the scenario builder (docs/physics.md §6, docs/validation.md).

A cylinder of sand of radius R_i and height H_i = a R_i stands on a rough base inside a rigid
cylinder wall; the wall is removed and the column collapses (:func:`collapse_scenario`).
"""

from __future__ import annotations

import math
from typing import Any

from .deposit import GRAIN_DIAMETER

__all__ = ["collapse_scenario", "DEFAULTS"]

#: Default parameters of the collapse scenarios (docs/validation.md explains each).
DEFAULTS: dict[str, Any] = {
    "radius": 0.03,  # m, R_i; the experiments' own radius is unconfirmed (validation-sources §2)
    "cell_size": 0.002,  # m, as in the seed paper
    "particles_per_cell": 2,  # per direction, as in the seed paper
    "density": 1550.0,  # kg/m³, glass-bead bulk density ≈ 1500–1600 (docs/physics.md §6)
    "youngs_modulus": 1.0e6,  # Pa
    "poisson_ratio": 0.3,
    "friction_angle": 25.0,  # degrees
    "dilation_angle": 0.0,  # degrees, as in the seed paper
    "cohesion": 0.0,
    # Disconnected state (experimental; mohr_coulomb.rs, drucker_prager.rs, Dunatunga & Kamrin
    # 2015): None = off; φ_c makes sand looser than φ_c (J > density/(grain_density φ_c))
    # stress-free.
    "critical_packing_fraction": None,
    "inertial_number_scale": 0.279,  # I₀ of μ(I) (Jop, Forterre & Pouliquen 2006, glass beads)
    "grain_diameter": GRAIN_DIAMETER,  # m, d in I
    "grain_density": 2500.0,  # kg/m³, glass (docs/physics.md §6)
    # The material model. The default, chosen in issue 15 (docs/validation.md, "The chosen
    # model"): "drucker_prager", the constant-friction cone at the beads' avalanche angle with
    # the Mohr–Coulomb deviatoric section and F-bar (keys below). Also "mohr_coulomb" (the seed
    # paper's model, with the keys above; the default until 2026-12-05) or
    # "granular_fluidity" (experimental), the nonlocal granular fluidity of Henann & Kamrin 2013
    # (granular_fluidity.rs), with its glass-bead μ_s, b and A below and grain_diameter,
    # grain_density above.
    "material_model": "drucker_prager",
    "static_friction": 0.3819,  # μ_s (granular_fluidity; Jop et al. 2006 via Henann & Kamrin 2013)
    "friction_rate": 0.9377,  # b (granular_fluidity; Henann & Kamrin 2013)
    "nonlocal_amplitude": 0.48,  # A (granular_fluidity; Henann & Kamrin 2013)
    # "drucker_prager" (drucker_prager.rs): the constant-friction cone τ = μ p; Rousseau et al.
    # (2023) set μ to the tangent of the avalanche angle, 27.4° for Lajeunesse et al.'s beads
    # (docs/physics.md §6a via Kumar 2015, medium confidence).
    "friction_coefficient": math.tan(math.radians(27.4)),
    # drucker_prager only: the Mohr–Coulomb deviatoric section with sin φ = μ (stronger in
    # triaxial compression, the same in plane-strain shear; drucker_prager.rs).
    "mohr_coulomb_section": True,
    # drucker_prager only, experimental: μ₂ of Jop et al.'s μ(I) with friction_coefficient as μ_s (glass beads:
    # 0.3819 and 0.6435, I₀ = inertial_number_scale; with grain_diameter and grain_density
    # above); None = constant friction.
    "inertial_friction": None,
    "base_friction": None,  # Coulomb μ of the base; None = tan(friction_angle)
    "shape_function": "cpgimp",
    "update_scheme": "musl",
    # Cell-mean dilatation (F-bar, docs/physics.md §1): without it the nearly isochoric plastic
    # flow of the cone locks ("none" = each particle's own dilatation rate).
    "volumetric_averaging": "cell",
    # Pure FLIP: the PIC part of a blend removes a fixed fraction of the particles' velocity
    # fluctuation *per step*, so its dissipation grows with the step count (stiffer E, finer
    # mesh) and set the runout (docs/validation.md, "Why the runout moved with the mesh").
    "flip_fraction": 1.0,
    "release_time": 0.0,  # s, wall removal; 0 = from the geostatic state at t = 0+
    # The confining cylinder lifted at a finite speed instead of removed at once: None = removed
    # at release_time (the seed set-up); a speed V (m/s) makes it a rigid tube (wall thickness
    # gate_thickness cells) that rises at V from release_time, in Coulomb contact with the sand
    # at gate_friction (docs/validation.md, "The lifted cylinder").
    "gate_speed": None,  # m/s
    "gate_friction": None,  # Coulomb μ bead–tube; None = tan(friction_angle)
    "gate_thickness": 2,  # cells
    "end_time": 1.0,  # s
    "output_interval": 0.02,  # s, the seed paper's profile interval
    "stop_at_rest": 1e-5,  # kinetic energy / work of gravity
    # Undamped pure-FLIP deposits keep an elastic vibration (KE ≈ 2e-3 of the work of
    # gravity) that never decays, so the run also stops once gravity does less than this
    # fraction of its work in settle_window: the deposit no longer moves down.
    "stop_when_settled": 5e-5,
    "settle_window": 0.1,  # s
    # Cells of grid below the base (a friction wall at z = 0 acts on them): a particle that
    # interpolation carries a hair below the base stays on the grid instead of ending the run.
    "cells_below_base": 2,
    # Plane strain: as many cells of grid behind the back wall (x = 0, a roller wall), for the
    # same reason: with the grid starting at x = 0 the a = 5.4 and 10 columns ended with a
    # particle carried a hair behind it (x = −7.5e-8 m, "left the grid"). In axisymmetry the
    # grid must start at the axis (none).
    "rest_check_after": 0.1,  # s after the release
    "formulation": "axisymmetric",
}


def _law_runout_guess(a: float, formulation: str = "axisymmetric") -> float:
    """(R∞−R_i)/R_i to size the grid: Lube et al. 2004 for a cylinder; for plane strain the
    longer of the planar laws, Lajeunesse et al. 2005 (1.8 a below a = 3, 2.3 a^(2/3) above;
    laws.py): a planar collapse spreads much further than a cylinder of the same a (nothing
    thins it by spreading round a circumference) — with the cylinder's law, a = 5.4 left the
    grid at t = 0.41 s at (R − R_i)/R_i = 9.2, still moving."""
    if formulation == "plane_strain":
        return 1.8 * a if a < 3.0 else 2.3 * a ** (2.0 / 3.0)
    return 1.24 * a if a < 1.7 else 1.6 * math.sqrt(a)


def collapse_scenario(
    aspect_ratio: float,
    radius: float = DEFAULTS["radius"],
    cell_size: float = DEFAULTS["cell_size"],
    *,
    height: float | None = None,
    formulation: str = DEFAULTS["formulation"],
    particles_per_cell: int = DEFAULTS["particles_per_cell"],
    density: float = DEFAULTS["density"],
    youngs_modulus: float = DEFAULTS["youngs_modulus"],
    poisson_ratio: float = DEFAULTS["poisson_ratio"],
    friction_angle: float = DEFAULTS["friction_angle"],
    dilation_angle: float = DEFAULTS["dilation_angle"],
    cohesion: float = DEFAULTS["cohesion"],
    critical_packing_fraction: float | None = DEFAULTS["critical_packing_fraction"],
    inertial_number_scale: float = DEFAULTS["inertial_number_scale"],
    grain_diameter: float = DEFAULTS["grain_diameter"],
    grain_density: float = DEFAULTS["grain_density"],
    material_model: str = DEFAULTS["material_model"],
    static_friction: float = DEFAULTS["static_friction"],
    friction_rate: float = DEFAULTS["friction_rate"],
    nonlocal_amplitude: float = DEFAULTS["nonlocal_amplitude"],
    friction_coefficient: float = DEFAULTS["friction_coefficient"],
    mohr_coulomb_section: bool = DEFAULTS["mohr_coulomb_section"],
    inertial_friction: float | None = DEFAULTS["inertial_friction"],
    base_friction: float | None = DEFAULTS["base_friction"],
    shape_function: str = DEFAULTS["shape_function"],
    update_scheme: str = DEFAULTS["update_scheme"],
    volumetric_averaging: str = DEFAULTS["volumetric_averaging"],
    flip_fraction: float = DEFAULTS["flip_fraction"],
    release_time: float = DEFAULTS["release_time"],
    gate_speed: float | None = DEFAULTS["gate_speed"],
    gate_friction: float | None = DEFAULTS["gate_friction"],
    gate_thickness: int = DEFAULTS["gate_thickness"],
    end_time: float = DEFAULTS["end_time"],
    output_interval: float = DEFAULTS["output_interval"],
    stop_at_rest: float = DEFAULTS["stop_at_rest"],
    stop_when_settled: float = DEFAULTS["stop_when_settled"],
    settle_window: float = DEFAULTS["settle_window"],
    cells_below_base: int = DEFAULTS["cells_below_base"],
    rest_check_after: float = DEFAULTS["rest_check_after"],
    domain_radius: float | None = None,
    as_dict: bool = False,
) -> Any:
    """A column-collapse scenario (a :class:`~axmpm.scenario.Scenario`, or its plain dict).

    The column [0, R_i] × [0, H_i] starts from the geostatic stress (k0 = 1 − sin φ) inside a
    roller wall at r = R_i that is removed at ``release_time``. Bodies must lie on grid
    lines, so R_i and H_i = a R_i are rounded to whole cells (``height`` overrides H_i);
    the scenario's actual aspect ratio is H_i/R_i of its body (:func:`geometry_from_scenario`).
    """
    from ...scenario import Scenario

    if material_model not in ("mohr_coulomb", "granular_fluidity", "drucker_prager"):
        raise ValueError("material_model: must be 'mohr_coulomb', 'granular_fluidity' or 'drucker_prager' "
                         f"(got {material_model!r})")
    if material_model != "mohr_coulomb":
        # A Mohr–Coulomb key given to another model would change nothing but, for
        # friction_angle, the base: refuse it rather than run something else than asked.
        for key, given in (("friction_angle", friction_angle != DEFAULTS["friction_angle"]),
                           ("dilation_angle", dilation_angle != DEFAULTS["dilation_angle"]),
                           ("cohesion", cohesion != DEFAULTS["cohesion"])):
            if given:
                raise ValueError(f"{key}: is a mohr_coulomb parameter, and material_model is {material_model!r} "
                                 "(set material_model=mohr_coulomb for the Mohr–Coulomb set-up; the base's friction is "
                                 "base_friction, the cone's friction_coefficient)")
    if material_model == "drucker_prager" and not (0.0 < friction_coefficient < 1.0):
        raise ValueError(f"friction_coefficient: must be > 0 and < 1 (got {friction_coefficient})")
    h = float(cell_size)
    n_r = max(1, int(round(radius / h)))
    H = aspect_ratio * n_r * h if height is None else float(height)
    n_z = max(1, int(round(H / h)))
    R_i, H_i = n_r * h, n_z * h
    a = H_i / R_i
    mu = math.tan(math.radians(friction_angle)) if base_friction is None else float(base_friction)
    if domain_radius is None:
        # Room for the thin sheet pure FLIP lets slide along the base beyond the deposit.
        domain_radius = R_i * (2.0 + 2.5 * _law_runout_guess(a, formulation))
    n_dr = max(n_r + 2, int(math.ceil(domain_radius / h - 1e-9)))
    n_below = max(0, int(cells_below_base))
    n_dz = n_z + 4 + n_below
    n_behind = n_below if formulation == "plane_strain" else 0
    if gate_speed is None:
        # The cylinder: a roller wall at r = R_i removed at release_time.
        cylinder_walls = [{"axis": "x", "position": R_i, "material_side": "negative", "condition": "roller",
                           "removal_time": release_time}]
        rigid_bodies = []
    else:
        # The cylinder as a rigid tube r ∈ [R_i, R_i + t], z ∈ [0, H_i + 2h] that rises at
        # gate_speed from release_time (constant speed: the lift's acceleration is not modelled).
        if not (gate_speed > 0.0 and math.isfinite(gate_speed)):
            raise ValueError(f"gate_speed: must be a finite speed > 0 m/s (got {gate_speed})")
        n_t = int(gate_thickness)
        if n_t < 1:
            raise ValueError(f"gate_thickness: must be a whole number of cells >= 1 (got {gate_thickness})")
        motion = [[0.0, 0.0, float(gate_speed)]] if release_time <= 0.0 else \
            [[release_time, 0.0, 0.0], [release_time + 1e-6, 0.0, float(gate_speed)]]
        # The tube stops when its top reaches the grid's (its path must stay inside the grid):
        # it rises by the head-room above it, 2 cells + half the column (below), less 1 µs of travel.
        room = (2 + math.ceil(0.5 * n_z)) * h
        stop = max(release_time, 0.0) + room / float(gate_speed) - 1e-6
        motion += [[stop, 0.0, float(gate_speed)], [stop + 1e-6, 0.0, 0.0]]
        cylinder_walls = []
        rigid_bodies = [{
            "name": "cylinder", "shape": "rectangle",
            "min": [R_i, 0.0], "max": [R_i + n_t * h, H_i + 2 * h],
            "motion": motion, "friction": mu if gate_friction is None else float(gate_friction),
        }]
        n_dr = max(n_dr, n_r + n_t + 2)
        # Head-room: the tube's friction drags the sand next to it upwards (at a = 10 and
        # 0.5 m/s a particle left a grid H_i + 4h tall at t = 0.027 s).
        n_dz += math.ceil(0.5 * n_z)
    data: dict[str, Any] = {
        "simulation": {
            "formulation": formulation,
            "shape_function": shape_function,
            "update_scheme": update_scheme,
            "volumetric_averaging": volumetric_averaging,
            "flip_fraction": flip_fraction,
            "end_time": end_time,
            "output_interval": output_interval,
            "gravity": [0.0, -9.81],
            "damping": 0.0,
            "stop_at_rest": stop_at_rest,
            "stop_when_settled": stop_when_settled,
            "settle_window": settle_window,
            "stop_at_rest_after": release_time + rest_check_after,
        },
        "grid": {"origin": [-n_behind * h, -n_below * h], "extent": [(n_dr + n_behind) * h, n_dz * h],
                 "cell_size": h},
        "materials": {
            "sand": {
                "model": "granular_fluidity",
                "density": density,
                "youngs_modulus": youngs_modulus,
                "poisson_ratio": poisson_ratio,
                "static_friction": static_friction,
                "friction_rate": friction_rate,
                "nonlocal_amplitude": nonlocal_amplitude,
                "grain_diameter": grain_diameter,
                "grain_density": grain_density,
                "experimental": True,
            } if material_model == "granular_fluidity" else {
                "model": "drucker_prager",
                "density": density,
                "youngs_modulus": youngs_modulus,
                "poisson_ratio": poisson_ratio,
                "friction": friction_coefficient,
                **({"mohr_coulomb_section": True} if mohr_coulomb_section else {}),
                **({"critical_packing_fraction": critical_packing_fraction,
                    "grain_density": grain_density}
                   if critical_packing_fraction is not None else {}),
                **({"inertial_friction": inertial_friction, "inertial_number_scale": inertial_number_scale,
                    "grain_diameter": grain_diameter, "grain_density": grain_density}
                   if inertial_friction is not None else {}),
                **({"experimental": True}
                   if inertial_friction is not None or critical_packing_fraction is not None else {}),
            } if material_model == "drucker_prager" else {
                "model": "mohr_coulomb",
                "density": density,
                "youngs_modulus": youngs_modulus,
                "poisson_ratio": poisson_ratio,
                "friction_angle": friction_angle,
                "dilation_angle": dilation_angle,
                "cohesion": cohesion,
                "tension_cutoff": 0.0,
                **({"critical_packing_fraction": critical_packing_fraction,
                    "grain_density": grain_density, "experimental": True}
                   if critical_packing_fraction is not None else {}),
            }
        },
        "bodies": [
            {
                "name": "column",
                "material": "sand",
                "min": [0.0, 0.0],
                "max": [R_i, H_i],
                "particles_per_cell": particles_per_cell,
                "initial_stress": "geostatic",
                # Jaky's k0 = 1 − sin φ (the fluidity and cone models: sin φ = μ).
                "k0": 1.0 - (static_friction if material_model == "granular_fluidity"
                             else friction_coefficient if material_model == "drucker_prager"
                             else math.sin(math.radians(friction_angle))),
            }
        ],
        "boundaries": {
            "left": {"condition": "roller"},
            "right": {"condition": "free"},
            "bottom": {"condition": "friction", "coefficient": mu},
            "top": {"condition": "free"},
        },
        "walls": ([
            # The base, when the grid reaches below it (else the bottom face is the base).
            {"axis": "y", "position": 0.0, "material_side": "positive", "condition": "friction",
             "coefficient": mu},
        ] if n_below else []) + ([
            # Plane strain: the back wall (symmetry plane), when the grid reaches behind it.
            {"axis": "x", "position": 0.0, "material_side": "positive", "condition": "roller"},
        ] if n_behind else []) + cylinder_walls,
    }
    if rigid_bodies:
        data["rigid_bodies"] = rigid_bodies
    if as_dict:
        return data
    return Scenario.from_dict(data)
