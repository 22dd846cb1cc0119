//! Mohr–Coulomb material dilated stress-free far beyond its placed volume (J = V/V0 ≫ 1) and
//! then re-compressed, integrated with the moduli of the material as placed, has a P-wave speed
//! c0 √J far beyond the one the time step was built for, and blows up. Here a block is put into that
//! state directly (its particles' volumes and deformation gradients set to J = 100 through a
//! checkpoint) and squeezed: without the limit of `Material::limit_wave_speed` (mohr_coulomb.rs,
//! "Dilute material and the time step") its velocities grow without bound within a few hundred
//! steps; with it the squeeze stays the smooth motion it started as.

mod common;
use axmpm_core::config::*;
use axmpm_core::simulation::COURANT_LIMIT;
use axmpm_core::Simulation;
use common::*;
use serde_json::Value;

fn sand() -> MaterialConfig {
    let mut sand = MaterialConfig::elastic("mohr_coulomb", 1550.0, 1e6, 0.3);
    sand.set("friction_angle", 30.0).set("dilation_angle", 0.0).set("cohesion", 0.0);
    sand
}

fn dilute_block(jacobian: f64) -> Simulation {
    block_of(sand(), |_| jacobian)
}

/// The block of `sand`, each particle dilated stress-free to `jacobian(x)` at its position x
/// and squeezed towards the centre (module doc).
fn block_of(sand: MaterialConfig, jacobian: impl Fn([f64; 2]) -> f64) -> Simulation {
    let mut cfg = block(FormulationKind::PlaneStrain, ShapeFunctionKind::Linear, [0.0, 0.0], [0.0, 0.0]);
    cfg.materials.clear();
    cfg.materials.insert("m".into(), sand);
    cfg.bodies[0] = BodyConfig::rectangle("m", [0.6, 0.6], [1.4, 1.4]);
    let sim = Simulation::new(cfg, 1).unwrap();
    // The same particles, dilated stress-free to J (isotropically: F = √J I in-plane) and
    // converging on the block's centre at 0.05 m/s per 0.1 m: a volumetric strain rate of −1/s.
    let mut checkpoint: Value = serde_json::from_slice(&sim.to_bytes().unwrap()).unwrap();
    let p = &mut checkpoint["particles"];
    let n = p["position"].as_array().unwrap().len();
    for i in 0..n {
        let x = [p["position"][i][0].as_f64().unwrap(), p["position"][i][1].as_f64().unwrap()];
        let jacobian = jacobian(x);
        let stretch = jacobian.sqrt();
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

fn jacobian_of(f: &[f64; 5]) -> f64 {
    (f[0] * f[3] - f[1] * f[2]) * f[4]
}

/// Where the limit sets in is the step's stability limit: J_s = (c_max/c0)² with
/// c_max = COURANT_LIMIT h/Δt (simulation.rs) and c0 = √((λ + 2μ)/ρ0) of the material as
/// placed. One step of the squeeze from σ = 0 (same grid velocities whatever J: the stress is
/// zero, the masses are the same): a block at J = 2 < J_s gets, bit for bit, the stresses of
/// the block as placed (J = 1); at J = 10 > J_s they are s = J_s/J times those (the elastic
/// increment scaled; the cohesionless return is homogeneous in the trial stress).
#[test]
fn the_limit_sets_in_at_the_steps_stability_jacobian() {
    let one_step = |jacobian: f64| {
        let mut sim = dilute_block(jacobian);
        assert_eq!(sim.advance(1e9, 1), Ok(1));
        sim
    };
    let placed = one_step(1.0);
    let (e, nu, rho): (f64, f64, f64) = (1e6, 0.3, 1550.0);
    let c0 = (e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)) / rho).sqrt();
    let stable = (COURANT_LIMIT * placed.grid().cell_size / (placed.dt() * c0)).powi(2);
    assert!((stable - (COURANT_LIMIT / 0.4).powi(2)).abs() < 1e-9, "J_s = {stable} at cfl = 0.4");
    let reference = placed.particles().stress.clone();
    let scale = reference.iter().flatten().fold(0.0f64, |m, s| m.max(s.abs()));
    assert!(scale > 0.0, "the squeeze loads the block");

    let below = one_step(2.0);
    assert!(below.particles().deformation_gradient.iter().all(|f| jacobian_of(f) < stable));
    assert_eq!(below.particles().stress, reference, "below J_s: unchanged, bit for bit");

    let above = one_step(10.0);
    let particles = above.particles();
    for (i, (s, f)) in particles.stress.iter().zip(&particles.deformation_gradient).enumerate() {
        let ratio = stable / jacobian_of(f);
        assert!(ratio < 0.4, "particle {i}: J = {} above J_s", jacobian_of(f));
        for c in 0..4 {
            assert!((s[c] - ratio * reference[i][c]).abs() <= 1e-9 * scale,
                    "particle {i}, component {c}: {} vs {ratio} × {}", s[c], reference[i][c]);
        }
    }
}

/// The disconnection test through the solver reads each particle's own J: every background cell
/// holds two particles at J = 1 and two at J = 3 (a checkerboard of the 2 × 2 particles per
/// cell); with J_c = 1.5 or 2.5 the dense ones stay connected (compressed after one step of the
/// squeeze) and the loose ones are stress-free.
#[test]
fn disconnection_reads_each_particles_own_jacobian() {
    let h = 0.1; // the block's cell size
    let checkerboard = |x: [f64; 2]| {
        let (i, j) = ((x[0] / (0.5 * h)).floor() as i64, (x[1] / (0.5 * h)).floor() as i64);
        if (i + j) % 2 == 0 { 1.0 } else { 3.0 }
    };
    // J_c → whether the dense and the loose particles stay connected.
    for (jc, dense_connected, loose_connected) in [(1.5, true, false), (2.5, true, false)] {
        let mut m = sand();
        m.set("grain_density", 2500.0).set("critical_packing_fraction", 1550.0 / 2500.0 / jc).set("experimental", true);
        let mut sim = block_of(m, checkerboard);
        let start = sim.particles().deformation_gradient.iter().map(jacobian_of).collect::<Vec<_>>();
        assert_eq!(start.iter().filter(|&&j| j < 2.0).count() * 2, start.len(), "half dense, half loose");
        assert_eq!(sim.advance(1e9, 1), Ok(1));
        for (i, (s, j)) in sim.particles().stress.iter().zip(&start).enumerate() {
            let connected = if *j < 2.0 { dense_connected } else { loose_connected };
            if connected {
                assert!(s[0] + s[1] + s[2] < 0.0, "J_c = {jc}: particle {i} (J = {j}) compressed: {s:?}");
            } else {
                assert_eq!(*s, [0.0; 4], "J_c = {jc}: particle {i} (J = {j}) stress-free");
            }
        }
    }
}
