//! The `axmpm bench` scenario (Mohr–Coulomb column collapse, 200,000 particles at 0.5 mm
//! cells) without Python, for profiling and bit-for-bit comparisons:
//!
//! `cargo run --release --example bench_step -- SCHEME FORMULATION THREADS STEPS [WARMUP] [CELL] [MATERIAL]`
//!
//! MATERIAL: `mohr_coulomb` (default) or `linear_elastic` (the column of `axmpm bench
//! --material linear_elastic` and of `benches/peer_taichi.py`: E = 1 MPa, ν = 0.3), or
//! `saturated_mohr_coulomb` (the granular column as a saturated two-phase body).
//!
//! Prints the throughput, a hash of every particle array after the run (equal hashes =
//! bit-for-bit equal results) and the serial fraction: the share of the timed wall time spent in
//! the parts of the step that run on one thread (`PhaseTimings::serial`); then, on a second
//! line, the wall time per particle-step of each pass.
#[path = "support/bench_case.rs"]
mod bench_case;
use axmpm_core::Simulation;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scheme = args.get(1).map(String::as_str).unwrap_or("linear");
    let formulation = args.get(2).map(String::as_str).unwrap_or("axisymmetric");
    let threads: usize = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(1);
    let steps: u64 = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(20);
    let warmup: u64 = args.get(5).map(|s| s.parse().unwrap()).unwrap_or(2);
    let cell: f64 = args.get(6).map(|s| s.parse().unwrap()).unwrap_or(0.0005);
    let material = args.get(7).map(String::as_str).unwrap_or("mohr_coulomb");
    let mut sim = Simulation::from_json(&bench_case::scenario(formulation, scheme, cell, material), threads).unwrap();
    sim.advance(1e9, warmup).unwrap();
    let before = sim.timings();
    let t = std::time::Instant::now();
    sim.advance(1e9, steps).unwrap();
    let el = t.elapsed().as_secs_f64();
    let after = sim.timings();
    let serial = after.serial - before.serial;
    let p = sim.particles();
    let h = bench_case::result_hash(&sim);
    println!(
        "{scheme} {formulation} threads={threads} isa={} N={} steps={steps} {:.3} M particle-steps/s hash={h:016x} bytes/particle={} serial={:.4}",

        sim.isa().name(),
        p.len(),
        steps as f64 * p.len() as f64 / el / 1e6,
        sim.bytes_per_particle(),
        serial / el
    );
    // Wall time per particle-step of each pass (ns): their ratios are steadier than the total
    // on a VM whose speed drifts between runs (a change to one pass shows against the others).
    let per = 1e9 / (steps as f64 * p.len() as f64);
    println!(
        "passes ns/particle-step: particle_to_grid={:.2} grid_update={:.2} grid_to_particle={:.2} update_particles={:.2}",
        (after.particle_to_grid - before.particle_to_grid) * per,
        (after.grid_update - before.grid_update) * per,
        (after.grid_to_particle - before.grid_to_particle) * per,
        (after.constitutive_update - before.constitutive_update) * per
    );
}
