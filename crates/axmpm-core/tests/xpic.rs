//! XPIC(m), the filter of the non-FLIP share of the velocity update (solver/xpic.rs): exact for
//! uniform motion, momentum-conserving, thread-count independent, and far less dissipative
//! than PIC for smooth motion.

mod common;
use axmpm_core::config::*;
use axmpm_core::Simulation;
use common::*;

/// Free fall under gravity is exact whatever the order: v* of a uniform field is the field
/// itself only if the binomial coefficients of the sum add up to one (Σ_k (−1)^{k+1} C(m, k) = 1).
#[test]
fn free_fall_is_exact_with_every_order() {
    for m in [2, 3, 5] {
        for flip in [0.0, 0.5] {
            for f in ALL_FORMULATIONS {
                for s in ALL_SHAPES {
                    let mut cfg = block(f, s, [0.0, -9.81], [0.0, 1.0]);
                    cfg.simulation.time_step = 1e-3;
                    cfg.simulation.flip_fraction = flip;
                    cfg.simulation.xpic_order = m;
                    cfg.simulation.experimental = true;
                    let mut sim = Simulation::new(cfg, 1).unwrap();
                    let t = 0.1;
                    sim.advance(t, u64::MAX).unwrap();
                    let p = sim.particles();
                    let v = 1.0 - 9.81 * t;
                    for i in 0..p.len() {
                        assert!((p.velocity[i][1] - v).abs() < 1e-8, "m {m} FLIP {flip} {f:?} {s:?}: {:?}", p.velocity[i]);
                        assert!(p.velocity[i][0].abs() < 1e-8, "m {m} FLIP {flip} {f:?} {s:?}: {:?}", p.velocity[i]);
                    }
                }
            }
        }
    }
}

/// Two elastic blocks colliding head-on in plane strain, no boundaries: the total momentum is
/// conserved with pure XPIC(3) (Σ_i m_i (G w)_i = Σ_i m_i w_i for the lumped round trip G), and
/// the collision does make the velocity field non-uniform (the filter is not idle).
#[test]
fn momentum_is_conserved_through_a_collision() {
    for s in ALL_SHAPES {
        let mut cfg = block(FormulationKind::PlaneStrain, s, [0.0, 0.0], [3.0, 0.5]);
        cfg.bodies.push(BodyConfig { velocity: [-2.0, 0.0], ..BodyConfig::rectangle("m", [1.05, 0.7], [1.35, 1.1]) });
        cfg.simulation.flip_fraction = 0.0;
        cfg.simulation.xpic_order = 3;
        cfg.simulation.experimental = true;
        let mut sim = Simulation::new(cfg, 1).unwrap();
        let p0 = material_momentum(&sim);
        sim.advance(0.1, u64::MAX).unwrap();
        let p1 = material_momentum(&sim);
        let scale = p0[0].abs() + p0[1].abs();
        assert!((p1[0] - p0[0]).abs() < 1e-10 * scale && (p1[1] - p0[1]).abs() < 1e-10 * scale, "{s:?}: {p0:?} -> {p1:?}");
        let vx: Vec<f64> = sim.particles().velocity.iter().map(|v| v[0]).collect();
        let spread = vx.iter().cloned().fold(f64::MIN, f64::max) - vx.iter().cloned().fold(f64::MAX, f64::min);
        assert!(spread > 1.0, "{s:?}: the blocks did not collide (spread of v_x {spread})");
    }
}

