//! Creating the particles of every body (its region filled by [`geometry::lattice_points`])
//! and giving them their initial state.

use crate::config::{BodyConfig, Config, InitialStress};
use crate::formulation::Formulation;
use crate::geometry::{self, Region};
use crate::grid::GridGeometry;
use crate::material::{Material, Parameters};
use crate::particles::Particles;

/// Creates the particles of every body: `n × n` per cell (n = `particles_per_cell`), each at
/// the centre of its sub-cell, with area (h/n)², mass ρ0 A_p (× R_p in axisymmetry) and
/// half-width h/(2n). A lattice point inside (or on) a rigid body at t = 0 gets no particle:
/// rigid bodies cut their region out of every body.
pub fn create_particles<F: Formulation>(
    config: &Config,
    grid: &GridGeometry,
    materials: &[Box<dyn Material>],
    material_names: &[String],
    state_stride: usize,
    with_corners: bool,
) -> Result<Particles, String> {
    let mut particles = Particles { state_stride, ..Default::default() };
    let rigid_bodies = rigid_bodies(config)?;
    for (i, body) in config.bodies.iter().enumerate() {
        let context = format!("bodies[{i}]");
        let region = geometry::build(&context, &body.region)?;
        let id = material_names.iter().position(|n| *n == body.material).expect("validated material name");
        let k0 = match body.k0 {
            Some(k0) => k0,
            None => {
                // At-rest ratio of a laterally confined elastic column, K0 = ν/(1 − ν).
                let parameters = Parameters::new(&body.material, &config.materials[&body.material].parameters);
                let nu = parameters.f64("poisson_ratio").map_err(|e| format!("{context}.k0: not given, and {e}"))?;
                nu / (1.0 - nu)
            }
        };
        let mut keep = |x: [f64; 2]| !rigid_bodies.iter().any(|b| b.contains(x, 0.0));
        let gravity = config.simulation.gravity;
        add_body::<F>(&mut particles, body, region.as_ref(), grid, materials[id].as_ref(), id as u32, k0, gravity, &mut keep);
    }
    if with_corners {
        particles.corners = (0..particles.len())
            .map(|p| Particles::rectangle_corners(particles.position[p], particles.initial_half_width[p]))
            .collect();
    }
    Ok(particles)
}

#[allow(clippy::too_many_arguments)]
fn add_body<F: Formulation>(
    particles: &mut Particles,
    body: &BodyConfig,
    region: &dyn Region,
    grid: &GridGeometry,
    material: &dyn Material,
    id: u32,
    k0: f64,
    gravity: [f64; 2],
    keep: &mut dyn FnMut([f64; 2]) -> bool,
) {
    let n = body.particles_per_cell as usize;
    let spacing = grid.cell_size / n as f64;
    let half = [0.5 * spacing, 0.5 * spacing];
    let area = spacing * spacing;
    let density = material.density();
    let top = region.bounding_box().1[1];
    geometry::lattice_points(region, grid, n, |x| {
        if !keep(x) {
            return;
        }
        let volume = area * F::volume_factor(x);
        let stress = match body.initial_stress {
            InitialStress::Zero => [0.0; 4],
            InitialStress::Geostatic => {
                // σ_v = ρ g_y (y_top − y) (compression under g_y < 0), σ_h = K0 σ_v.
                let vertical = density * gravity[1] * (top - x[1]);
                [k0 * vertical, vertical, k0 * vertical, 0.0]
            }
        };
        particles.push(x, body.velocity, density * volume, volume, half, stress, id);
    });
}

/// The rigid bodies of the scenario (validated: errors name `rigid_bodies[i].key`).
pub fn rigid_bodies(config: &Config) -> Result<Vec<crate::constraint::RigidBody>, String> {
    let g = &config.grid;
    let upper = [g.origin[0] + g.extent[0], g.origin[1] + g.extent[1]];
    let axisymmetric = config.simulation.formulation == crate::config::FormulationKind::Axisymmetric;
    crate::constraint::rigid_body::build_all(&config.rigid_bodies, g.origin, upper, axisymmetric)
}
