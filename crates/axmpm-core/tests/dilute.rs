//! Issue 15, the a = 10 collapse at 30 cells per radius: Mohr–Coulomb material dilated
//! stress-free far beyond its placed volume (J = V/V0 ≫ 1) and then re-compressed was
//! integrated with the moduli of the material as placed, i.e. with a P-wave speed c0 √J far
//! beyond the one the time step was built for, and blew up. Here a block is put into that
//! state directly (its particles' volumes and deformation gradients set to J = 100 through a
//! checkpoint) and squeezed: without the limit of `Material::limit_wave_speed` (mohr_coulomb.rs,
//! "Dilute material and the time step") its velocities grow without bound within a few hundred
//! steps; with it the squeeze stays the smooth motion it started as.

mod common;
use axmpm_core::config::*;
use axmpm_core::Simulation;
use common::*;
use serde_json::Value;

fn dilute_block(jacobian: f64) -> Simulation {
    let mut cfg = block(FormulationKind::PlaneStrain, ShapeFunctionKind::Linear, [0.0, 0.0], [0.0, 0.0]);
    let mut sand = MaterialConfig::elastic("mohr_coulomb", 1550.0, 1e6, 0.3);
    sand.set("friction_angle", 30.0).set("dilation_angle", 0.0).set("cohesion", 0.0);
    cfg.materials.clear();
    cfg.materials.insert("m".into(), sand);
    cfg.bodies[0] = BodyConfig::rectangle("m", [0.6, 0.6], [1.4, 1.4]);
    let sim = Simulation::new(cfg, 1).unwrap();
    // The same particles, dilated stress-free to J (isotropically: F = √J I in-plane) and
    // converging on the block's centre at 0.05 m/s per 0.1 m: a volumetric strain rate of −1/s.
    let mut checkpoint: Value = serde_json::from_slice(&sim.to_bytes().unwrap()).unwrap();
    let p = &mut checkpoint["particles"];
    let n = p["position"].as_array().unwrap().len();
    let stretch = jacobian.sqrt();
    for i in 0..n {
        let x = [p["position"][i][0].as_f64().unwrap(), p["position"][i][1].as_f64().unwrap()];
        p["velocity"][i] = serde_json::json!([-0.5 * (x[0] - 1.0), -0.5 * (x[1] - 1.0)]);
        p["deformation_gradient"][i] = serde_json::json!([stretch, 0.0, 0.0, stretch, 1.0]);
        let v0 = p["initial_volume"][i].as_f64().unwrap();
        p["volume"][i] = serde_json::json!(v0 * jacobian);
        p["stress"][i] = serde_json::json!([0.0, 0.0, 0.0, 0.0]);
    }
    Simulation::from_bytes(&serde_json::to_vec(&checkpoint).unwrap(), 1).unwrap()
}

fn max_speed(sim: &Simulation) -> f64 {
    sim.particles().velocity.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max)
}

#[test]
fn a_dilute_block_squeezed_stays_stable() {
    // J = 100: c0 √J = 10 c0, a Courant number of 4 at cfl = 0.4 without the limit.
    let mut sim = dilute_block(100.0);
    let start = max_speed(&sim);
    assert!(start > 0.2 && start < 0.3, "{start}");
    let result = sim.advance(1e9, 400);
    let end = max_speed(&sim);
    assert!(result.is_ok(), "the run failed: {result:?}");
    // The squeeze builds a little pressure (J ≫ the limit: the moduli scaled by J_s/J) that
    // slows it; a blow-up reaches any bound.
    assert!(end.is_finite() && end < 2.0 * start, "max speed {start} → {end}");
}
