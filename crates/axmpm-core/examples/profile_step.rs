//! Runs a column-collapse-sized block for profiling: `cargo run --release --example profile_step -- linear 1`.
use axmpm_core::config::*;
use axmpm_core::Simulation;
use std::collections::BTreeMap;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let shape: ShapeFunctionKind = serde_json::from_str(&format!("\"{}\"", args.get(1).map(|s| s.as_str()).unwrap_or("linear"))).unwrap();
    let threads: usize = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(1);
    let steps: u64 = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(200);
    let mut materials = BTreeMap::new();
    materials.insert("m".to_string(), MaterialConfig::elastic("linear_elastic", 1500.0, 1e6, 0.3));
    let cfg = Config {
        simulation: SimulationConfig { formulation: FormulationKind::Axisymmetric, shape_function: shape, end_time: 1.0,
            output_interval: 0.1, gravity: [0.0, -9.81], gravity_ramp_time: 0.0, time_step: 0.0, cfl: 0.4,
            update_scheme: UpdateScheme::Musl, flip_fraction: 0.99, xpic_order: 1, experimental: false, damping: 0.0, volumetric_averaging: VolumetricAveraging::None, extra: Default::default() },
        grid: GridConfig { origin: [0.0, 0.0], extent: [0.4, 0.3], cell_size: std::env::var("H").map(|s| s.parse().unwrap()).unwrap_or(0.001), follow: None, experimental: false },
        materials,
        bodies: vec![BodyConfig::rectangle("m", [0.0, 0.0], [0.1, 0.2])],
        boundaries: BoundariesConfig { left: BoundaryCondition::ROLLER, right: BoundaryCondition::FREE,
            bottom: BoundaryCondition::friction(0.5), top: BoundaryCondition::FREE },
        walls: vec![], rigid_bodies: vec![], drainage: Default::default(), surcharges: Vec::new(), extra: Default::default() };
    let mut sim = Simulation::new(cfg, threads).unwrap();
    sim.advance(1e9, 10).unwrap();
    let t = std::time::Instant::now();
    sim.advance(1e9, steps).unwrap();
    let el = t.elapsed().as_secs_f64();
    println!("{:?} threads={} N={} {:.2} M particle-steps/s", shape, threads, sim.particles().len(),
        steps as f64 * sim.particles().len() as f64 / el / 1e6);
    println!("{:?}", sim.timings());
}
