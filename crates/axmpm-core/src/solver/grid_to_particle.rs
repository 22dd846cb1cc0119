//! Grid → particle: the FLIP/PIC velocity blend
//! v_p ← FLIP (v_p + Σ_i S_ip (v⁺_i − v_i)) + (1 − FLIP) Σ_i S_ip v⁺_i and the position
//! increment Δx_p = Δt Σ_i S_ip v⁺_i; with MUSL, the new momentum Σ_p S_ip m_p v_p is scattered
//! back to the grid in the same pass.

use rayon::prelude::*;

use super::grid_update::remap_velocity;
use super::lanes::{lane_length, sum_lanes};
use super::State;
use crate::config::UpdateScheme;
use crate::formulation::Formulation;
use crate::interpolation::{ParticleDomain, ShapeFunction};
use crate::particles::Particles;

/// New particle velocities (PIC/FLIP blend) and position increments; with MUSL the new
/// momentum is scattered back to the grid in the same pass (same stencil, same lanes).
#[inline(never)] // one call per step; a symbol of its own for profiles (callgrind --toggle-collect)
pub(super) fn grid_to_particle<F: Formulation, S: ShapeFunction>(state: &mut State, dt: f64, cache: &[S::Cache]) {
    let grid = &state.grid;
    let fields = &state.fields;
    let flip = state.parameters.flip_fraction;
    let musl = state.parameters.scheme == UpdateScheme::Musl;
    // Velocities are updated in place (each particle reads only its own); the rest is read only.
    let Particles { velocity, position, initial_half_width, deformation_gradient, corners, mass, .. } =
        &mut state.particles;
    let (position, initial_half_width, deformation_gradient, corners, mass) =
        (&*position, &*initial_half_width, &*deformation_gradient, &*corners, &*mass);
    let len = lane_length(velocity.len());
    velocity
        .par_chunks_mut(len)
        .zip(state.scratch.displacement.par_chunks_mut(len))
        .zip(state.lanes.par_iter_mut())
        .enumerate()
        .for_each(|(k, ((velocity_io, displacement_out), lane))| {
            // The MUSL re-map scatters the same stencils as particle → grid, so it reaches the
            // same node box: kept instead of grown again particle by particle.
            let reached = lane.touched;
            if musl {
                lane.clear(grid.nodes[0]);
            }
            // Local copies and slices, kept in registers across the nodal stores (see P2G).
            let (grid, flip, dt, musl) = (*grid, flip, dt, musl);
            let (velocity_new, velocity_old) = (&fields.velocity_new[..], &fields.velocity[..]);
            let nodes = &mut lane.nodes[..];
            let corners: &[[[f64; 2]; 4]] = corners;
            // The lane's particles as slices of one length (no bounds checks in the loop).
            let n = velocity_io.len();
            let first = k * len;
            let position = &position[first..first + n];
            let initial_half_width = &initial_half_width[first..first + n];
            let deformation_gradient = &deformation_gradient[first..first + n];
            let mass = &mass[first..first + n];
            let cache = &cache[first..first + n];
            for (i, (v_io, dx)) in velocity_io.iter_mut().zip(displacement_out.iter_mut()).enumerate() {
                let domain = ParticleDomain {
                    position: position[i],
                    initial_half_width: initial_half_width[i],
                    deformation_gradient: &deformation_gradient[i],
                    corners: corners.get(first + i),
                };
                let mut v_grid = [0.0; 2];
                let mut dv = [0.0; 2];
                S::visit_entries(&grid, &cache[i], &domain, F::AXISYMMETRIC, |node, w, _| {
                    let vn = velocity_new[node];
                    let vo = velocity_old[node];
                    v_grid[0] += w * vn[0];
                    v_grid[1] += w * vn[1];
                    dv[0] += w * (vn[0] - vo[0]);
                    dv[1] += w * (vn[1] - vo[1]);
                });
                let v = *v_io;
                let v_new = [
                    flip * (v[0] + dv[0]) + (1.0 - flip) * v_grid[0],
                    flip * (v[1] + dv[1]) + (1.0 - flip) * v_grid[1],
                ];
                *v_io = v_new;
                *dx = [dt * v_grid[0], dt * v_grid[1]];
                if musl {
                    let m = mass[i];
                    S::visit_entries(&grid, &cache[i], &domain, F::AXISYMMETRIC, |node, w, _| {
                        let sums = &mut nodes[node];
                        let wm = w * m;
                        sums.momentum[0] += wm * v_new[0];
                        sums.momentum[1] += wm * v_new[1];
                    });
                }
            }
            if musl {
                lane.touched = reached;
            }
        });
    if musl {
        sum_lanes(&state.lanes, grid.nodes[0], state.scratch.grid_region, &mut state.fields, false);
        remap_velocity(state, dt);
    }
}

