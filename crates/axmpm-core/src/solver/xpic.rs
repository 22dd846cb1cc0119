//! XPIC(m), the extended particle-in-cell filter of the velocity update (Hammerquist & Nairn
//! 2017, Comput. Methods Appl. Mech. Engrg. 318:724–738; docs/physics.md §1).
//!
//! Write P for the round trip particle → grid → particle of a velocity field (mass-weighted
//! projection onto the nodes, then interpolation back). FLIP keeps the part (I − P) v_p of the
//! particles' velocities that the grid cannot represent; PIC removes all of it, and with it a
//! share of every smooth motion, since P smooths over a stencil: the PIC share of a FLIP/PIC
//! blend damps the velocity field at the rate (1 − FLIP)/Δt, a numerical viscosity of the order
//! (1 − FLIP) h²/Δt that grows as the time step shrinks. XPIC(m) removes (I − P)^m v_p instead:
//! the grid's null-space noise (where P ≈ 0) as fully as PIC, smooth motion (where P ≈ I) to the
//! order m. Expanding the binomial, the particle's non-FLIP velocity becomes
//!
//!   v_p ← Σ_i S_ip (v⁺_i − v_i + v*_i),   v* = Σ_{k=1..m} (−1)^{k+1} C(m, k) G^{k−1} v,
//!
//! with v the start-of-step nodal velocity and G the round trip grid → particle → grid,
//! (G w)_i = Σ_p S_ip m_p (Σ_j S_jp w_j) / m_i. m = 1 gives v* = v, i.e. PIC. Each order above 1
//! costs one pass over the particles (gather and scatter), tiled and coloured like the others,
//! so the sums do not depend on the thread count.

use rayon::prelude::*;

use super::tiles::{inside, zero_box, Shared, COLOURS};
use super::State;
use crate::constraint::NodalContext;
use crate::formulation::Formulation;
use crate::grid::{GridGeometry, NodeBox};
use crate::interpolation::{ParticleDomain, ShapeFunction};
use crate::particles::Particles;

/// The nodal fields of the filter, allocated once for the run.
#[derive(Default)]
pub struct XpicFields {
    /// The current term C(m, k) G^{k−1} v of the sum.
    term: Vec<[f64; 2]>,
    /// Σ_p S_ip m_p (Σ_j S_jp term_j), before the division by m_i.
    projected: Vec<[f64; 2]>,
    /// v*, the filtered start-of-step velocity.
    pub velocity_star: Vec<[f64; 2]>,
}

impl XpicFields {
    pub fn new(num_nodes: usize) -> Self {
        Self {
            term: vec![[0.0; 2]; num_nodes],
            projected: vec![[0.0; 2]; num_nodes],
            velocity_star: vec![[0.0; 2]; num_nodes],
        }
    }
}

/// Computes v* (module doc) into `state.scratch.xpic.velocity_star` from the start-of-step
/// nodal velocity, for the step's XPIC order m ≥ 2; the faces' and the axis's start-of-step
/// constraints then apply to it as they did to v.
pub(super) fn filtered_velocity<F: Formulation, S: ShapeFunction>(state: &mut State, dt: f64, cache: &[S::Cache]) {
    let m = state.parameters.xpic_order;
    debug_assert!(m >= 2);
    let Some(fields) = state.scratch.xpic.as_mut() else { return };
    let nx = state.grid.nodes[0];
    let region = state.scratch.grid_region;
    let (first_row, rows) = region.row_span();
    let columns = region.column_span(nx);
    let mass = &state.fields.mass;
    // k = 1: term = star = m v.
    let order = m as f64;
    fields
        .term
        .par_chunks_mut(nx)
        .zip(fields.velocity_star.par_chunks_mut(nx))
        .zip(state.fields.velocity.par_chunks(nx))
        .skip(first_row)
        .take(rows)
        .for_each(|((term, star), v)| {
            let c = columns.clone();
            for ((t, s), v) in term[c.clone()].iter_mut().zip(&mut star[c.clone()]).zip(&v[c]) {
                *t = [order * v[0], order * v[1]];
                *s = *t;
            }
        });
    let mut serial = std::time::Duration::ZERO;
    for k in 2..=m {
        zero_box(&mut fields.projected, nx, region);
        serial += project::<F, S>(&state.grid, &state.particles, &state.tiles, cache, &fields.term, &mut fields.projected);
        // term_k = C(m, k) G^{k−1} v = (m − k + 1)/k · G term_{k−1}; star += (−1)^{k+1} term_k.
        let scale = (m - k + 1) as f64 / k as f64;
        let sign = if k % 2 == 0 { -1.0 } else { 1.0 };
        fields
            .term
            .par_chunks_mut(nx)
            .zip(fields.velocity_star.par_chunks_mut(nx))
            .zip(fields.projected.par_chunks(nx))
            .zip(mass.par_chunks(nx))
            .skip(first_row)
            .take(rows)
            .for_each(|(((term, star), projected), mass)| {
                let c = columns.clone();
                let row = term[c.clone()].iter_mut().zip(&mut star[c.clone()]).zip(&projected[c.clone()]).zip(&mass[c]);
                for (((t, s), p), &mi) in row {
                    *t = if mi > 0.0 { [scale * p[0] / mi, scale * p[1] / mi] } else { [0.0; 2] };
                    s[0] += sign * t[0];
                    s[1] += sign * t[1];
                }
            });
    }
    let serial_start = std::time::Instant::now();
    let context = NodalContext { grid: &state.grid, mass, time: state.time, dt, axisymmetric: state.parameters.axisymmetric };
    state.constraints.apply_start_of_step(&context, &mut fields.velocity_star);
    serial += serial_start.elapsed();
    state.timings.serial += serial.as_secs_f64();
}

