//! The energy budget (`Simulation::energies`, issue 15): each term from its own accumulation
//! (kinetic from the particle velocities, released potential from the displacements, stored
//! elastic from the stresses, plastic work from the stress returns, boundary dissipation from
//! the constraints' v⁺ corrections), so that the residual is what the scheme itself loses.

mod common;
use axmpm_core::config::*;
use axmpm_core::Simulation;
use common::*;

const G: f64 = 9.81;

/// A 0.4 m × 0.2 m elastic block (ρ = 1000, E = 10 MPa, geostatic start so it does not
/// bounce) sliding at 1 m/s on a Coulomb base μ = 0.3, plane strain. It decelerates at μg
/// and stops after v/(μg) = 0.34 s: the base friction dissipation must equal the initial
/// kinetic energy ½ M v² less the work of lifting the block (its geostatic start relaxes
/// upwards by about a millimetre; within 2 % of ½ M v², measured −0.8 %), the kinetic energy
/// must be gone, and the residual must stay a small fraction of it (1 %).
#[test]
fn a_block_sliding_to_rest_dissipates_its_kinetic_energy_in_base_friction() {
    let (v0, mu) = (1.0, 0.3);
    let mut cfg = block(FormulationKind::PlaneStrain, ShapeFunctionKind::Linear, [0.0, -G], [v0, 0.0]);
    cfg.materials.get_mut("m").unwrap().set("youngs_modulus", 1e7);
    cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [1.2, 0.4], cell_size: 0.05, follow: None, experimental: false };
    cfg.bodies[0].set_rectangle([0.1, 0.0], [0.5, 0.2]);
    cfg.bodies[0].initial_stress = InitialStress::Geostatic;
    cfg.boundaries.bottom = BoundaryCondition::friction(mu);
    let mut sim = Simulation::new(cfg, 1).unwrap();
    let e0 = sim.energies();
    let mass: f64 = sim.particles().mass.iter().sum();
    let kinetic0 = 0.5 * mass * v0 * v0;
    assert!((e0.kinetic_energy - kinetic0).abs() < 1e-9 * kinetic0);
    sim.advance(0.5, u64::MAX).unwrap();
    let e = sim.energies();
    let friction = e.boundary_friction_dissipation;
    // gravity_work < 0: the energy spent lifting the block.
    let available = kinetic0 + e.gravity_work;
    assert!((friction - available).abs() < 0.02 * kinetic0, "friction {friction} vs ½Mv² − lift {available}: {e:?}");
    assert!(e.kinetic_energy < 0.01 * kinetic0, "{e:?}");
    // Sources: the released potential (here negative: the geostatic block relaxes upwards), the
    // initial kinetic energy and the initial stored elastic energy.
    let lost = e.residual() + kinetic0 + e0.elastic_energy;
    // Measured +0.43 % of ½Mv². It was −4.9 % (energy created: the block rose 3 mm while it
    // slid, gravity_work = −2.5 J) before the MUSL re-map kept the base's contact state of v⁺
    // (`ConstrainedNodes::correct_remapped`): the stressed particles on the base were pushed
    // off it without relaxing. A tolerance of 1 %.
    assert!(lost.abs() < 0.01 * kinetic0, "residual {lost}: {e:?} from {e0:?}");
    assert_eq!(e.plastic_work, 0.0);
    // The slide: v²/(2μg) = 0.170 m.
    let x = sim.particles().position.iter().map(|x| x[0]).sum::<f64>() / sim.particles().len() as f64;
    assert!((x - 0.3 - v0 * v0 / (2.0 * mu * G)).abs() < 0.01, "slid to {x}");
}

/// An elastic column dropped under gravity on a roller base (undamped, pure FLIP) oscillates:
/// the released potential energy goes into kinetic and stored elastic energy, and the
/// residual stays below 2 % of the released energy at every output (in both formulations).
#[test]
fn an_elastic_column_keeps_its_energy() {
    for formulation in ALL_FORMULATIONS {
        let mut cfg = block(formulation, ShapeFunctionKind::Cpgimp, [0.0, -G], [0.0, 0.0]);
        cfg.materials.get_mut("m").unwrap().set("youngs_modulus", 2e5);
        cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [0.6, 1.2], cell_size: 0.05, follow: None, experimental: false };
        cfg.bodies[0].set_rectangle([0.0, 0.0], [0.2, 1.0]);
        cfg.boundaries.bottom = BoundaryCondition::ROLLER;
        cfg.boundaries.left = BoundaryCondition::ROLLER;
        let mut sim = Simulation::new(cfg, 1).unwrap();
        let mut peak: f64 = 0.0;
        let mut worst: f64 = 0.0;
        for k in 1..=10 {
            sim.advance(0.05 * k as f64, u64::MAX).unwrap();
            let e = sim.energies();
            peak = peak.max(e.gravity_work);
            worst = worst.max(e.residual().abs());
            assert!(e.elastic_energy > 0.0 && e.plastic_work == 0.0 && e.boundary_friction_dissipation == 0.0);
        }
        assert!(peak > 0.0);
        assert!(worst < 0.02 * peak, "{formulation:?}: residual {worst} of released {peak}");
    }
}

