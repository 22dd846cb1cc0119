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
    let mut ranges = Vec::with_capacity(config.bodies.len());
    for (i, body) in config.bodies.iter().enumerate() {
        let first = particles.len();
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
        ranges.push(first..particles.len());
    }
    // Saturated bodies: porosity, pore pressure, solid mass (nothing for a dry run).
    saturate::<F>(config, &mut particles, &ranges);
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
    let reserved = crate::constraint::rigid_body::reserved_names(config.walls.len());
    let end_time = config.simulation.end_time;
    crate::constraint::rigid_body::build_all(&config.rigid_bodies, g.origin, upper, axisymmetric, end_time, &reserved)
}

/// Gives the particles of the saturated bodies (`bodies[i]` made the particles `ranges[i]`)
/// their water: porosity, conductivity, initial pore pressure, the solid mass (1 − n) ρ_s V
/// (the material's density is the grains'), the effective geostatic stress and the surface
/// load. Allocates the water arrays for every particle (dry bodies get n = 0).
fn saturate<F: Formulation>(config: &Config, particles: &mut Particles, ranges: &[std::ops::Range<usize>]) {
    if !config.bodies.iter().any(|b| b.saturated.is_some()) {
        return;
    }
    let n_particles = particles.len();
    particles.pore_pressure = vec![0.0; n_particles];
    particles.porosity = vec![0.0; n_particles];
    particles.water_velocity = vec![[0.0; 2]; n_particles];
    particles.hydraulic_conductivity = vec![0.0; n_particles];
    particles.external_force = vec![[0.0; 2]; n_particles];
    let gravity_y = config.simulation.gravity[1];
    for (body, range) in config.bodies.iter().zip(ranges) {
        let Some(s) = &body.saturated else { continue };
        let n = s.porosity;
        let rho_s = Parameters::new(&body.material, &config.materials[&body.material].parameters)
            .f64("density")
            .unwrap_or(0.0);
        let rho_sat = (1.0 - n) * rho_s + n * s.water_density;
        let spacing = config.grid.cell_size / body.particles_per_cell.max(1) as f64;
        let top = range.clone().map(|p| particles.position[p][1]).fold(f64::NEG_INFINITY, f64::max);
        for p in range.clone() {
            let x = particles.position[p];
            particles.porosity[p] = n;
            particles.hydraulic_conductivity[p] = s.hydraulic_conductivity;
            particles.mass[p] *= 1.0 - n;
            let pressure = match (s.water_table, s.pore_pressure) {
                (Some(z), _) => s.water_density * (-gravity_y) * (z - x[1]).max(0.0),
                (None, Some(p0)) => p0,
                (None, None) => 0.0,
            };
            particles.pore_pressure[p] = pressure;
            if body.initial_stress == crate::config::InitialStress::Geostatic {
                // The set-up's total geostatic stress of the grains' density, made effective:
                // σ′_v = ρ_sat g_y d + p, the lateral components in the same ratio K0.
                let stress = &mut particles.stress[p];
                if stress[1] != 0.0 {
                    let vertical = stress[1] * rho_sat / rho_s + pressure;
                    let scale = vertical / stress[1];
                    for c in stress.iter_mut() {
                        *c *= scale;
                    }
                }
            }
            // The top row of particles carries the surface load: q times its width (× R_p).
            if s.surface_load > 0.0 && x[1] > top - 0.5 * spacing {
                particles.external_force[p] = [0.0, -s.surface_load * spacing * F::volume_factor(x)];
            }
        }
    }
}

