//! Filling bodies with particles and giving them their initial state.

use crate::config::{BodyConfig, Config, InitialStress};
use crate::formulation::Formulation;
use crate::grid::GridGeometry;
use crate::material::Material;
use crate::particles::Particles;

/// Creates the particles of every body: `n × n` per cell (n = `particles_per_cell`), each at
/// the centre of its sub-cell, with area (h/n)², mass ρ0 A_p (× R_p in axisymmetry) and
/// half-width h/(2n).
pub fn create_particles<F: Formulation>(
    config: &Config,
    grid: &GridGeometry,
    materials: &[Box<dyn Material>],
    material_names: &[String],
    state_stride: usize,
    with_corners: bool,
) -> Particles {
    let mut particles = Particles { state_stride, ..Default::default() };
    for body in &config.bodies {
        let id = material_names.iter().position(|n| *n == body.material).expect("validated material name");
        let nu = config.materials[&body.material].poisson_ratio;
        let k0 = body.k0.unwrap_or(nu / (1.0 - nu));
        add_body::<F>(&mut particles, body, grid, materials[id].as_ref(), id as u32, k0, config.simulation.gravity);
    }
    if with_corners {
        particles.corners = (0..particles.len())
            .map(|p| Particles::rectangle_corners(particles.position[p], particles.initial_half_width[p]))
            .collect();
    }
    particles
}

fn add_body<F: Formulation>(
    particles: &mut Particles,
    body: &BodyConfig,
    grid: &GridGeometry,
    material: &dyn Material,
    id: u32,
    k0: f64,
    gravity: [f64; 2],
) {
    let h = grid.cell_size;
    let n = body.particles_per_cell as usize;
    let spacing = h / n as f64;
    let half = [0.5 * spacing, 0.5 * spacing];
    let area = spacing * spacing;
    let cell_range = |d: usize| {
        let lo = ((body.min[d] - grid.origin[d]) / h).round() as i64;
        let hi = ((body.max[d] - grid.origin[d]) / h).round() as i64;
        (lo.max(0) as usize)..(hi.max(0) as usize).min(grid.cells[d])
    };
    let density = material.density();
    let top = body.max[1];
    for cj in cell_range(1) {
        for b in 0..n {
            for ci in cell_range(0) {
                for a in 0..n {
                    let x = [
                        grid.origin[0] + ci as f64 * h + (a as f64 + 0.5) * spacing,
                        grid.origin[1] + cj as f64 * h + (b as f64 + 0.5) * spacing,
                    ];
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
                }
            }
        }
    }
}
