"""Rigid bodies, polygon bodies and Tresca from the front end (issue #13): scenario checks naming
the key (exit 2), particles cut out of the soil, history/summary/load_run columns, the footing
case's N_c from a run folder, and the run-time estimate of ``axmpm check``."""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from axmpm import load_run, run
from axmpm.cli import main
from axmpm.errors import ScenarioError
from axmpm.scenario import Scenario, apply_overrides


def footing(**simulation: object) -> dict:
    """A small half-strip footing on Tresca clay (a few hundred particles)."""
    return {
        "simulation": {"formulation": "plane_strain", "shape_function": "linear", "end_time": 0.05,
                       "output_interval": 0.025, "history_interval": 0.005, "gravity": [0.0, 0.0],
                       "volumetric_averaging": "cell", **simulation},
        "grid": {"extent": [1.0, 0.8], "cell_size": 0.05},
        "materials": {"clay": {"model": "mohr_coulomb", "density": 1800.0, "youngs_modulus": 3e6,
                               "poisson_ratio": 0.45, "friction_angle": 0.0, "cohesion": 10e3}},
        "bodies": [{"material": "clay", "min": [0.0, 0.0], "max": [1.0, 0.6]}],
        "rigid_bodies": [{"name": "footing", "shape": "polygon",
                          "vertices": [[0.0, 0.6], [0.25, 0.6], [0.25, 0.7], [0.0, 0.7]],
                          "motion": [[0.0, 0.0, 0.0], [0.01, 0.0, -0.5]], "friction": "rough"}],
        "boundaries": {"left": "roller", "right": "roller", "bottom": "fixed"},
    }


def errors_of(data: dict, *overrides: str) -> dict[str, str]:
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(apply_overrides(data, list(overrides)))
    return dict(info.value.errors)


BAD_INPUT = [
    ("rigid_bodies.0.vertices=[[0, 0.6], [0.25, 0.7], [0.25, 0.6], [0, 0.7]]", "rigid_bodies.0.vertices",
     "must be simple"),
    ("rigid_bodies.0.vertices=[[0, 0.6], [0.1, 0.6], [0.2, 0.6]]", "rigid_bodies.0.vertices", "degenerate"),
    ("rigid_bodies.0.vertices=[[0, 0.6], [0.25, 0.6], [0.25, 0.9], [0, 0.9]]", "rigid_bodies.0",
     "must lie inside the grid"),
    ("rigid_bodies.0.motion=[[0, 0, 0], [0.01, 0, -0.5], [0.01, 0, 0]]", "rigid_bodies.0.motion.2.0",
     "times must increase"),
    ("rigid_bodies.0.friction=-0.1", "rigid_bodies.0.friction", 'must be a number >= 0 or "rough"'),
    ("rigid_bodies.0.friction='sticky'", "rigid_bodies.0.friction", 'must be a number >= 0 or "rough"'),
    ("rigid_bodies.0.contact='glue'", "rigid_bodies.0.contact", "penalty"),
    ("rigid_bodies.0.contact='penalty'", "rigid_bodies.0.contact", "set experimental = true"),
    ("rigid_bodies.0.name='left'", "rigid_bodies.0.name", "grid face or wall"),
    ("rigid_bodies.0.name='a.b'", "rigid_bodies.0.name", "without dots"),
    ("rigid_bodies.0.shape='circle'", "rigid_bodies.0.shape", "unknown shape 'circle'"),
    ("rigid_bodies.0.min=[0, 0.6]", "rigid_bodies.0.min", "unknown key"),
    ("rigid_bodies.0.adhesion=-1", "rigid_bodies.0.adhesion", "must be a finite number >= 0 Pa"),
    ("rigid_bodies.0.adhesion_limit=0", "rigid_bodies.0.adhesion_limit", "must be a finite number > 0 Pa"),
    ("rigid_bodies.0.motion=[[0, 0, 1e308], [1, 0, 1e308]]", "rigid_bodies.0.motion",
     "carries the body out of the grid at t = "),
    ("grid.follow='pile'", "grid.follow", "must name a rigid body ('footing') (got 'pile')"),
    ("walls=[{axis='x', position=0.9, material_side='negative', condition='roller'}]", "grid.follow",
     "cannot be combined with walls"),
    ("grid.experimental=false", "grid.follow", "set grid.experimental = true"),
    ("materials.clay.cohesion=0", "materials.clay.friction_angle", "= 0 (Tresca) needs cohesion > 0"),
    ("materials.clay.dilation_angle=2", "materials.clay.dilation_angle", "<= friction_angle"),
]