/// A Mohr–Coulomb column collapsing on a friction base: the plastic work is never negative,
/// grows, and (with the base friction) accounts for most of the released energy once the
/// flow has slowed down.
#[test]
fn plastic_work_of_a_collapsing_column_is_positive_and_closes_the_budget() {
    let mut cfg = block(FormulationKind::Axisymmetric, ShapeFunctionKind::Cpgimp, [0.0, -G], [0.0, 0.0]);
    let mut mc = material("mohr_coulomb", 1550.0, 1e6, 0.3);
    mc.set("friction_angle", 25.0).set("dilation_angle", 0.0).set("cohesion", 0.0).set("tension_cutoff", 0.0);
    cfg.materials.insert("m".to_string(), mc);
    cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [0.3, 0.12], cell_size: 0.01, follow: None, experimental: false };
    cfg.bodies[0].set_rectangle([0.0, 0.0], [0.05, 0.1]);
    cfg.bodies[0].initial_stress = InitialStress::Geostatic;
    cfg.bodies[0].k0 = Some(0.58);
    cfg.boundaries.bottom = BoundaryCondition::friction(0.466);
    let mut sim = Simulation::new(cfg, 1).unwrap();
    let names = sim.state_names().to_vec();
    let slot = names.iter().position(|n| n == "plastic_work").expect("plastic_work state");
    let mut last = 0.0;
    for k in 1..=8 {
        sim.advance(0.05 * k as f64, u64::MAX).unwrap();
        let e = sim.energies();
        assert!(e.plastic_work >= last, "plastic work fell: {last} -> {}", e.plastic_work);
        last = e.plastic_work;
        let table = sim.state_table();
        assert!(table.chunks(names.len()).all(|row| row[slot] >= 0.0));
    }
    let e = sim.energies();
    let dissipated = e.plastic_work + e.boundary_friction_dissipation + e.boundary_normal_dissipation;
    assert!(e.plastic_work > 0.3 * e.gravity_work && e.boundary_friction_dissipation > 0.0, "{e:?}");
    assert!(e.residual().abs() < 0.1 * e.gravity_work && dissipated > 0.8 * e.gravity_work, "{e:?}");
}

/// A rigid block (B = 0.4 m) pressed into an elastic layer (2 m × 1 m, E = 1 MPa, ν = 0.3,
/// fixed base, rollers on the sides, no gravity) at 0.05 m/s for 1 s (5 % of the layer's
/// depth, quasi-static: c_p ≈ 37 m/s): the work the block does on the layer (−Σ J·w over the
/// steps) goes into stored elastic and kinetic energy, and the residual stays within 3 % of
/// that work (measured +1.4 % in plane strain, +1.7 % in axisymmetry, CPGIMP, h = 0.1 m),
/// smooth, rough and with Coulomb friction 0.3, in both formulations. Without the body's work
/// in the budget the residual would be the whole work: the check fails.
#[test]
fn the_work_of_a_rigid_block_pressed_into_an_elastic_layer_closes_the_budget() {
    for formulation in ALL_FORMULATIONS {
        for friction in [serde_json::json!(0.0), serde_json::json!("rough"), serde_json::json!(0.3)] {
            let mut cfg = block(formulation, ShapeFunctionKind::Cpgimp, [0.0, 0.0], [0.0, 0.0]);
            cfg.bodies[0].set_rectangle([0.0, 0.0], [2.0, 1.0]);
            cfg.boundaries.bottom = BoundaryCondition::FIXED;
            cfg.boundaries.left = BoundaryCondition::ROLLER;
            cfg.boundaries.right = BoundaryCondition::ROLLER;
            cfg.simulation.flip_fraction = 0.99;
            cfg.rigid_bodies = vec![serde_json::from_value(serde_json::json!({"name": "block", "shape": "rectangle",
                "min": [0.0, 1.0], "max": [0.4, 1.2], "motion": [[0.0, 0.0, 0.0], [0.1, 0.0, -0.05]],
                "friction": friction}))
            .unwrap()];
            let mut sim = Simulation::new(cfg, 1).unwrap();
            sim.advance(1.0, u64::MAX).unwrap();
            let e = sim.energies();
            let label = format!("{formulation:?} friction {friction}");
            assert!(e.rigid_body_work > 0.0 && e.elastic_energy > 0.5 * e.rigid_body_work, "{label}: {e:?}");
            assert!(e.residual().abs() < 0.03 * e.rigid_body_work, "{label}: residual {} of work {}", e.residual(), e.rigid_body_work);
            let without = e.residual() - e.rigid_body_work;
            assert!(without.abs() > 0.5 * e.rigid_body_work, "{label}");
        }
    }
}

