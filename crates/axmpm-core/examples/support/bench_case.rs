//! The `bench_step` scenario and its result hash, shared by `examples/bench_step.rs` and the
//! pinned-hash test `tests/bench_hashes.rs` (so that the test checks exactly what the benchmark runs).
use axmpm_core::Simulation;

/// The `axmpm bench` column: a granular column (`mohr_coulomb`, φ = 25°) or an elastic one
/// (`linear_elastic`, E = 1 MPa, ν = 0.3) collapsing under gravity on a rough base, 2 × 2
/// particles per cell, as JSON for `Simulation::from_json`. `saturated_mohr_coulomb` is the
/// granular column as a saturated two-phase body (n = 0.4, k = 1e-4 m/s, water at rest
/// below a table at the column's top): the cost of the two-phase step against the dry one.
pub fn scenario(formulation: &str, scheme: &str, cell: f64, material: &str) -> String {
    const MOHR_COULOMB: &str = r#"{"model": "mohr_coulomb", "density": 1550.0, "youngs_modulus": 1.0e6,
    "poisson_ratio": 0.3, "friction_angle": 25.0, "dilation_angle": 0.0, "cohesion": 0.0,
    "tension_cutoff": 0.0}"#;
    let (sand, water) = match material {
        "mohr_coulomb" => (MOHR_COULOMB, ""),
        "linear_elastic" => (r#"{"model": "linear_elastic", "density": 1550.0, "youngs_modulus": 1.0e6, "poisson_ratio": 0.3}"#, ""),
        "saturated_mohr_coulomb" => (
            MOHR_COULOMB,
            r#", "saturated": {"porosity": 0.4, "hydraulic_conductivity": 1.0e-4, "water_table": 0.125}"#,
        ),
        other => panic!("MATERIAL must be mohr_coulomb, linear_elastic or saturated_mohr_coulomb (got {other})"),
    };
    format!(
        r#"{{
  "simulation": {{"formulation": "{formulation}", "shape_function": "{scheme}", "end_time": 1.0,
    "output_interval": 1.0, "gravity": [0.0, -9.81], "gravity_ramp_time": 0.0, "time_step": 0.0,
    "cfl": 0.4, "update_scheme": "musl", "flip_fraction": 0.99, "damping": 0.0}},
  "grid": {{"origin": [0.0, 0.0], "extent": [0.4, 0.15], "cell_size": {cell}}},
  "materials": {{"sand": {sand}}},
  "bodies": [{{"material": "sand", "shape": "rectangle", "min": [0.0, 0.0], "max": [0.1, 0.125],
    "particles_per_cell": 2, "velocity": [0.0, 0.0], "initial_stress": "geostatic"{water}}}],
  "boundaries": {{"left": {{"condition": "roller", "coefficient": 0.0}},
    "right": {{"condition": "free", "coefficient": 0.0}},
    "bottom": {{"condition": "friction", "coefficient": 0.466}},
    "top": {{"condition": "free", "coefficient": 0.0}}}},
  "walls": []
}}"#
    )
}

/// FNV-1a over the bits of a sequence of floats.
fn fnv1a(h: &mut u64, values: impl IntoIterator<Item = f64>) {
    for v in values {
        for b in v.to_bits().to_le_bytes() {
            *h ^= b as u64;
            *h = h.wrapping_mul(0x100_0000_01b3);
        }
    }
}

/// A hash of every particle array of `sim` (equal hashes = bit-for-bit equal results). The
/// `plastic_work` state is left out: it is booked only, never fed back into the motion.
pub fn result_hash(sim: &Simulation) -> u64 {
    let p = sim.particles();
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    fnv1a(&mut h, p.position.iter().flatten().copied());
    fnv1a(&mut h, p.velocity.iter().flatten().copied());
    fnv1a(&mut h, p.stress.iter().flatten().copied());
    fnv1a(&mut h, p.deformation_gradient.iter().flatten().copied());
    fnv1a(&mut h, p.volume.iter().copied());
    let skip = sim.state_names().iter().position(|n| n == "plastic_work");
    let stride = p.state_stride;
    fnv1a(&mut h, p.state.iter().enumerate().filter(|(k, _)| Some(k % stride) != skip).map(|(_, v)| *v));
    fnv1a(&mut h, p.corners.iter().flatten().flatten().copied());
    h
}
