//! The nonlocal granular fluidity model in a run (material/granular_fluidity/ with its cell
//! Laplacian): a collapsing column of glass beads, bit-for-bit independent of the thread count,
//! its fluidity nonlocal (the Laplacian changing the flow), and its energy budget closed.

mod common;
use axmpm_core::config::*;
use axmpm_core::Simulation;
use common::*;

/// A column of glass beads (Henann & Kamrin 2013 values; A given) 0.12 m wide and 0.2 m tall
/// collapsing on a rough base, 1 cm cells, 2 × 2 particles per cell.
fn beads(formulation: FormulationKind, amplitude: f64) -> Config {
    let mut cfg = block(formulation, ShapeFunctionKind::Cpgimp, [0.0, -9.81], [0.0, 0.0]);
    let mut beads = MaterialConfig::elastic("granular_fluidity", 1550.0, 1e6, 0.3);
    beads
        .set("static_friction", 0.3819)
        .set("friction_rate", 0.9377)
        .set("nonlocal_amplitude", amplitude)
        .set("grain_diameter", 4e-3)
        .set("grain_density", 2500.0)
        .set("experimental", true);
    cfg.materials.clear();
    cfg.materials.insert("beads".into(), beads);
    cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [0.48, 0.3], cell_size: 0.01, follow: None, experimental: false };
    cfg.bodies[0] = BodyConfig {
        initial_stress: InitialStress::Geostatic,
        k0: Some(1.0 - 0.3819),
        particles_per_cell: 2,
        ..BodyConfig::rectangle("beads", [0.0, 0.0], [0.12, 0.2])
    };
    cfg.boundaries.bottom = BoundaryCondition::friction(0.466);
    cfg.boundaries.left = BoundaryCondition::ROLLER;
    cfg.simulation.flip_fraction = 1.0;
    cfg
}

fn run(cfg: &Config, threads: usize, steps: u64) -> Simulation {
    let mut sim = Simulation::new(cfg.clone(), threads).unwrap();
    assert_eq!(sim.advance(1e9, steps).unwrap(), steps);
    sim
}

fn state_column(sim: &Simulation, name: &str) -> Vec<f64> {
    let k = sim.state_names().iter().position(|n| n == name).unwrap();
    let p = sim.particles();
    (0..p.len()).map(|i| p.state[i * p.state_stride + k]).collect()
}

#[test]
fn fluidity_collapse_is_bit_identical_on_1_2_and_3_threads() {
    for f in ALL_FORMULATIONS {
        let cfg = beads(f, 0.48);
        let bits = |sim: &Simulation| -> Vec<u64> {
            let p = sim.particles();
            p.position.iter().flatten().chain(p.stress.iter().flatten()).chain(p.state.iter()).map(|v| v.to_bits()).collect()
        };
        let reference = bits(&run(&cfg, 1, 300));
        for threads in [2, 3] {
            assert!(bits(&run(&cfg, threads, 300)) == reference, "{f:?}: {threads} threads differ from 1");
        }
    }
}

#[test]
fn the_column_flows_its_fluidity_diffuses_and_the_energy_budget_closes() {
    for f in ALL_FORMULATIONS {
        let mut sim = Simulation::new(beads(f, 0.48), 1).unwrap();
        sim.advance(0.15, u64::MAX).unwrap();
        let g = state_column(&sim, "fluidity");
        assert_eq!(sim.state_names(), ["fluidity", "plastic_shear_strain", "plastic_work"], "no solver scratch in the state");
        assert!(g.iter().all(|&g| g >= 0.0 && g.is_finite()), "{f:?}: the fluidity stays ≥ 0");
        assert!(g.iter().any(|&g| g > 1.0), "{f:?}: the column flows (g up to {})", g.iter().cloned().fold(0.0, f64::max));
        let e = sim.energies();
        // Measured at 0.15 s: plastic 57 % (plane strain) and 51 % (axisymmetric) of the released energy.
        assert!(e.plastic_work > 0.3 * e.gravity_work, "{f:?}: {e:?}");
        // Released energy = kinetic + stored + plastic + boundary + residual; the model adds no
        // residual of its own (its dissipation closes the stored-energy change): measured
        // −0.017 % (plane strain) and +0.054 % (axisymmetric) of the released energy at 0.15 s
        // (+4 % with the end-point rule τ Δγᵖ instead). A tolerance of 0.5 %.
        assert!(e.residual().abs() < 0.005 * e.gravity_work, "{f:?}: residual {} of {}", e.residual(), e.gravity_work);
    }
}

#[test]
fn the_nonlocal_term_changes_the_flow_and_a_zero_amplitude_is_the_local_law() {
    let positions = |amplitude: f64| -> Vec<[f64; 2]> { run(&beads(FormulationKind::Axisymmetric, amplitude), 1, 400).particles().position.clone() };
    let (local, nonlocal) = (positions(0.0), positions(0.48));
    let largest_difference = local.iter().zip(&nonlocal).map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs())).fold(0.0, f64::max);
    assert!(largest_difference > 1e-6, "the cooperativity length moved no particle: {largest_difference}");
}
