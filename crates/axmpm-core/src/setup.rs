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
    let mut lateral_ratios = Vec::with_capacity(config.bodies.len());
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
        lateral_ratios.push(k0);
    }
    add_overburden::<F>(config, grid, &mut particles, &ranges, &lateral_ratios);
    // Saturated bodies: porosity, pore pressure, solid mass (nothing for a dry run).
    saturate::<F>(config, &mut particles, &ranges);
    add_surcharges::<F>(config, &mut particles)?;
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
                // σ_v = ρ g_y (y_top − y) (compression under g_y < 0), σ_h = K0 σ_v; the
                // weight of other bodies and the surcharges above: `add_overburden`.
                let vertical = density * gravity[1] * (top - x[1]);
                [k0 * vertical, vertical, k0 * vertical, 0.0]
            }
            InitialStress::Given(stress) => stress,
        };
        particles.push(x, body.velocity, density * volume, volume, half, stress, id);
    });
}

/// Adds to the geostatic stress of every particle what lies above it besides its own body:
/// per grid column (the particles whose x falls in the same cell column), the weight of the
/// other bodies' particles higher up, g_y Σ ρ_q a_q / h (a_q the particle's area: the
/// column's mass per unit width, so a uniform layer of thickness t gives ρ g t), and the
/// pressure of each surcharge whose level is above the particle and whose range covers its x.
/// The lateral components follow with the body's K0. A single body without surcharges is
/// untouched (nothing is added, not even a zero).
fn add_overburden<F: Formulation>(
    config: &Config,
    grid: &GridGeometry,
    particles: &mut Particles,
    ranges: &[std::ops::Range<usize>],
    lateral_ratios: &[f64],
) {
    let geostatic = |b: &BodyConfig| b.initial_stress == InitialStress::Geostatic;
    if !config.bodies.iter().any(geostatic) || (config.bodies.len() < 2 && config.surcharges.is_empty()) {
        return;
    }
    let gravity_y = config.simulation.gravity[1];
    // Per grid column, (y, body, ρ a) of every particle.
    let mut columns: Vec<Vec<(f64, usize, f64)>> = vec![Vec::new(); grid.cells[0]];
    for (b, range) in ranges.iter().enumerate() {
        for p in range.clone() {
            let x = particles.position[p];
            let areal_mass = particles.mass[p] / F::volume_factor(x);
            columns[grid.cell_of(x)[0]].push((x[1], b, areal_mass));
        }
    }
    for (b, range) in ranges.iter().enumerate() {
        if !geostatic(&config.bodies[b]) {
            continue;
        }
        let k0 = lateral_ratios[b];
        for p in range.clone() {
            let x = particles.position[p];
            let above: f64 = columns[grid.cell_of(x)[0]]
                .iter()
                .filter(|&&(y, other, _)| other != b && y > x[1])
                .map(|&(_, _, areal_mass)| areal_mass)
                .sum();
            let mut vertical = gravity_y * above / grid.cell_size;
            for c in config.surcharges.iter().filter(|c| c.level > x[1] && c.covers(x[0])) {
                vertical -= c.pressure;
            }
            if vertical != 0.0 {
                let stress = &mut particles.stress[p];
                stress[0] += k0 * vertical;
                stress[1] += vertical;
                stress[2] += k0 * vertical;
            }
        }
    }
}

/// Loads the particles under each surcharge (`config.surcharges`, [`crate::config::SurchargeConfig`]):
/// a particle whose x (r) the surcharge covers and whose upper edge y_p + l_y lies within
/// l_y/2 of the level carries the pressure over its width 2 l_x (× R_p, per radian, in
/// axisymmetry) as a downward dead load in [`Particles::external_force`]. A surcharge that
/// finds no such particle is an error: it must lie on a free surface of a body.
fn add_surcharges<F: Formulation>(config: &Config, particles: &mut Particles) -> Result<(), String> {
    if config.surcharges.is_empty() {
        return Ok(());
    }
    if particles.external_force.is_empty() {
        particles.external_force = vec![[0.0; 2]; particles.len()];
    }
    for (i, c) in config.surcharges.iter().enumerate() {
        let mut loaded = false;
        for p in 0..particles.len() {
            if let Some(load) = surcharge_load::<F>(c, particles, p) {
                particles.external_force[p][1] += load;
                loaded = true;
            }
        }
        if !loaded {
            return Err(format!(
                "surcharges[{i}]: no material has its surface at level = {} m within the range: a surcharge \
                 must lie on the top of a body (the upper edge of its top row of particles)",
                c.level
            ));
        }
    }
    Ok(())
}

/// The total force of each surcharge at full load (N per metre; per radian in axisymmetry):
/// the sum of its particles' loads as [`add_surcharges`] gave them (from the particles'
/// initial positions), in particle id order, so that a resumed run reports the same bits.
pub fn surcharge_forces<F: Formulation>(config: &Config, particles: &Particles) -> Vec<[f64; 2]> {
    let mut order: Vec<usize> = (0..particles.len()).collect();
    order.sort_by_key(|&p| particles.id.get(p).copied().unwrap_or(p as u32));
    config
        .surcharges
        .iter()
        .map(|c| [0.0, order.iter().filter_map(|&p| surcharge_load::<F>(c, particles, p)).sum()])
        .collect()
}

/// The vertical load surcharge `c` puts on particle `p` at its initial position (N per metre,
/// per radian in axisymmetry; ≤ 0), `None` for a particle it does not cover.
fn surcharge_load<F: Formulation>(c: &crate::config::SurchargeConfig, particles: &Particles, p: usize) -> Option<f64> {
    let x = particles.initial_position[p];
    let [half_x, half_y] = particles.initial_half_width[p];
    (c.covers(x[0]) && (x[1] + half_y - c.level).abs() <= 0.5 * half_y)
        .then(|| -c.pressure * 2.0 * half_x * F::volume_factor(x))
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
    if !config.has_saturated_bodies() {
        return;
    }
    let n_particles = particles.len();
    particles.pore_pressure = vec![0.0; n_particles];
    particles.porosity = vec![0.0; n_particles];
    particles.water_velocity = vec![[0.0; 2]; n_particles];
    particles.hydraulic_conductivity = vec![0.0; n_particles];
    if particles.external_force.is_empty() {
        particles.external_force = vec![[0.0; 2]; n_particles];
    }
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