/// Adds Σ_p S_ip m_p (Σ_j S_jp input_j) to `output` (zero where the particles reach), tile by
/// tile, colour by colour, the particles that left their tile's zone on one thread (as the
/// MUSL re-map of `grid_to_particle`). Returns the time spent on one thread.
fn project<F: Formulation, S: ShapeFunction>(
    grid: &GridGeometry,
    particles: &Particles,
    order: &super::TileOrder,
    cache: &[S::Cache],
    input: &[[f64; 2]],
    output: &mut [[f64; 2]],
) -> std::time::Duration {
    let output = Shared::new(output);
    let mut serial = std::time::Duration::ZERO;
    for c in 0..COLOURS {
        let range = order.colour(c);
        order.tiles[range.clone()].par_iter().zip(&order.reach[range.clone()]).for_each(|(tile, reach)| {
            let zone = if reach.overflow { Some(tile.zone()) } else { None };
            // SAFETY: within a colour a tile writes only to nodes inside its zone, and zones of
            // one colour are disjoint (`super::tiles`).
            unsafe { project_tile::<F, S>(grid, particles, tile.range(), cache, zone, input, output, false) };
        });
        let serial_start = std::time::Instant::now();
        for (tile, reach) in order.tiles[range.clone()].iter().zip(&order.reach[range]) {
            if reach.overflow {
                // SAFETY: nothing else runs now.
                unsafe { project_tile::<F, S>(grid, particles, tile.range(), cache, Some(tile.zone()), input, output, true) };
            }
        }
        serial += serial_start.elapsed();
    }
    serial
}

/// The particles `range` of one tile: with `overflow` false those whose stencil stays in
/// `zone` (`None`: all), with `overflow` true the others.
/// SAFETY: no other thread writes to the nodes this call writes to.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
unsafe fn project_tile<F: Formulation, S: ShapeFunction>(
    grid: &GridGeometry,
    particles: &Particles,
    range: std::ops::Range<usize>,
    cache: &[S::Cache],
    zone: Option<NodeBox>,
    input: &[[f64; 2]],
    output: Shared<[f64; 2]>,
    overflow: bool,
) {
    for p in range {
        let domain = ParticleDomain {
            position: particles.position[p],
            initial_half_width: particles.initial_half_width[p],
            deformation_gradient: &particles.deformation_gradient[p],
            corners: particles.corners.get(p),
        };
        let in_zone = zone.is_none_or(|z| inside(S::node_box(grid, &cache[p], &domain), z));
        if in_zone == overflow {
            continue;
        }
        let mut u = [0.0; 2];
        S::visit_entries(grid, &cache[p], &domain, F::AXISYMMETRIC, |node, w, _| {
            let v = input[node];
            u[0] += w * v[0];
            u[1] += w * v[1];
        });
        let mu = [particles.mass[p] * u[0], particles.mass[p] * u[1]];
        S::visit_entries(grid, &cache[p], &domain, F::AXISYMMETRIC, move |node, w, _| {
            let o = output.at(node);
            o[0] += w * mu[0];
            o[1] += w * mu[1];
        });
    }
}