/// An elastic column dropped on a roller base oscillates (as in tests/energy.rs). With the whole
/// velocity update from the filter (FLIP share 0), PIC = XPIC(1) dissipates much of the motion;
/// each higher order dissipates less: the energy the scheme lost after 0.5 s falls with m, and
/// XPIC(4) loses less than a quarter of what PIC loses.
#[test]
fn dissipation_of_smooth_motion_falls_with_the_order() {
    for formulation in ALL_FORMULATIONS {
        let lost = |m: u32| {
            let mut cfg = block(formulation, ShapeFunctionKind::Cpgimp, [0.0, -9.81], [0.0, 0.0]);
            cfg.materials.get_mut("m").unwrap().set("youngs_modulus", 2e5);
            cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [0.6, 1.2], cell_size: 0.05, follow: None, experimental: false };
            cfg.bodies[0].set_rectangle([0.0, 0.0], [0.2, 1.0]);
            cfg.boundaries.bottom = BoundaryCondition::ROLLER;
            cfg.boundaries.left = BoundaryCondition::ROLLER;
            cfg.simulation.flip_fraction = 0.0;
            cfg.simulation.xpic_order = m;
                    cfg.simulation.experimental = true;
            let mut sim = Simulation::new(cfg, 1).unwrap();
            sim.advance(0.5, u64::MAX).unwrap();
            let e = sim.energies();
            e.residual() / e.gravity_work
        };
        let losses: Vec<f64> = [1, 2, 4].into_iter().map(lost).collect();
        assert!(losses[0] > 0.0, "{formulation:?}: PIC lost {}", losses[0]);
        assert!(losses[0] > losses[1] && losses[1] > losses[2], "{formulation:?}: {losses:?}");
        assert!(losses[2] < 0.25 * losses[0], "{formulation:?}: {losses:?}");
    }
}

/// A block flying through the grid at about its wave speed, so that particles leave their
/// tiles' zones between sorts (the scatter's one-thread part): XPIC(3) results are bit for bit
/// the same on 1, 2 and 5 threads.
#[test]
fn xpic_is_bit_identical_on_any_thread_count() {
    for s in [ShapeFunctionKind::Cpgimp, ShapeFunctionKind::Cpdi2] {
        let mut cfg = block(FormulationKind::PlaneStrain, s, [0.0, 0.0], [0.0, 0.0]);
        cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [0.64, 0.64], cell_size: 0.01, follow: None, experimental: false };
        cfg.bodies[0] = BodyConfig { particles_per_cell: 2, ..BodyConfig::rectangle("m", [0.05, 0.05], [0.35, 0.3]) };
        cfg.bodies[0].velocity = [36.0, 10.0];
        cfg.bodies.push(BodyConfig { particles_per_cell: 2, ..BodyConfig::rectangle("m", [0.4, 0.1], [0.6, 0.5]) });
        cfg.simulation.flip_fraction = 0.5;
        cfg.simulation.xpic_order = 3;
        cfg.simulation.experimental = true;
        let run = |threads| {
            let mut sim = Simulation::new(cfg.clone(), threads).unwrap();
            sim.advance(1e9, 60).unwrap();
            fingerprint(&sim)
        };
        let one = run(1);
        assert_eq!(one, run(2), "{s:?}");
        assert_eq!(one, run(5), "{s:?}");
    }
}

/// Orders outside [1, 8], and orders above 1 without `simulation.experimental`, are refused,
/// naming the key.
#[test]
fn bad_orders_are_refused() {
    for (m, experimental) in [(0, true), (9, true), (2, false)] {
        let mut cfg = block(FormulationKind::PlaneStrain, ShapeFunctionKind::Linear, [0.0, 0.0], [0.0, 0.0]);
        cfg.simulation.xpic_order = m;
        cfg.simulation.experimental = experimental;
        let err = Simulation::new(cfg, 1).err().expect("refused");
        assert!(err.contains("simulation.xpic_order"), "{err}");
        assert_eq!(err.contains("experimental"), !experimental, "{err}");
    }
}

/// A configuration that does not name the order gets PIC (order 1) and is accepted without
/// `simulation.experimental`.
#[test]
fn the_default_order_is_pic() {
    let cfg = block(FormulationKind::PlaneStrain, ShapeFunctionKind::Linear, [0.0, 0.0], [0.0, 0.0]);
    let mut json = serde_json::to_value(&cfg).unwrap();
    let simulation = json["simulation"].as_object_mut().unwrap();
    assert!(simulation.remove("xpic_order").is_some() && simulation.remove("experimental").is_some());
    let parsed: Config = serde_json::from_value(json.clone()).unwrap();
    assert_eq!(parsed.simulation.xpic_order, 1);
    assert!(!parsed.simulation.experimental);
    assert!(Simulation::from_json(&json.to_string(), 1).is_ok());
}
