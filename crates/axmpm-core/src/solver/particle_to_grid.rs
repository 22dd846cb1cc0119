//! Particle → grid: the nodal mass m_i = Σ_p S_ip m_p, momentum p_i = Σ_p S_ip m_p v_p and
//! force f_i = f_int + f_ext (docs/physics.md §1–2), with
//! f_int = −Σ_p V_p σ_p·∇S_ip (plus the hoop term −V_p σ_θθ S_ip / R_p in axisymmetry) and
//! f_ext = Σ_p S_ip m_p g.

use rayon::prelude::*;

use super::lanes::{lane_length, sum_lanes};
use super::State;
use crate::formulation::Formulation;
use crate::grid::NodeBox;
use crate::interpolation::{ParticleDomain, ShapeFunction};

/// Scatters mass, momentum, internal and gravity forces to the nodes, lane by lane, then sums
/// the lanes in a fixed order. Computes each particle's stencil cache for the step.
#[inline(never)] // one call per step; a symbol of its own for profiles (callgrind --toggle-collect)
pub(super) fn particle_to_grid<F: Formulation, S: ShapeFunction>(state: &mut State, gravity: [f64; 2], cache: &mut [S::Cache]) {
    let particles = &state.particles;
    let grid = &state.grid;
    let len = lane_length(particles.len());
    let nodes_x = grid.nodes[0];
    cache.par_chunks_mut(len).zip(state.lanes.par_iter_mut()).enumerate().for_each(|(k, (lane_cache, lane))| {
        lane.clear(nodes_x);
        let mut touched = NodeBox::EMPTY;
        // Local copies of what the loop reads and slices of what it writes: the compiler then
        // keeps them in registers instead of reloading them after every nodal store (which it
        // cannot prove does not alias them).
        let (grid, gravity) = (*grid, gravity);
        let nodes = &mut lane.nodes[..];
        let corners = &particles.corners[..];
        // The lane's particles as slices of one length, so the loop indexes without bounds checks.
        let n = lane_cache.len();
        let first = k * len;
        let position = &particles.position[first..first + n];
        let initial_half_width = &particles.initial_half_width[first..first + n];
        let deformation_gradient = &particles.deformation_gradient[first..first + n];
        let mass = &particles.mass[first..first + n];
        let velocity = &particles.velocity[first..first + n];
        let volume = &particles.volume[first..first + n];
        let stress = &particles.stress[first..first + n];
        for (i, c) in lane_cache.iter_mut().enumerate() {
            let domain = ParticleDomain {
                position: position[i],
                initial_half_width: initial_half_width[i],
                deformation_gradient: &deformation_gradient[i],
                corners: corners.get(first + i),
            };
            S::prepare(&grid, &domain, F::AXISYMMETRIC, c);
            touched = touched.union(S::node_box(&grid, c, &domain));
            let m = mass[i];
            let v = velocity[i];
            let vol = volume[i];
            let s = stress[i];
            let hoop = F::hoop_factor(position[i]);
            S::visit_entries(&grid, c, &domain, F::AXISYMMETRIC, |node, w, g| {
                let sums = &mut nodes[node];
                sums.mass += w * m;
                sums.momentum[0] += w * m * v[0];
                sums.momentum[1] += w * m * v[1];
                // Internal force (Sulsky & Schreyer 1996, docs/physics.md §2) plus gravity.
                sums.force[0] += -vol * (s[0] * g[0] + s[3] * g[1] + s[2] * w * hoop) + w * m * gravity[0];
                sums.force[1] += -vol * (s[3] * g[0] + s[1] * g[1]) + w * m * gravity[1];
            });
        }
        lane.touched = touched;
    });
    let reached = state.lanes.iter().fold(NodeBox::EMPTY, |b, lane| b.union(lane.touched));
    state.scratch.grid_region = reached.union(state.scratch.grid_reached);
    state.scratch.grid_reached = reached;
    sum_lanes(&state.lanes, grid.nodes[0], state.scratch.grid_region, &mut state.fields, true);
}