@pytest.mark.parametrize("override,key,text", BAD_INPUT, ids=[b[1] + ":" + b[2] for b in BAD_INPUT])
def test_bad_rigid_body_input_names_the_key(override: str, key: str, text: str) -> None:
    data = footing()
    if key == "grid.follow":
        data["grid"].update(follow="footing", experimental=True)
    errors = errors_of(data, override)
    assert key in errors, errors
    assert text in errors[key], errors[key]


def test_every_refusal_of_a_moving_grid_is_reported() -> None:
    """The engine's follow_errors, each one under grid.follow (not only the first)."""
    data = footing()
    data["grid"]["follow"] = "pile"
    data["walls"] = [{"axis": "x", "position": 0.9, "material_side": "negative", "condition": "roller"}]
    data["bodies"][0]["saturated"] = {"porosity": 0.4, "hydraulic_conductivity": 1e-6}
    with pytest.raises(ScenarioError) as info:
        Scenario.from_dict(data)
    found = [message for key, message in info.value.errors if key == "grid.follow"]
    assert len(found) == 4, found
    for text in ("set grid.experimental = true", "must name a rigid body ('footing') (got 'pile')",
                 "cannot be combined with walls", "cannot be combined with saturated bodies"):
        assert any(text in message for message in found), (text, found)


def test_a_moving_grid_with_a_nonlocal_material_is_refused() -> None:
    data = footing()
    data["grid"].update(follow="footing", experimental=True)
    data["materials"]["grains"] = {"model": "granular_fluidity", "density": 1550.0, "youngs_modulus": 1e6,
                                   "poisson_ratio": 0.3, "experimental": True}
    Scenario.from_dict(data)  # defined but used by no body: accepted
    data["bodies"][0]["material"] = "grains"
    errors = errors_of(data)
    assert "non-local material" in errors["grid.follow"], errors


def test_radial_motion_in_axisymmetry_is_refused() -> None:
    data = footing()
    data["simulation"]["formulation"] = "axisymmetric"
    errors = errors_of(data, "rigid_bodies.0.motion=[[0, 0, 0], [0.01, 0.1, -0.5]]")
    assert "vx must be 0 in axisymmetric runs" in errors["rigid_bodies.0.motion.1.1"]
    errors = errors_of(data, "rigid_bodies.0.velocity=[0.2, 0]", "rigid_bodies.0.motion=[]")
    assert "rigid_bodies.0.velocity.0" in errors or "rigid_bodies.0.motion" in errors


def test_cli_check_exits_2_naming_the_key(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import tomli_w

    data = apply_overrides(footing(), ["rigid_bodies.0.motion=[[0, 0, 0], [0, 0, -1]]"])
    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(data))
    assert main(["check", str(path), "--no-estimate"]) == 2
    assert "error: rigid_bodies.0.motion.1.0: times must increase" in capsys.readouterr().err


