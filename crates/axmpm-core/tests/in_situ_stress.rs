//! In-situ stress: a given initial stress held by a surcharge, the geostatic stress of stacked
//! bodies under a surcharge, and the surcharge's reported force (docs/physics.md §11).

mod common;

use axmpm_core::config::*;
use axmpm_core::simulation::Simulation;
use common::*;
use std::collections::BTreeMap;

#[test]
fn a_surcharge_holds_a_weightless_layer_at_its_in_situ_stress() {
    for formulation in ALL_FORMULATIONS {
        let mut sim = Simulation::new(in_situ_layer(formulation, true), 1).unwrap();
        assert_eq!(in_situ_stress_error(&sim), 0.0);
        sim.advance(1.0, 1000).unwrap();
        let error = in_situ_stress_error(&sim);
        assert!(error < 1e-10, "{formulation:?}: {error}");
        // The force it applies: −q × the loaded width (× 2π r̄ for the ring: −q π R²).
        let area = if formulation == FormulationKind::Axisymmetric { std::f64::consts::PI * 0.25 } else { 0.5 };
        let [(name, force)] = sim.surcharge_forces().try_into().unwrap();
        assert_eq!(name, "q");
        assert_eq!(force[0], 0.0);
        assert!((force[1] / (-S_V0 * area) - 1.0).abs() < 1e-12, "{formulation:?}: {force:?}");
        // Without it the top unloads: the check above can fail.
        let mut free = Simulation::new(in_situ_layer(formulation, false), 1).unwrap();
        free.advance(1.0, 1000).unwrap();
        assert!(in_situ_stress_error(&free) > 0.05, "{formulation:?}");
    }
}

#[test]
fn the_surcharge_ramps_in_with_gravity() {
    let mut cfg = in_situ_layer(FormulationKind::PlaneStrain, true);
    cfg.simulation.gravity_ramp_time = 0.01;
    let mut sim = Simulation::new(cfg, 1).unwrap();
    sim.advance(0.0025, u64::MAX).unwrap();
    let force = sim.surcharge_forces()[0].1[1];
    assert!((force / (-S_V0 * 0.5 * 0.25) - 1.0).abs() < 1e-12, "{force}");
}

#[test]
fn stacked_geostatic_bodies_count_the_weight_above_and_the_surcharge() {
    let (g, rho_c, rho_s, q) = (9.81, 1800.0, 2000.0, 10e3);
    for formulation in ALL_FORMULATIONS {
        let mut cfg = block(formulation, ShapeFunctionKind::Cpgimp, [0.0, -g], [0.0, 0.0]);
        cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [1.0, 4.0], cell_size: 0.25, follow: None, experimental: false };
        cfg.materials = BTreeMap::from([
            ("clay".to_string(), material("linear_elastic", rho_c, 1e7, 0.4)),
            ("sand".to_string(), material("linear_elastic", rho_s, 5e7, 0.25)),
        ]);
        let mut sand = BodyConfig::rectangle("sand", [0.0, 0.0], [1.0, 1.5]);
        let mut clay = BodyConfig::rectangle("clay", [0.0, 1.5], [1.0, 3.5]);
        sand.initial_stress = InitialStress::Geostatic;
        clay.initial_stress = InitialStress::Geostatic;
        cfg.bodies = vec![sand, clay];
        cfg.surcharges = vec![SurchargeConfig { name: None, pressure: q, level: 3.5, range: None }];
        let sim = Simulation::new(cfg, 1).unwrap();
        let sand_id = sim.material_names().iter().position(|n| n == "sand").unwrap() as u32;
        let p = sim.particles();
        for i in 0..p.len() {
            let y = p.position[i][1];
            let (v, k0) = if p.material[i] == sand_id {
                (-(q + rho_c * g * 2.0 + rho_s * g * (1.5 - y)), 0.25 / 0.75)
            } else {
                (-(q + rho_c * g * (3.5 - y)), 0.4 / 0.6)
            };
            let s = p.stress[i];
            for (got, want) in [(s[1], v), (s[0], k0 * v), (s[2], k0 * v)] {
                assert!((got / want - 1.0).abs() < 1e-12, "{formulation:?} y = {y}: {got} vs {want}");
            }
            assert_eq!(s[3], 0.0);
        }
    }
}

#[test]
fn bad_surcharges_and_geostatic_without_gravity_are_refused_naming_the_key() {
    let cases: [(fn(&mut Config), &str); 5] = [
        (|c| c.surcharges[0].pressure = -1.0, "surcharges[0].pressure"),
        (|c| c.surcharges[0].level = 2.0, "surcharges[0].level"),
        (|c| c.surcharges[0].range = Some([0.4, 0.1]), "surcharges[0].range"),
        (|c| c.surcharges[0].level = 0.7, "surcharges[0]: no material has its surface at level = 0.7"),
        (|c| c.bodies[0].initial_stress = InitialStress::Geostatic, "bodies[0].initial_stress: \"geostatic\" needs gravity"),
    ];
    for (change, key) in cases {
        let mut cfg = in_situ_layer(FormulationKind::PlaneStrain, true);
        change(&mut cfg);
        let err = Simulation::new(cfg, 1).err().expect(key);
        assert!(err.contains(key), "{key}: {err}");
    }
}
