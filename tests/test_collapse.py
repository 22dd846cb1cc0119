"""Granular column collapse: deposit analysis on synthetic particle sets, the scenario
builder, and a tiny coarse run through ``axmpm validate``."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from axmpm.cases.column_collapse import collapse_scenario
from axmpm.cases.column_collapse.deposit import (ColumnGeometry, deposit_metrics, final_height,
                            geometry_from_scenario, particle_metrics, runout_radius, surface_profile)

H_CELL = 0.002
S = H_CELL / 2


def geom(formulation="axisymmetric", R=0.03, H=0.016):
    return ColumnGeometry(radius=R, height=H, axis=0.0, base=0.0, cell_size=H_CELL,
                          particles_per_cell=2, formulation=formulation)


def lattice(profile, r_max, formulation="axisymmetric"):
    """Particles on the s-lattice under the surface z = profile(r) (0 < r < r_max)."""
    rs = (np.arange(int(round(r_max / S))) + 0.5) * S
    pts = []
    for r in rs:
        top = profile(r)
        n = int(round(top / S))
        pts += [(r, (k + 0.5) * S) for k in range(n)]
    x = np.array(pts)
    v0 = (x[:, 0] * S * S) if formulation == "axisymmetric" else np.full(len(x), S * S)
    return x, v0, 1550.0 * v0


@pytest.mark.parametrize("formulation", ["axisymmetric", "plane_strain"])
def test_rectangle_gives_its_radius_and_height(formulation):
    g = geom(formulation)
    x, v0, m = lattice(lambda r: 0.016, 0.03, formulation)
    met = particle_metrics(x, v0, m, g)
    assert met["runout_radius_particle_edge"] == pytest.approx(0.03, abs=1e-12)
    assert met["runout_normalised_particle_edge"] == pytest.approx(0.0, abs=1e-9)
    # one-grain edge: the 2 mm thickness profile steps from H to 0 between the bin centres
    # 29 and 31 mm; linear interpolation puts thickness d at 29 + 2 (H - d)/H mm.
    d = 1.15e-3
    one_grain = 0.029 + 0.002 * (0.016 - d) / 0.016
    assert met["runout_radius"] == pytest.approx(one_grain, abs=1e-9)
    assert met["runout_normalised"] == pytest.approx((one_grain - 0.03) / 0.03, abs=1e-7)
    assert met["final_height"] == pytest.approx(0.016, rel=1e-9)
    assert met["final_height_normalised"] == pytest.approx(0.016 / 0.03)
    r, h = surface_profile(x, v0, g)
    np.testing.assert_allclose(h[r < 0.03], 0.016, rtol=1e-9)


@pytest.mark.parametrize("formulation", ["axisymmetric", "plane_strain"])
def test_cone_gives_apex_and_foot(formulation):
    g = geom(formulation)
    H0, Rc = 0.024, 0.05  # cone apex height and foot radius (slope ~ 26°)
    x, v0, m = lattice(lambda r: H0 * (1 - r / Rc), Rc, formulation)
    met = particle_metrics(x, v0, m, g)
    # lattice staircase: within one particle spacing
    assert met["final_height"] == pytest.approx(H0, abs=S)
    assert abs(met["runout_radius_particle_edge"] - Rc) <= 1.5 * S + 1e-12


def test_truncated_cone():
    g = geom()
    x, v0, m = lattice(lambda r: min(0.016, 0.016 * (0.045 - r) / 0.025), 0.045)
    assert final_height(x, v0, g) == pytest.approx(0.016, abs=0.2 * S)
    assert runout_radius(x, v0, g) == pytest.approx(0.045, abs=1.5 * S)


def test_stray_particles_do_not_change_runout():
    g = geom()
    x, v0, m = lattice(lambda r: 0.016 * min(1.0, (0.045 - r) / 0.02), 0.045)
    base = particle_metrics(x, v0, m, g)
    # isolated grains thrown beyond an empty bin, and a thin spike on the axis
    strays = np.array([[0.0520, 0.0005], [0.0600, 0.0005], [0.0800, 0.0015], [0.070, 0.0005]])
    spike = np.array([[0.0005, 0.0165 + k * S] for k in range(4)])
    extra = np.vstack([strays, spike])
    xe = np.vstack([x, extra])
    ve = np.concatenate([v0, extra[:, 0] * S * S])
    me = 1550.0 * ve
    with_strays = particle_metrics(xe, ve, me, g)
    assert with_strays["runout_radius"] == base["runout_radius"]
    assert with_strays["runout_radius_particle_edge"] == base["runout_radius_particle_edge"]
    assert with_strays["max_particle_radius"] > 0.08  # the strays are there
    assert with_strays["final_height"] == pytest.approx(base["final_height"], abs=0.25 * S)
    assert with_strays["max_particle_height"] > base["max_particle_height"] + 3 * S


def test_builder_default_model_is_the_chosen_one():
    # Issue 15's chosen model: the cone at the beads' avalanche angle with the Mohr–Coulomb
    # section and F-bar; Jaky's k0 = 1 − μ.
    s = collapse_scenario(0.8)
    sand = s.materials["sand"]
    assert (sand.model, sand.mohr_coulomb_section, sand.inertial_friction) == ("drucker_prager", True, None)
    assert sand.friction == pytest.approx(math.tan(math.radians(27.4)))
    assert sand.critical_packing_fraction is None
    # Production options only: the builder's table does not opt into experimental ones.
    assert sand.experimental is False and "experimental" not in collapse_scenario(0.8, as_dict=True)["materials"]["sand"]
    assert s.simulation.volumetric_averaging == "cell"
    assert s.bodies[0].k0 == pytest.approx(1.0 - sand.friction)
    assert s.walls[0].coefficient == pytest.approx(math.tan(math.radians(25.0)))
    assert collapse_scenario(0.8, volumetric_averaging="none").simulation.volumetric_averaging == "none"
    assert collapse_scenario(0.8, material_model="mohr_coulomb").materials["sand"].model == "mohr_coulomb"


def test_builder_geometry_walls_and_friction():
    s = collapse_scenario(0.8, material_model="mohr_coulomb")
    g = geometry_from_scenario(s)
    assert (g.radius, g.height, g.cells_per_radius) == pytest.approx((0.03, 0.024, 15.0))
    assert s.simulation.formulation == "axisymmetric" and s.simulation.output_interval == 0.02
    assert s.simulation.shape_function == "cpgimp" and s.simulation.update_scheme == "musl"
    mat = s.materials["sand"]
    assert (mat.model, mat.friction_angle, mat.dilation_angle, mat.cohesion) == ("mohr_coulomb", 25.0, 0.0, 0.0)
    body = s.bodies[0]
    assert body.initial_stress == "geostatic"
    assert body.k0 == pytest.approx(1 - math.sin(math.radians(25.0)))
    base, wall = s.walls
    assert (wall.axis, wall.position, wall.material_side, wall.condition) == ("x", 0.03, "negative", "roller")
    assert wall.removal_time == 0.0
    # the base is a friction wall at z = 0 with two cells of grid below it
    assert (base.axis, base.position, base.material_side, base.condition) == ("y", 0.0, "positive", "friction")
    assert base.removal_time is None
    assert base.coefficient == pytest.approx(math.tan(math.radians(25.0)))
    assert s.grid.origin[1] == pytest.approx(-2 * 0.002)
    assert s.boundaries.bottom.condition == "friction"
    assert s.simulation.stop_at_rest > 0 and s.simulation.stop_when_settled > 0
    assert s.simulation.flip_fraction == 1.0
    flat = collapse_scenario(0.8, cells_below_base=0)
    assert len(flat.walls) == 1 and flat.grid.origin[1] == 0.0
    assert flat.boundaries.bottom.coefficient == pytest.approx(math.tan(math.radians(25.0)))
    # H_i = 0.56 R_i = 16.8 mm is not on the 2 mm grid: rounded to 16 mm
    g56 = geometry_from_scenario(collapse_scenario(0.56))
    assert g56.height == pytest.approx(0.016) and g56.aspect_ratio == pytest.approx(0.5333, abs=1e-3)
    assert geometry_from_scenario(collapse_scenario(0.56, cell_size=0.001)).height == pytest.approx(0.017)
    assert geometry_from_scenario(collapse_scenario(5.4)).height == pytest.approx(0.162)


def test_builder_critical_packing_fraction():
    mc = {"material_model": "mohr_coulomb"}
    sand = collapse_scenario(0.8, **mc).materials["sand"]
    assert sand.critical_packing_fraction is None and sand.grain_density is None  # off by default
    sand = collapse_scenario(0.8, critical_packing_fraction=0.55, **mc).materials["sand"]
    assert sand.critical_packing_fraction == 0.55 and sand.grain_density == 2500.0 and sand.experimental is True
    sand = collapse_scenario(0.8, material_model="drucker_prager", critical_packing_fraction=0.55).materials["sand"]
    assert sand.model == "drucker_prager" and sand.critical_packing_fraction == 0.55 and sand.grain_density == 2500.0
    assert sand.experimental is True


def test_builder_material_models():
    # Drucker–Prager at the avalanche angle of the beads (Rousseau et al. 2023), k0 = 1 − μ.
    sc = collapse_scenario(0.8, material_model="drucker_prager")
    sand = sc.materials["sand"]
    assert sand.model == "drucker_prager" and sand.friction == pytest.approx(math.tan(math.radians(27.4)))
    assert sc.bodies[0].k0 == pytest.approx(1.0 - sand.friction)
    assert collapse_scenario(0.8, material_model="drucker_prager", friction_coefficient=0.4).bodies[0].k0 == 0.6
    # the Mohr–Coulomb deviatoric section: on by default (the chosen model), passed through
    assert sand.mohr_coulomb_section is True
    assert collapse_scenario(0.8, material_model="drucker_prager",
                             mohr_coulomb_section=False).materials["sand"].mohr_coulomb_section is False
    from axmpm.scenario import Scenario, ScenarioError

    bad = collapse_scenario(0.8, material_model="drucker_prager", as_dict=True)
    bad["materials"]["sand"]["mohr_coulomb_section"] = 3
    with pytest.raises(ScenarioError, match="materials.sand.mohr_coulomb_section"):
        Scenario.from_dict(bad)
    # Jop et al.'s μ(I) on the cone: off by default; with it friction_coefficient is μ_s
    assert sand.inertial_friction is None
    sc = collapse_scenario(0.8, material_model="drucker_prager", friction_coefficient=0.3819, inertial_friction=0.6435)
    sand = sc.materials["sand"]
    assert (sand.friction, sand.inertial_friction, sand.inertial_number_scale) == (0.3819, 0.6435, 0.279)
    assert (sand.grain_diameter, sand.grain_density) == (1.15e-3, 2500.0)
    assert sand.experimental is True
    assert sc.bodies[0].k0 == pytest.approx(1.0 - 0.3819)
    fluidity = collapse_scenario(0.8, material_model="granular_fluidity")
    assert fluidity.bodies[0].k0 == pytest.approx(1.0 - 0.3819) and fluidity.materials["sand"].experimental is True
    with pytest.raises(ValueError, match="material_model: must be 'mohr_coulomb', 'granular_fluidity' or "
                                         "'drucker_prager' \\(got 'cam_clay'\\)"):
        collapse_scenario(0.8, material_model="cam_clay")


def test_examples_match_builder():
    from axmpm.scenario import Scenario

    root = Path(__file__).resolve().parents[1] / "examples"
    for name, a in (("a056", 0.56), ("a08", 0.8), ("a54", 5.4)):
        # the seed paper's Mohr–Coulomb set-up (the builder's default until 2026-12-05)
        ex = Scenario.from_toml(root / f"column_collapse_{name}.toml")
        assert ex.to_dict() == collapse_scenario(a, material_model="mohr_coulomb",
                                                 volumetric_averaging="none").to_dict()
    # Drucker–Prager at the avalanche angle with F-bar, 30 cells per radius, circular section.
    data = collapse_scenario(5.4, cell_size=0.001, material_model="drucker_prager", mohr_coulomb_section=False,
                             as_dict=True)
    ex = Scenario.from_toml(root / "column_collapse_a54_drucker_prager.toml")
    assert ex.to_dict() == Scenario.from_dict(data).to_dict()
    assert ex.materials["sand"].model == "drucker_prager" and ex.simulation.volumetric_averaging == "cell"
    # The same with the Mohr–Coulomb deviatoric section.
    # The same with the Mohr–Coulomb deviatoric section: the chosen model, the builder's default.
    ex = Scenario.from_toml(root / "column_collapse_a54_mohr_coulomb_section.toml")
    assert ex.to_dict() == collapse_scenario(5.4, cell_size=0.001).to_dict()
    assert ex.materials["sand"].mohr_coulomb_section is True


def test_tiny_validate_run(tmp_path):
    out = tmp_path / "val"
    from axmpm.cli import main

    code = main(["validate", "--cases", "a056", "--out", str(out), "--jobs", "1",
                 "--set", "cell_size=0.004", "--set", "end_time=0.06", "--set", "simulation.cfl=0.5"])
    assert code == 0
    data = json.loads((out / "validation.json").read_text())
    (case,) = data["cases"]
    for key in ("name", "aspect_ratio", "formulation", "initial_radius", "initial_height",
                "runout_radius", "final_height", "run_dir", "cells_per_radius", "laws"):
        assert key in case
    assert case["name"] == "a056" and case["formulation"] == "axisymmetric"
    # the driver's reference: Lube et al. 2004 at the simulated aspect ratio, (R∞ − R_i)/R_i =
    # 1.24 a below a = 1.7 (docs/physics.md §6), and the error of the runout recomputed from the
    # last frame against it
    a = case["aspect_ratio"]
    assert a == pytest.approx(0.5)  # R_i = 3 cm and H_i = 0.56 R_i rounded to 4 mm cells: 8 and 4 cells
    lube_runout = 1.24 * a
    m = deposit_metrics(out / case["run_dir"])
    assert case["reference"]["runout_normalised"] == pytest.approx(lube_runout, rel=1e-12)
    assert case["relative_error"]["runout_normalised"] == pytest.approx(
        (m["runout_normalised"] - lube_runout) / lube_runout, rel=1e-12)
    assert data["formulation"] == "axisymmetric"
    # every check passes: the run completed and its energy budget closes
    assert [c["name"] for c in data["checks"]] == [
        "a056 completed", "a056: energy budget closes (residual within 5 % of the released energy)"]
    assert all(c["passed"] for c in data["checks"])
    assert case["status"] == "completed" and case["cells_per_radius"] == pytest.approx(8.0)
    lube = case["laws"]["lube2004"]
    for key in ("runout_radius", "final_height", "runout_radius_rel_diff", "final_height_rel_diff"):
        assert key in lube
    # reported values are those of the last frame
    assert case["case"] == "column_collapse" and case["run_dir"] == "cases/column_collapse/a056"
    assert m["runout_radius"] == case["runout_radius"] and m["final_height"] == case["final_height"]
    assert m["time"] == pytest.approx(0.06)
    assert case["initial_radius"] < case["runout_radius"] < 2 * case["initial_radius"]
    assert (out / "report.md").exists() and (out / "profiles.png").exists() and (out / "laws.png").exists()
    assert "cells per initial radius" in (out / "report.md").read_text()
    # the animated collapse: one GIF frame per output frame, shown in the report
    from PIL import Image

    with Image.open(out / "a056.gif") as gif:
        assert gif.n_frames == len(list((out / case["run_dir"] / "frames").glob("frame_*.npz")))
    assert "![a056](a056.gif)" in (out / "report.md").read_text()
    assert case["stress_free_fraction"] >= 0.0 and case["disconnection_fraction_of_plastic_work"] is None
    # the tail figures: R∞(3d) inside the one-grain edge, the mass beyond each law's R∞ a share
    assert case["runout_radius_3_grains"] <= case["runout_radius"]
    assert case["runout_3_grains_rel_diff"]["lube2004"] == pytest.approx(
        (m["runout_normalised_3_grains"] - lube_runout) / lube_runout, rel=1e-12)
    assert 0.0 <= case["mass_beyond_law"]["lube2004"] <= 1.0
    assert "| at 3 d | diff | mass beyond Lube 2004 |" in (out / "report.md").read_text()
    # the sideways share of the released energy (Staron & Hinch's measure), a share below 1
    side = case["sideways_energy"]
    assert 0.0 < side["peak_sideways_share"] < 1.0 and 0.0 < side["peak_sideways_time"] <= 0.06
    # the plastic work split by Lode parameter: shares of one whole, the total at least the
    # work the last frame holds (increments that go negative count as nothing)
    lode = case["plastic_work_by_lode"]
    assert sum(lode["shares"].values()) == pytest.approx(1.0)
    from axmpm.run.output import load_run

    last = load_run(out / case["run_dir"]).last
    held = float((last.state[:, list(last.state_names).index("plastic_work")] * last.volume0).sum())
    assert lode["plastic_work"] >= held * (1 - 1e-12) > 0.0


@pytest.mark.parametrize("formulation", ["axisymmetric", "plane_strain"])
def test_one_grain_runout_is_where_a_cone_is_one_grain_thick(formulation):
    from axmpm.cases.column_collapse.deposit import GRAIN_DIAMETER, runout_radius_at_thickness

    g = geom(formulation)
    H0, Rc = 0.024, 0.05
    x, v0, m = lattice(lambda r: H0 * (1 - r / Rc), Rc, formulation)
    expected = Rc * (1 - GRAIN_DIAMETER / H0)
    met = particle_metrics(x, v0, m, g)
    assert met["runout_radius"] == pytest.approx(expected, abs=0.5e-3)
    assert met["runout_normalised"] == pytest.approx((expected - 0.03) / 0.03, abs=0.02)
    # a thicker threshold moves the edge inwards along the slope
    inner = runout_radius_at_thickness(x, v0, g, thickness=0.012)
    assert inner == pytest.approx(Rc * 0.5, abs=0.5e-3)
    # a block thinner than the threshold everywhere has no deposit edge beyond the axis
    xb, vb, _ = lattice(lambda r: S, 0.03, formulation)  # one 1 mm layer
    assert runout_radius_at_thickness(xb, vb, g) == 0.0


@pytest.mark.parametrize("formulation", ["axisymmetric", "plane_strain"])
def test_tail_runout_and_mass_beyond_a_radius_on_a_cone(formulation):
    """The tail figures reported beside the headline runout: R∞(3d) where the cone is three
    grains thick (inside the one-grain edge), and the share of the mass beyond a radius,
    against the cone's exact volume share outside ρ = r/Rc: ∫ρ¹ u(1 − u) du / ∫₀¹ u(1 − u) du
    = 1 − 3ρ² + 2ρ³ axisymmetric, (1 − ρ)² planar."""
    from axmpm.cases.column_collapse.deposit import GRAIN_DIAMETER, TAIL_GRAINS, mass_fraction_beyond

    g = geom(formulation)
    H0, Rc = 0.024, 0.05
    x, v0, m = lattice(lambda r: H0 * (1 - r / Rc), Rc, formulation)
    met = particle_metrics(x, v0, m, g)
    tail = Rc * (1 - TAIL_GRAINS * GRAIN_DIAMETER / H0)
    assert met["runout_radius_3_grains"] == pytest.approx(tail, abs=0.5e-3)
    assert met["runout_normalised_3_grains"] == pytest.approx((tail - 0.03) / 0.03, abs=0.02)
    assert met["runout_radius_3_grains"] < met["runout_radius"] - 0.004
    for rho in (0.3, 0.6, 0.9):
        exact = 1 - 3 * rho**2 + 2 * rho**3 if formulation == "axisymmetric" else (1 - rho) ** 2
        assert mass_fraction_beyond(x, m, g, rho * Rc) == pytest.approx(exact, abs=0.02)
    assert mass_fraction_beyond(x, m, g, Rc) == 0.0
    assert mass_fraction_beyond(x, m, g, 0.0) == 1.0


def test_pure_flip_runout_does_not_depend_on_the_step_count(tmp_path):
    """docs/validation.md, "Why the runout moved with the mesh": a FLIP/PIC blend damps a fixed
    fraction of the particles' sub-cell velocity per step, so a stiffer material (√10 × more
    steps) ran out shorter; with pure FLIP (the builder's default) E no longer matters.
    a = 0.8 on 4 mm cells (7.5 cells per radius) to keep the test short."""
    import axmpm

    def runout(E, flip):
        out = tmp_path / f"E{E:g}_flip{flip:g}"
        axmpm.run(collapse_scenario(0.8, cell_size=0.004, youngs_modulus=E, flip_fraction=flip), out, threads=1)
        return deposit_metrics(out)["runout_normalised"]

    assert collapse_scenario(0.8).simulation.flip_fraction == 1.0
    soft, stiff = runout(1e6, 1.0), runout(1e7, 1.0)
    assert abs(soft - stiff) < 0.01, (soft, stiff)
    blend_soft, blend_stiff = runout(1e6, 0.99), runout(1e7, 0.99)
    assert blend_soft - blend_stiff > 0.02, (blend_soft, blend_stiff)  # the step-count damping
    assert soft > blend_soft


def test_builder_gate_is_a_lifted_rigid_tube():
    """gate_speed replaces the removed roller wall by a rigid tube at r = R_i rising at that speed."""
    from axmpm.cases.column_collapse.case import ColumnCollapse

    s = collapse_scenario(2.0, gate_speed=0.5)
    assert [w.removal_time for w in s.walls] == [None]  # only the base is left
    (tube,) = s.rigid_bodies
    assert tube.name == "cylinder" and tube.shape == "rectangle"
    assert tube.min == pytest.approx((0.03, 0.0)) and tube.max == pytest.approx((0.034, 0.064))
    # rising at 0.5 m/s until its top reaches the grid's (2 cells + half the column above it)
    room = s.grid.origin[1] + s.grid.extent[1] - tube.max[1]
    assert room == pytest.approx(0.002 * (2 + 15))  # h = 2 mm, H_i = 30 cells
    assert [list(row) for row in tube.motion] == [[0.0, 0.0, 0.5], [pytest.approx(room / 0.5 - 1e-6), 0.0, 0.5],
                                                  [pytest.approx(room / 0.5), 0.0, 0.0]]
    assert tube.friction == pytest.approx(math.tan(math.radians(25.0)))  # default: the sand's
    assert collapse_scenario(2.0, gate_speed=0.5, gate_friction=0.16).rigid_bodies[0].friction == 0.16
    # head-room for the sand the tube drags up: half the column above the usual grid
    plain = collapse_scenario(2.0)
    assert s.grid.extent[1] == pytest.approx(plain.grid.extent[1] + 0.5 * 0.06)
    # a later release: at rest until then
    late = collapse_scenario(2.0, gate_speed=0.5, release_time=0.1).rigid_bodies[0]
    assert [list(r) for r in late.motion][:2] == [[0.1, 0.0, 0.0], [pytest.approx(0.1 + 1e-6), 0.0, 0.5]]
    assert ColumnCollapse().matches(s.to_dict()) and ColumnCollapse().matches(plain.to_dict())
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(ValueError, match="gate_speed"):
            collapse_scenario(2.0, gate_speed=bad)


def test_lifted_tube_holds_the_sand_above_its_bottom_edge(tmp_path):
    """While the tube rises, sand leaves only below its bottom edge (z ≤ V t): with the wall
    removed at once the same column has sand beyond R_i higher up."""
    from axmpm.run.output import load_run
    from axmpm.run.runner import run

    V, t_end = 0.5, 0.08
    kwargs = dict(cell_size=0.004, end_time=t_end, output_interval=t_end, stop_at_rest=0.0, stop_when_settled=0.0)
    heights = {}
    radius = collapse_scenario(2.0, gate_speed=V, **kwargs).rigid_bodies[0].min[0]  # R_i on the 4 mm grid
    for name, gate in (("gate", V), ("instant", None)):
        run(collapse_scenario(2.0, gate_speed=gate, **kwargs), tmp_path / name, threads=1, progress=False)
        last = load_run(tmp_path / name).last
        outside = last.x[:, 0] > radius + 0.001  # beyond the tube's inner face by a quarter cell
        heights[name] = float(last.x[outside, 1].max()) if outside.any() else 0.0
    assert 0.0 < heights["gate"] <= V * t_end + 0.002, heights
    assert heights["instant"] > heights["gate"] + 0.008, heights  # two cells higher


def test_kinetic_energy_split_of_given_frames():
    """½ Σ m v_r², ½ Σ m v_z² and Σ m g·(x − X0) of each frame, by hand."""
    from types import SimpleNamespace

    from axmpm.cases.column_collapse.energy import kinetic_energy_split

    frame = SimpleNamespace(time=0.5, mass=np.array([2.0, 3.0]), v=np.array([[1.0, -2.0], [0.5, 0.0]]),
                            X0=np.array([[0.0, 1.0], [0.1, 2.0]]), x=np.array([[0.2, 0.5], [0.1, 2.25]]))
    split = kinetic_energy_split([frame], (0.0, -10.0))
    assert split["time"].tolist() == [0.5]
    assert split["sideways"][0] == pytest.approx(0.5 * (2.0 * 1.0 + 3.0 * 0.25))
    assert split["vertical"][0] == pytest.approx(0.5 * 2.0 * 4.0)
    # 2 kg fell 0.5 m, 3 kg rose 0.25 m: (10 − 7.5) J released
    assert split["released"][0] == pytest.approx(2.0 * 10.0 * 0.5 - 3.0 * 10.0 * 0.25)
    # a sideways gravity releases energy with sideways displacement
    assert kinetic_energy_split([frame], (-10.0, 0.0))["released"][0] == pytest.approx(-2.0 * 10.0 * 0.2)


def test_lode_parameter_of_the_reference_states():
    """ξ = −1 for triaxial compression, 0 for shear, +1 for triaxial extension, whatever the
    in-plane orientation (a state rotated in the 1–2 plane keeps its ξ), NaN without deviator."""
    from axmpm.cases.column_collapse.energy import lode_parameter

    def rotated(s11, s22, s33, angle):
        c, s = np.cos(angle), np.sin(angle)
        return [c * c * s11 + s * s * s22, s * s * s11 + c * c * s22, s33, c * s * (s11 - s22)]

    stresses = np.array([
        [-3.0, -1.0, -1.0, 0.0],  # compression along 1
        rotated(-1.0, -3.0, -1.0, 0.4),  # compression along a rotated in-plane axis
        [-1.0, -1.0, -3.0, 0.0],  # compression along the hoop
        [-2.0, -1.0, 0.0, 0.0],  # middle stress the mean: shear
        [0.0, 0.0, 0.0, 1.5],  # simple shear in the plane
        [-1.0, -3.0, -3.0, 0.0],  # extension along 1
        rotated(-3.0, -1.0, -3.0, 1.1),  # extension along a rotated in-plane axis
        [-2.0, -2.0, -2.0, 0.0],  # isotropic
        [0.0, 0.0, 0.0, 0.0],  # stress-free
    ])
    xi = lode_parameter(stresses)
    assert xi[:7] == pytest.approx([-1.0, -1.0, -1.0, 0.0, 0.0, 1.0, 1.0], abs=1e-12)
    assert np.isnan(xi[7:]).all()
    # an intermediate state by hand: s = (−4/3, 1/6, 7/6), J2 = 19/12, J3 = −7/27
    assert lode_parameter(np.array([[-2.5, -1.0, 0.0, 0.0]]))[0] == pytest.approx(
        1.5 * np.sqrt(3) * (-7 / 27) / (19 / 12) ** 1.5, rel=1e-12)


def test_plastic_work_is_booked_by_the_lode_parameter_of_each_interval():
    """Each frame's increase of plastic_work × V0 goes to the bin of the particle's ξ at that
    frame; the first frame counts from zero, a decrease counts as nothing."""
    from types import SimpleNamespace

    from axmpm.cases.column_collapse.energy import plastic_work_by_lode

    compression, shear, extension, free = [-3.0, -1.0, -1.0, 0.0], [0.0, 0.0, 0.0, 1.0], [-1.0, -3.0, -3.0, 0.0], [0.0] * 4
    names = ["plastic_shear_strain", "plastic_work"]
    volume0 = np.array([2.0, 1.0, 1.0, 1.0])

    def frame(work, stress):
        return SimpleNamespace(state_names=names, volume0=volume0, stress=np.array(stress),
                               state=np.column_stack([np.zeros(4), work]))

    frames = [frame([1.0, 0.0, 0.0, 0.0], [compression, shear, extension, free]),
              frame([1.5, 3.0, 1.0, 2.0], [shear, shear, extension, free]),
              frame([1.5, 2.0, 1.0, 2.0], [shear, compression, compression, free])]  # a decrease: nothing
    out = plastic_work_by_lode(frames)
    # compression 2×1 (frame 1); shear 2×0.5 + 3 (frame 2); extension 1; stress-free 2
    assert out["plastic_work"] == pytest.approx(9.0)
    assert out["shares"] == pytest.approx({"compression": 2 / 9, "shear": 4 / 9, "extension": 1 / 9,
                                           "stress_free": 2 / 9})
    assert out["mean_lode_parameter"] == pytest.approx((-2.0 + 0.0 + 1.0) / 7.0)
    # no plastic_work state, or no plastic work: nothing to split
    assert plastic_work_by_lode([SimpleNamespace(state_names=["x"], volume0=volume0, stress=np.zeros((4, 4)),
                                                 state=np.zeros((4, 1)))]) is None
    assert plastic_work_by_lode([frame(np.zeros(4), [shear] * 4)]) is None


def test_sideways_energy_of_a_block_thrown_sideways_in_free_fall(tmp_path):
    """A stress-free elastic block launched at u sideways and falling freely: its sideways
    kinetic energy stays ½ M u², its vertical one is the released potential energy ½ M (g t)²."""
    import axmpm
    from axmpm.cases.column_collapse.energy import sideways_energy

    u, g, t_end = 0.2, 10.0, 0.1
    scenario = {
        "simulation": {"formulation": "plane_strain", "shape_function": "linear", "end_time": t_end,
                       "output_interval": 0.05, "gravity": [0.0, -g], "flip_fraction": 1.0},
        "grid": {"extent": [0.3, 0.3], "cell_size": 0.01},
        "materials": {"m": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1e5,
                            "poisson_ratio": 0.3}},
        "bodies": [{"material": "m", "min": [0.05, 0.2], "max": [0.1, 0.25], "velocity": [u, 0.0]}],
    }
    summary = axmpm.run(scenario, tmp_path / "fall")
    assert summary["status"] == "completed"
    e = sideways_energy(tmp_path / "fall")
    # Released by the end: ½ M g² t (t + Δt) (the explicit step moves with the updated
    # velocity), the sideways peak ½ M u² and the vertical ½ M (g t)².
    t, dt = summary["end_time"], summary["dt"]
    # (rel 1e-4: the last step is cut to land on end_time; Δt/t itself is 3e-3)
    assert e["peak_sideways_share"] == pytest.approx(u ** 2 / (g ** 2 * t * (t + dt)), rel=1e-4)
    assert e["peak_vertical_share"] == pytest.approx(t / (t + dt), rel=1e-4)
    assert e["released_share_at_peak"] >= 0.0


def test_demo_names_the_model_it_runs():
    from axmpm.cases.column_collapse.demo import model_description

    assert model_description() == "Drucker-Prager (mu = 0.518 = tan 27.4 deg, Mohr-Coulomb section), F-bar"
    assert model_description({"mohr_coulomb_section": False, "volumetric_averaging": "none"}) == \
        "Drucker-Prager (mu = 0.518 = tan 27.4 deg)"
    assert model_description({"material_model": "mohr_coulomb", "friction_angle": 22.0,
                              "volumetric_averaging": "none"}) == "Mohr-Coulomb (phi 22, psi 0)"


@pytest.mark.parametrize("key, value", [("friction_angle", 22.45), ("dilation_angle", 5.0), ("cohesion", 10.0)])
def test_mohr_coulomb_keys_are_refused_with_the_other_models(key, value):
    # The default model is the cone: a Mohr–Coulomb key would silently change nothing (or only
    # the base), so the builder names it and the model instead.
    for model in ("drucker_prager", "granular_fluidity"):
        with pytest.raises(ValueError, match=f"{key}: is a mohr_coulomb parameter, and material_model is '{model}'"):
            collapse_scenario(0.8, material_model=model, **{key: value})
    assert collapse_scenario(0.8, material_model="mohr_coulomb", **{key: value}).materials["sand"].model \
        == "mohr_coulomb"


def test_a_mohr_coulomb_key_without_the_model_is_bad_input(tmp_path, capsys):
    from axmpm.cli import main

    out = tmp_path / "v"
    code = main(["validate", "--cases", "a056", "--out", str(out), "--set", "friction_angle=22"])
    assert code == 2
    err = capsys.readouterr().err
    assert "friction_angle: is a mohr_coulomb parameter" in err and "Traceback" not in err
    assert not (out / "cases").exists()


def test_validation_fails_when_a_run_did_not_complete_or_its_energy_budget_does_not_close():
    """The column collapse's enforced checks on fabricated records: a completed run with a
    residual of 1 % of the released energy passes, one with 6 % (energy created or lost by the
    scheme) fails, and a failed run fails; the laws are not among the checks."""
    from axmpm.cases.column_collapse.case import CASE, ENERGY_RESIDUAL_LIMIT

    def record(name, status, residual):
        return {"name": name, "status": status, "message": "particle left the grid" if status != "completed" else "",
                "energy": {"released": 0.5, "shares": {"energy_residual": residual}}}

    checks = CASE.checks([record("a", "completed", -0.01), record("b", "completed", 0.06),
                          record("c", "failed", None)])
    passed = {c["name"]: c["passed"] for c in checks}
    assert ENERGY_RESIDUAL_LIMIT == 0.05
    assert passed == {"a completed": True, "a: energy budget closes (residual within 5 % of the released energy)": True,
                      "b completed": True, "b: energy budget closes (residual within 5 % of the released energy)": False,
                      "c completed": False}
    assert all("lube" not in c["name"].lower() for c in checks)


def test_reports_score_the_runout_against_one_law_and_against_the_closer_law():
    """The status paragraph's two scores, by hand on fabricated records: against Lube et al. 2004
    alone |−5 %| and |+20 %| (mean 12.5 %, 1 of 2 within 10 %); against the closer law 5 % and
    8 % (mean 6.5 %, 2 of 2)."""
    from axmpm.cases.column_collapse.status import law_scores, status_text

    cases = [{"formulation": "axisymmetric", "laws": {"lube2004": {"runout_normalised_rel_diff": -0.05},
                                                      "lajeunesse2004_kk": {"runout_normalised_rel_diff": -0.30}}},
             {"formulation": "axisymmetric", "laws": {"lube2004": {"runout_normalised_rel_diff": 0.20},
                                                      "lajeunesse2004_kk": {"runout_normalised_rel_diff": -0.08}}},
             {"formulation": "axisymmetric", "status": "failed"}]
    from axmpm.cases.column_collapse.laws import TABLE_LAWS

    assert [law.key for law in TABLE_LAWS["axisymmetric"]] == ["lube2004", "lajeunesse2004_kk"]
    s = law_scores(cases)
    assert s["single_mean"] == pytest.approx(0.125) and (s["single_within"], s["single_runs"]) == (1, 2)
    assert s["closer_mean"] == pytest.approx(0.065) and (s["closer_within"], s["closer_runs"]) == (2, 2)
    text = status_text(cases)
    assert text.startswith("**Status: calibrated.**")
    assert "Lube et al. 2004 alone: mean |difference| 12.5 %, 1 of 2 within 10 %" in text
    assert "mean 6.5 %, 2 of 2 within 10 %" in text
    assert law_scores([cases[2]]) is None
