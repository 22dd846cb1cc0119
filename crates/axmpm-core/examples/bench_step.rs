//! The `axmpm bench` scenario (Mohr–Coulomb column collapse, 200,000 particles at 0.5 mm
//! cells) without Python, for profiling and bit-for-bit comparisons:
//!
//! `cargo run --release --example bench_step -- SCHEME FORMULATION THREADS STEPS [WARMUP] [CELL] [MATERIAL]`
//!
//! MATERIAL: `mohr_coulomb` (default) or `linear_elastic` (the column of `axmpm bench
//! --material linear_elastic` and of `benches/peer_taichi.py`: E = 1 MPa, ν = 0.3).
//!
//! Prints the throughput, a hash of every particle array after the run (equal hashes =
//! bit-for-bit equal results) and the serial fraction: the share of the timed wall time spent in
//! the parts of the step that run on one thread (`PhaseTimings::serial`); then, on a second
//! line, the wall time per particle-step of each pass.
use axmpm_core::Simulation;

fn scenario(formulation: &str, scheme: &str, cell: f64, material: &str) -> String {
    let sand = match material {
        "mohr_coulomb" => r#"{"model": "mohr_coulomb", "density": 1550.0, "youngs_modulus": 1.0e6,
    "poisson_ratio": 0.3, "friction_angle": 25.0, "dilation_angle": 0.0, "cohesion": 0.0,
    "tension_cutoff": 0.0}"#,
        "linear_elastic" => r#"{"model": "linear_elastic", "density": 1550.0, "youngs_modulus": 1.0e6, "poisson_ratio": 0.3}"#,
        other => panic!("MATERIAL must be mohr_coulomb or linear_elastic (got {other})"),
    };
    format!(
        r#"{{
  "simulation": {{"formulation": "{formulation}", "shape_function": "{scheme}", "end_time": 1.0,
    "output_interval": 1.0, "gravity": [0.0, -9.81], "gravity_ramp_time": 0.0, "time_step": 0.0,
    "cfl": 0.4, "update_scheme": "musl", "flip_fraction": 0.99, "damping": 0.0}},
  "grid": {{"origin": [0.0, 0.0], "extent": [0.4, 0.15], "cell_size": {cell}}},
  "materials": {{"sand": {sand}}},
  "bodies": [{{"material": "sand", "shape": "rectangle", "min": [0.0, 0.0], "max": [0.1, 0.125],
    "particles_per_cell": 2, "velocity": [0.0, 0.0], "initial_stress": "geostatic"}}],
  "boundaries": {{"left": {{"condition": "roller", "coefficient": 0.0}},
    "right": {{"condition": "free", "coefficient": 0.0}},
    "bottom": {{"condition": "friction", "coefficient": 0.466}},
    "top": {{"condition": "free", "coefficient": 0.0}}}},
  "walls": []
}}"#
    )
}

/// FNV-1a over the bits of a sequence of floats.
fn hash(h: &mut u64, values: impl IntoIterator<Item = f64>) {
    for v in values {
        for b in v.to_bits().to_le_bytes() {
            *h ^= b as u64;
            *h = h.wrapping_mul(0x100_0000_01b3);
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scheme = args.get(1).map(String::as_str).unwrap_or("linear");
    let formulation = args.get(2).map(String::as_str).unwrap_or("axisymmetric");
    let threads: usize = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(1);
    let steps: u64 = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(20);
    let warmup: u64 = args.get(5).map(|s| s.parse().unwrap()).unwrap_or(2);
    let cell: f64 = args.get(6).map(|s| s.parse().unwrap()).unwrap_or(0.0005);
    let material = args.get(7).map(String::as_str).unwrap_or("mohr_coulomb");
    let mut sim = Simulation::from_json(&scenario(formulation, scheme, cell, material), threads).unwrap();
    sim.advance(1e9, warmup).unwrap();
    let before = sim.timings();
    let t = std::time::Instant::now();
    sim.advance(1e9, steps).unwrap();
    let el = t.elapsed().as_secs_f64();
    let after = sim.timings();
    let serial = after.serial - before.serial;
    let p = sim.particles();
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    hash(&mut h, p.position.iter().flatten().copied());
    hash(&mut h, p.velocity.iter().flatten().copied());
    hash(&mut h, p.stress.iter().flatten().copied());
    hash(&mut h, p.deformation_gradient.iter().flatten().copied());
    hash(&mut h, p.volume.iter().copied());
    // The state without `plastic_work` (issue 15: booked only, never fed back), so the hash
    // compares the same arrays as before that slot existed.
    let skip = sim.state_names().iter().position(|n| n == "plastic_work");
    let stride = p.state_stride;
    hash(&mut h, p.state.iter().enumerate().filter(|(k, _)| Some(k % stride) != skip).map(|(_, v)| *v));
    hash(&mut h, p.corners.iter().flatten().flatten().copied());
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