def test_a_path_out_of_the_grid_exits_2_naming_the_key_and_the_time(tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    import tomli_w

    # The footing's top (0.7 m) reaches the grid's (0.8 m) after 10 ms of the ramp to 0.5 m/s
    # up (2.5 mm) and 0.195 s more: t = 0.205 s, before end_time = 0.5 s.
    data = apply_overrides(footing(end_time=0.5), ["rigid_bodies.0.motion=[[0, 0, 0], [0.01, 0, 0.5]]"])
    path = tmp_path / "out.toml"
    path.write_text(tomli_w.dumps(data))
    assert main(["check", str(path), "--no-estimate"]) == 2
    err = capsys.readouterr().err
    assert "error: rigid_bodies.0.motion: the prescribed path carries the body out of the grid at t = 2.05" in err, err
    assert "Traceback" not in err


def test_no_particle_is_created_inside_a_rigid_body_and_polygon_bodies_fill_their_lattice() -> None:
    data = footing()
    # A pre-embedded pile and a sloping polygon body.
    data["rigid_bodies"].append({"name": "pile", "shape": "rectangle", "min": [0.6, 0.3], "max": [0.7, 0.7],
                                 "velocity": [0.0, 0.0]})
    data["bodies"].append({"material": "clay", "shape": "polygon", "allow_overlap": True,
                           "vertices": [[0.5, 0.6], [1.0, 0.6], [1.0, 0.75]]})
    s = Scenario.from_dict(data)
    positions = s.particle_positions()
    for body in s.rigid_bodies:
        for p in positions:
            assert not body.contains(p).any()
    # The soil block loses the pile's 2 × 6 cells (48 particles); the triangle keeps the lattice
    # points inside it: area 0.0375 m² = 15 cells of 4 → about 60.
    assert len(positions[0]) == 20 * 12 * 4 - 2 * 6 * 4
    assert abs(len(positions[1]) - 60) <= 8
    from axmpm._core import Simulation

    sim = Simulation(s.engine_json(), 1)
    assert sim.num_particles == s.particle_count() == sum(len(p) for p in positions)


def test_history_summary_and_load_run_report_the_rigid_body(tmp_path: Path) -> None:
    from axmpm import run

    summary = run(Scenario.from_dict(footing()), tmp_path / "run", threads=1)
    assert summary["status"] == "completed"
    r = load_run(tmp_path / "run")
    body = r.rigid_bodies["footing"]
    times = r.history["time"]
    assert len(times) == 11  # every 5 ms: history_interval between the 3 frames
    # Displacement: the integral of the ramp 0 → 0.5 m/s over 10 ms, then 0.5 m/s.
    expect = np.where(times <= 0.01, 0.5 * 0.5 * times**2 / 0.01, 0.5 * (times - 0.005))
    assert np.allclose(-body["displacement"][:, 1], expect, rtol=1e-12, atol=1e-15)
    # The footing bears on the clay, mostly through its base; the rough shaft (the side x = 0.25 m,
    # whose normal is horizontal) carries load only by friction, so its vertical force is a
    # minor, positive share, and the rough base also takes the clay's outward shear (force_x).
    assert body["force"][-1, 1] > 0.0
    assert body["base_force"][-1, 1] > 5.0 * body["shaft_force"][-1, 1] > 0.0
    assert body["base_force"][-1, 0] > 0.0
    assert np.array_equal(r.reactions["footing"], body["force"])
    saved = json.loads((tmp_path / "run" / "summary.json").read_text())["rigid_bodies"]["footing"]
    assert saved["displacement"][1] == pytest.approx(-0.5 * 0.045)
    assert saved["force"] == pytest.approx(list(body["force"][-1]))


def test_a_smooth_footing_pushes_only_along_the_normals_of_its_faces(tmp_path: Path) -> None:
    """Without friction the contact removes only the normal part of the soil's velocity: the flat
    base (normal −y) takes no horizontal force, and the vertical side takes no vertical force, so
    the vertical load is the base's and the side's push is horizontal."""
    data = footing()
    data["rigid_bodies"][0]["friction"] = 0.0
    run(Scenario.from_dict(data), tmp_path / "run", threads=1)
    body = load_run(tmp_path / "run").rigid_bodies["footing"]
    assert body["force"][-1, 1] > 0.0
    assert np.all(body["base_force"][:, 0] == 0.0) and np.all(body["shaft_force"][:, 1] == 0.0)
    assert np.allclose(body["base_force"][:, 1], body["force"][:, 1], rtol=1e-12, atol=0.0)


def test_footing_case_reads_nc_from_a_run_folder(tmp_path: Path) -> None:
    from axmpm import run
    from axmpm.cases.footing.scenario import bearing_capacity_factor, load_settlement

    # A fabricated history: 0.001B per row, q/s_u rising to 5 over 0.02B then flat at 5 ± 0.2.
    s = np.arange(0, 0.0705, 0.001)
    nc = np.minimum(5.0, 250.0 * s) + 0.2 * np.sin(1000.0 * s)
    mid = 0.5 * (s[1:] + s[:-1])
    window = (mid >= 0.04 - 1e-9) & (mid <= 0.06 + 1e-9)
    assert bearing_capacity_factor(mid, nc[1:]) == pytest.approx(np.mean(nc[1:][window]))
    assert bearing_capacity_factor(mid[mid < 0.05], nc[1:][mid < 0.05]) is None  # did not reach 0.06B
    # From a real (short) run folder: the curve starts at zero load and rises.
    run(Scenario.from_dict(footing()), tmp_path / "run", threads=1)
    settlement, q = load_settlement(tmp_path / "run", "plane_strain")
    assert settlement[0] > 0.0 and np.all(np.diff(settlement) > 0.0)
    assert q[-1] > q[0] > 0.0


def test_check_estimates_the_run_time(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import tomli_w

    path = tmp_path / "footing.toml"
    path.write_text(tomli_w.dumps(footing()))
    assert main(["check", str(path), "--threads", "1"]) == 0
    out = capsys.readouterr().out
    s = Scenario.from_dict(footing())
    c_p = math.sqrt(3e6 * 0.55 / (1.45 * 0.1) / 1800.0)  # (λ + 2μ)/ρ with ν = 0.45
    dt = 0.4 * 0.05 / c_p
    assert f"time step {dt:.4g} s" in out
    assert f"{math.ceil(0.05 / dt):,} steps" in out
    assert f"{s.particle_count():,} particles" in out
    assert "particle-steps/s" in out and "of run time" in out


def test_tresca_defaults_have_no_tension_cutoff() -> None:
    s = Scenario.from_dict(footing())
    clay = s.materials["clay"]
    assert clay.tension_cutoff is None and clay.dilation_angle == 0.0
    assert "tension_cutoff" not in s.to_toml()
    assert json.loads(s.engine_json())["materials"]["clay"]["tension_cutoff"] is None
    data = footing()
    data["materials"]["clay"]["friction_angle"] = 25.0
    assert Scenario.from_dict(data).materials["clay"].tension_cutoff == 0.0


def _pile_example():
    import importlib.util

    root = Path(__file__).resolve().parents[1]
    spec = importlib.util.spec_from_file_location("pile_load_test", root / "examples" / "pile_load_test.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return root / "examples" / "pile_load_test.toml", module


def test_pile_example_berezantzev_estimate() -> None:
    """Between the chart's readings (Berezantzev et al. 1961 as reproduced by Tomlinson: N_q =
    27.5 and 39.8 at φ = 30° and 32°, L/D = 10; 36.3 and 27.5 at L/D = 5 and 10, φ = 30°) the
    lookup is log-linear in φ and in log(L/D), so half-way it is the geometric mean of the two
    readings; beyond the chart it is clamped. The example's base estimate is N_q γ L π r² from
    its own scenario."""
    toml_path, pile = _pile_example()
    assert pile.berezantzev_nq(31.0, 10.0) == pytest.approx(math.sqrt(27.5 * 39.8), rel=1e-9)
    assert pile.berezantzev_nq(30.0, math.sqrt(50.0)) == pytest.approx(math.sqrt(36.3 * 27.5), rel=1e-9)
    assert pile.berezantzev_nq(40.0, 10.0) == pytest.approx(pile.berezantzev_nq(36.0, 10.0), rel=1e-12)
    assert pile.berezantzev_nq(31.0, 10.0) > pile.berezantzev_nq(30.0, 10.0) > pile.berezantzev_nq(30.0, 14.0)
    import shutil
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        shutil.copy(toml_path, Path(tmp) / "scenario.toml")
        est = pile.textbook_estimates(Path(tmp))
    assert est["embedment_ratio"] == pytest.approx(10.0)
    assert est["base"] == pytest.approx(27.5 * 1800.0 * 9.81 * 5.0 * np.pi * 0.25**2, rel=1e-9)
    assert est["shaft"] == pytest.approx(0.5 * 0.364 * 1800.0 * 9.81 * 12.5 * 2.0 * np.pi * 0.25, rel=1e-9)


def test_pile_example_carries_the_geostatic_load_before_the_push(tmp_path: Path) -> None:
    """The pile load test on a coarse grid, stopped before the push: the base carries the
    geostatic vertical stress ρ g L over the tip area and the shaft carries nothing."""
    toml_path, _ = _pile_example()
    data = tomllib.loads(toml_path.read_text())
    data["grid"]["cell_size"] = 0.125
    data["simulation"].update(end_time=0.25, output_interval=0.25, history_interval=0.05)
    run(Scenario.from_dict(data), tmp_path / "run", threads=1)
    pile = load_run(tmp_path / "run").rigid_bodies["pile"]
    geostatic = 1800.0 * 9.81 * 5.0 * np.pi * 0.25**2
    assert pile["base_force"][-1, 1] == pytest.approx(geostatic, rel=0.02)
    assert abs(pile["shaft_force"][-1, 1]) < 0.05 * geostatic
    assert np.all(pile["displacement"][:, 1] == 0.0)


def test_a_grid_that_follows_the_footing_moves_with_it(tmp_path: Path) -> None:
    """``grid.follow``: the engine steps on a grid one row taller than the scenario's, placed at
    the footing's displacement modulo a cell; the run completes and the footing carries load."""
    data = footing(end_time=0.2, output_interval=0.1)
    data["grid"].update(follow="footing", experimental=True)
    summary = run(Scenario.from_dict(data), tmp_path / "run", threads=1)
    assert summary["status"] == "completed", summary["message"]
    assert summary["grid_shape"] == [21, 18], "21 × 17 nodes in the scenario, one row more"
    body = load_run(tmp_path / "run").rigid_bodies["footing"]
    # 0.5 m/s after a 10 ms ramp: 97.5 mm in 0.2 s, about two cells of 50 mm.
    assert body["displacement"][-1, 1] == pytest.approx(-0.0975, rel=1e-9)
    assert body["force"][-1, 1] > 0.0


def driven_footing() -> dict:
    """The footing of :func:`footing` driven by a force instead of its motion."""
    data = footing()
    body = data["rigid_bodies"][0]
    del body["motion"]
    body.update(mass=100.0, force=[[0.0, 0.0, 0.0], [0.01, 0.0, -1e3]])
    return data


BAD_DRIVEN_INPUT = [
    ("rigid_bodies.0.mass=0", "rigid_bodies.0.mass", "must be a finite number > 0 kg"),
    ("rigid_bodies.0.mass=-5", "rigid_bodies.0.mass", "must be a finite number > 0 kg"),
    ("rigid_bodies.0.mass=nan", "rigid_bodies.0.mass", "finite"),
    ("rigid_bodies.0.force=[[0, 0, 0], [0, 0, -1]]", "rigid_bodies.0.force.1.0", "times must increase"),
    ("rigid_bodies.0.force=[[0, 0, nan]]", "rigid_bodies.0.force.0.2", "finite"),
    ("rigid_bodies.0.force=[[0, 1, -1]]", "rigid_bodies.0.force.0.1", "grid's left edge"),
    ("rigid_bodies.0.initial_velocity=[0.1, 0]", "rigid_bodies.0.initial_velocity.0", "grid's left edge"),
    ("rigid_bodies.0.velocity=[0, -1]", "rigid_bodies.0.velocity", "not both"),
]


@pytest.mark.parametrize("override,key,text", BAD_DRIVEN_INPUT, ids=[b[0] for b in BAD_DRIVEN_INPUT])
def test_bad_force_driven_input_names_the_key(override: str, key: str, text: str) -> None:
    errors = errors_of(driven_footing(), override)
    assert key in errors, errors
    assert text in errors[key], errors[key]


def test_a_force_driven_footing_runs_and_reports_its_velocity(tmp_path: Path) -> None:
    """The driven footing runs; history has its displacement and velocity (the rate of its
    displacement between rows, to the step's noise), and the budget books its work."""
    run(Scenario.from_dict(driven_footing()), tmp_path / "run", threads=1)
    history = np.genfromtxt(tmp_path / "run" / "history.csv", delimiter=",", names=True)
    d, v, t = history["footingdisplacement_y"], history["footingvelocity_y"], history["time"]
    assert d[-1] < 0.0 and "footingvelocity_x" in history.dtype.names
    rate = np.diff(d) / np.diff(t)
    assert np.all(np.abs(v[1:] - rate) < 0.5 * np.abs(rate).max() + 1e-6), (v, rate)
    assert history["rigid_body_work"][-1] > 0.0
