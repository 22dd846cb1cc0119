//! Issue 15, the plane-strain a = 10 collapse that threw particles out of the grid: a lone,
//! dilute (J = 100), compressed particle resting on a frictional base. The base's correction of v⁺ removes the
//! half of its internal force that points into the base, so the other half lifts it; if the
//! MUSL re-mapped velocities then let the base nodes go (the particle's velocity now points
//! away from the base), all its nodes carry one velocity, its strain rate is zero and its
//! stress never relaxes: it accelerates at J σ/(ρ0 h) for ever, creating energy. With the
//! base's contact state of v⁺ kept for the re-map (`ConstrainedNodes::correct_remapped`) it
//! lengthens as it leaves, its stress relaxes, and it flies off stress-free at a constant speed.

mod common;
use axmpm_core::config::*;
use axmpm_core::Simulation;
use common::*;
use serde_json::Value;

const DENSITY: f64 = 1000.0;
const YOUNGS_MODULUS: f64 = 1e6;
const POISSON_RATIO: f64 = 0.3;
/// The particle's (isotropic) stress, Pa (compression).
const STRESS_YY: f64 = -1000.0;

/// One cohesionless Mohr–Coulomb particle (one per 0.1 m cell) at (1.05, 0.05) on a
/// frictional bottom face, no gravity, at rest, dilated to J = 100 (F = diag(10, 10, 1)) and
/// carrying an isotropic stress STRESS_YY (elastic: on the hydrostatic axis), set through a
/// checkpoint, in `shape`.
fn pressed_particle(shape: ShapeFunctionKind) -> Simulation {
    let mut cfg = block(FormulationKind::PlaneStrain, shape, [0.0, 0.0], [0.0, 0.0]);
    let mut sand = material("mohr_coulomb", DENSITY, YOUNGS_MODULUS, POISSON_RATIO);
    sand.set("friction_angle", 30.0).set("dilation_angle", 0.0).set("cohesion", 0.0);
    cfg.materials.insert("m".into(), sand);
    cfg.bodies[0] = BodyConfig { particles_per_cell: 1, ..BodyConfig::rectangle("m", [1.0, 0.0], [1.1, 0.1]) };
    cfg.boundaries.bottom = BoundaryCondition::friction(0.5);
    let sim = Simulation::new(cfg, 1).unwrap();
    let mut checkpoint: Value = serde_json::from_slice(&sim.to_bytes().unwrap()).unwrap();
    let p = &mut checkpoint["particles"];
    assert_eq!(p["position"].as_array().unwrap().len(), 1);
    p["stress"][0] = serde_json::json!([STRESS_YY, STRESS_YY, STRESS_YY, 0.0]);
    p["deformation_gradient"][0] = serde_json::json!([10.0, 0.0, 0.0, 10.0, 1.0]);
    let v0 = p["initial_volume"][0].as_f64().unwrap();
    p["volume"][0] = serde_json::json!(100.0 * v0);
    Simulation::from_bytes(&serde_json::to_vec(&checkpoint).unwrap(), 1).unwrap()
}

fn speed(sim: &Simulation) -> f64 {
    let v = sim.particles().velocity[0];
    v[0].hypot(v[1])
}

#[test]
fn a_pressed_particle_pushes_off_the_base_once_and_relaxes() {
    for shape in [ShapeFunctionKind::Linear, ShapeFunctionKind::Cpgimp] {
        let mut sim = pressed_particle(shape);
        let mut speeds = Vec::new();
        for t in [0.1, 0.3] {
            sim.advance(t, 1_000_000).unwrap_or_else(|e| panic!("{shape:?}: {e:?}"));
            speeds.push(speed(&sim));
        }
        let p = sim.particles();
        eprintln!("{shape:?}: speeds {speeds:?}, y = {}, stress {:?}", p.position[0][1], p.stress[0]);
        // Pushed off (its stored energy becomes motion)...
        assert!(speeds[0] > 0.01, "{shape:?}: the particle did not leave the base: {speeds:?}");
        // ... then flies stress-free at a constant speed (no gravity). Without the kept
        // contact its stress stays −1 kPa and it accelerates at ≈ 19 m/s² (5.7 m/s at 0.3 s).
        assert!(p.stress[0].iter().all(|s| s.abs() < 1e-6), "{shape:?}: stress {:?} not relaxed", p.stress[0]);
        assert!((speeds[1] - speeds[0]).abs() <= 1e-9 * speeds[0], "{shape:?}: still accelerating: {speeds:?}");
    }
}
