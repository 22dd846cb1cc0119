//! A Mohr–Coulomb body through `Simulation`: masses from the model's density, the geostatic
//! initial stress with the default K0 = ν/(1 − ν) read from the material table, and a column
//! that stands on a fixed base.

mod common;
use axmpm_core::config::*;
use axmpm_core::Simulation;
use common::*;

const RHO: f64 = 1550.0;
const G: f64 = 9.81;

fn sand_column(formulation: FormulationKind) -> Config {
    let mut cfg = block(formulation, ShapeFunctionKind::Linear, [0.0, -G], [0.0, 0.0]);
    let mut sand = MaterialConfig::elastic("mohr_coulomb", RHO, 5e6, 0.25);
    sand.set("friction_angle", 35.0).set("dilation_angle", 0.0).set("cohesion", 2e3);
    cfg.materials.clear();
    cfg.materials.insert("sand".into(), sand);
    cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [0.6, 0.6], cell_size: 0.05, follow: None, experimental: false };
    cfg.bodies[0] = BodyConfig {
        initial_stress: InitialStress::Geostatic,
        ..BodyConfig::rectangle("sand", [0.0, 0.0], [0.3, 0.4])
    };
    cfg.boundaries.bottom = BoundaryCondition::FIXED;
    cfg.boundaries.left = BoundaryCondition::ROLLER;
    cfg.boundaries.right = BoundaryCondition::ROLLER;
    cfg.grid.extent[0] = 0.3; // laterally confined: K0 conditions
    cfg.simulation.flip_fraction = 0.99;
    cfg
}

#[test]
fn a_confined_mohr_coulomb_column_keeps_its_geostatic_stress() {
    for formulation in ALL_FORMULATIONS {
        {
            let mut sim = Simulation::new(sand_column(formulation), 1).unwrap();
            let names = sim.state_names().to_vec();
            assert_eq!(&names[..2], ["plastic_shear_strain", "plastic_volumetric_strain"]);
            assert_eq!(names.len(), 3); // + plastic_work
            // Mass ρ A per metre, ρ ∫ r dA per radian.
            let mass: f64 = sim.particles().mass.iter().sum();
            let expect = match formulation {
                FormulationKind::PlaneStrain => RHO * 0.3 * 0.4,
                FormulationKind::Axisymmetric => RHO * 0.5 * 0.09 * 0.4,
            };
            assert!((mass - expect).abs() < 1e-9 * expect, "{formulation:?}: mass {mass} vs {expect}");
            // Geostatic start: σ_v = −ρ g (H − y), σ_h = K0 σ_v with K0 = ν/(1 − ν) = 1/3.
            let k0 = 0.25 / 0.75;
            let check = |sim: &Simulation, tolerance: f64| {
                let p = sim.particles();
                let (mut num, mut den) = (0.0, 0.0);
                for i in 0..p.len() {
                    let y = p.initial_position[i][1];
                    let vertical = -RHO * G * (0.4 - y);
                    if y > 0.1 && y < 0.3 {
                        num += (p.stress[i][1] - vertical).powi(2) + (p.stress[i][0] - k0 * vertical).powi(2);
                        den += vertical.powi(2) * (1.0 + k0 * k0);
                    }
                }
                let error = (num / den).sqrt();
                assert!(error < tolerance, "{formulation:?}: geostatic stress error {error:.4}");
            };
            check(&sim, 1e-12);
            // At K0 = 1/3 with φ = 35° and c = 2 kPa the column is elastic and stays put.
            sim.advance(0.2, u64::MAX).unwrap();
            check(&sim, 0.05);
            let p = sim.particles();
            let settlement = (0..p.len()).map(|i| (p.position[i][1] - p.initial_position[i][1]).abs()).fold(0.0, f64::max);
            assert!(settlement < 1e-3, "{formulation:?}: settlement {settlement}");
        }
    }
}
