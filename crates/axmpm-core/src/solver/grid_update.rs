//! Grid update: v_i = p_i / m_i, a_i = (f_int + f_ext)_i / m_i (with Cundall local damping),
//! v⁺_i = v_i + Δt a_i, then the constraints (grid faces, the axis, walls) correct the nodal
//! velocities. Also the MUSL re-map's velocities from the re-mapped momentum.

use rayon::prelude::*;

use super::State;
use crate::constraint::NodalContext;

/// Nodal velocities before and after the momentum update, with damping and constraints.
pub(super) fn update_grid(state: &mut State, dt: f64) {
    let params = state.parameters;
    if state.constraints.has_particle_contact() {
        // Rigid bodies' penalty contact: forces at the particles' domain corners
        // (`constraint/rigid_body.rs`), added to f_i before the momentum update.
        let serial_start = std::time::Instant::now();
        let fields = &mut state.fields;
        let context = crate::constraint::ParticleContext {
            particles: &state.particles,
            grid: &state.grid,
            mass: &fields.mass,
            light: params.mass_threshold,
            time: state.time,
            dt,
            axisymmetric: params.axisymmetric,
        };
        state.constraints.add_contact_forces(&context, &mut fields.force);
        state.timings.serial += serial_start.elapsed().as_secs_f64();
    }
    let fields = &mut state.fields;
    // Row by row over the region of this step (elsewhere every field is zero and stays so).
    let region = state.scratch.grid_region;
    let nx = state.grid.nodes[0];
    let (first_row, rows) = region.row_span();
    let columns = region.column_span(nx);
    fields
        .velocity
        .par_chunks_mut(nx)
        .zip(fields.velocity_new.par_chunks_mut(nx))
        .zip(fields.mass.par_chunks(nx))
        .zip(fields.momentum.par_chunks(nx))
        .zip(fields.force.par_chunks(nx))
        .skip(first_row)
        .take(rows)
        .with_min_len(4)
        .for_each(|((((v, v_new), m), p), f)| {
            // One row as a plain loop, the node update inlined (not left to the inliner's
            // heuristics: as a closure called per node it cost 40 % more instructions).
            let c = columns.clone();
            let row = v[c.clone()].iter_mut().zip(&mut v_new[c.clone()]).zip(&m[c.clone()]).zip(&p[c.clone()]).zip(&f[c]);
            for ((((v, v_new), &m), p), f) in row {
                update_node(&params, dt, v, v_new, m, p, f);
            }
        });
    constrain_velocities(state, dt);
}

/// Constraints on the start-of-step velocities (so that FLIP sees v⁺ − v of the constrained
/// field; rigid bodies excepted, see `constraint/rigid_body.rs`), then on v⁺: that correction
/// is the physical one, recorded as the reaction (shared with the saturated pass). The nodal
/// mass the constraints book their impulses with is the solid's, or in a saturated run the
/// mixture's response to a change of the solid's velocity
/// ([`super::saturated::WaterState::reaction_mass`]).
pub(super) fn constrain_velocities(state: &mut State, dt: f64) {
    let serial_start = std::time::Instant::now();
    let fields = &mut state.fields;
    let mass = match &state.water {
        Some(water) => &water.reaction_mass,
        None => &fields.mass,
    };
    let context = NodalContext { grid: &state.grid, mass, time: state.time, dt, axisymmetric: state.parameters.axisymmetric };
    state.constraints.apply_start_of_step(&context, &mut fields.velocity);
    state.constraints.apply(&context, &mut fields.velocity_new, true);
    state.timings.serial += serial_start.elapsed().as_secs_f64();
}

/// One node: v = p/m and v⁺ = v + Δt a (module doc), or the momentum's velocity alone for a
/// node lighter than the threshold, or zero for a node without mass.
#[inline(always)]
fn update_node(params: &super::StepParameters, dt: f64, v: &mut [f64; 2], v_new: &mut [f64; 2], m: f64, p: &[f64; 2], f: &[f64; 2]) {
    if m > params.mass_threshold {
        let v0 = [p[0] / m, p[1] / m];
        let mut a = [0.0; 2];
        for d in 0..2 {
            a[d] = damped(f[d], params.damping, v0[d]) / m;
        }
        *v = v0;
        *v_new = [v0[0] + dt * a[0], v0[1] + dt * a[1]];
    } else if m > 0.0 {
        // A node lighter than the threshold (a GIMP/CPDI domain barely reaching it):
        // no force update (f/m would be unbounded), but the velocity of the momentum it
        // carries, so that it stays consistent with its particles in every stencil
        // (a rigid translation stays stress-free to round-off: issue #13).
        *v = [p[0] / m, p[1] / m];
        *v_new = *v;
    } else {
        *v = [0.0; 2];
        *v_new = [0.0; 2];
    }
}

/// Cundall local damping: the unbalanced force `force` reduced by `damping` × its magnitude
/// against the motion `velocity` (shared with the saturated pass).
#[inline(always)]
pub(super) fn damped(force: f64, damping: f64, velocity: f64) -> f64 {
    force - damping * force.abs() * sign(velocity)
}

/// The sign of `x` (0 at ±0).
#[inline(always)]
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// MUSL: nodal velocities from the re-mapped momentum, constrained; stored in `fields.velocity`.
pub(super) fn remap_velocity(state: &mut State, dt: f64) {
    let fields = &mut state.fields;
    let region = state.scratch.grid_region;
    let nx = state.grid.nodes[0];
    let (first_row, rows) = region.row_span();
    let columns = region.column_span(nx);
    fields
        .velocity
        .par_chunks_mut(nx)
        .zip(fields.mass.par_chunks(nx))
        .zip(fields.momentum.par_chunks(nx))
        .skip(first_row)
        .take(rows)
        .with_min_len(4)
        .for_each(|((v, m), p)| {
            let c = columns.clone();
            for ((v, &m), p) in v[c.clone()].iter_mut().zip(&m[c.clone()]).zip(&p[c]) {
                // Every node with mass, light ones included (see `update_grid`).
                *v = if m > 0.0 { [p[0] / m, p[1] / m] } else { [0.0; 2] };
            }
        });
    let serial_start = std::time::Instant::now();
    let context = NodalContext {
        grid: &state.grid,
        mass: &fields.mass,
        time: state.time,
        dt,
        axisymmetric: state.parameters.axisymmetric,
    };
    state.constraints.apply_remapped(&context, &mut fields.velocity);
    state.timings.serial += serial_start.elapsed().as_secs_f64();
}

