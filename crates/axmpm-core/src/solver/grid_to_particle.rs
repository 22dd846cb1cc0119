//! Grid → particle: the FLIP/PIC velocity blend
//! v_p ← FLIP (v_p + Σ_i S_ip (v⁺_i − v_i)) + (1 − FLIP) Σ_i S_ip v⁺_i and the position
//! increment Δx_p = Δt Σ_i S_ip v⁺_i; with XPIC(m), m > 1, the non-FLIP share is
//! Σ_i S_ip (v⁺_i − v_i + v*_i) ([`super::xpic`]); with MUSL, the new momentum Σ_p S_ip m_p v_p
//! is scattered back to the grid in the same pass.

use rayon::prelude::*;

use super::grid_update::remap_velocity;
use super::tiles::{inside, zero_box, Shared, COLOURS};
use super::State;
use crate::config::UpdateScheme;
use crate::formulation::Formulation;
use crate::grid::{GridGeometry, NodeBox};
use crate::interpolation::{ParticleDomain, ShapeFunction};
use crate::particles::Particles;

/// What one tile of grid → particle reads and writes.
#[derive(Clone, Copy)]
struct Pass<'a> {
    grid: GridGeometry,
    flip: f64,
    dt: f64,
    velocity_new: &'a [[f64; 2]],
    velocity_old: &'a [[f64; 2]],
    /// XPIC(m > 1) only: the filtered start-of-step velocity v*.
    velocity_star: Option<&'a [[f64; 2]]>,
    /// The momentum the MUSL re-map adds to (`None`: USL, no re-map).
    momentum: Option<Shared<[f64; 2]>>,
}

/// New particle velocities (PIC/FLIP blend) and position increments; with MUSL the new
/// momentum is scattered back to the grid in the same pass (same stencils, same tiles and
/// colours as particle → grid).
#[inline(never)] // one call per step; a symbol of its own for profiles (callgrind --toggle-collect)
pub(super) fn grid_to_particle<F: Formulation, S: ShapeFunction>(state: &mut State, dt: f64, cache: &[S::Cache]) {
    if state.parameters.xpic_order > 1 {
        super::xpic::filtered_velocity::<F, S>(state, dt, cache);
    }
    let musl = state.parameters.scheme == UpdateScheme::Musl;
    let nodes_x = state.grid.nodes[0];
    // The re-map reaches the nodes particle → grid reached; elsewhere the momentum is +0.
    if musl {
        zero_box(&mut state.fields.momentum, nodes_x, state.scratch.grid_reached);
    }
    let fields = &mut state.fields;
    let pass = Pass {
        grid: state.grid,
        flip: state.parameters.flip_fraction,
        dt,
        momentum: if musl { Some(Shared::new(&mut fields.momentum)) } else { None },
        velocity_new: &fields.velocity_new,
        velocity_old: &fields.velocity,
        velocity_star: state.scratch.xpic.as_ref().map(|x| &x.velocity_star[..]),
    };
    let velocities = Shared::new(&mut state.particles.velocity);
    let displacements = Shared::new(&mut state.scratch.displacement);
    let particles = &state.particles;
    let order = &state.tiles;
    let isa = state.parameters.isa;
    let mut serial = std::time::Duration::ZERO;
    for c in 0..COLOURS {
        let range = order.colour(c);
        order.tiles[range.clone()].par_iter().zip(&order.reach[range.clone()]).for_each(|(tile, reach)| {
            // SAFETY: tiles are disjoint particle ranges; within a colour, a tile writes only
            // to nodes inside its zone, and zones of one colour are disjoint.
            let (v, dx) = unsafe { (velocities.slice(tile.range()), displacements.slice(tile.range())) };
            let zone = if reach.overflow { Some(tile.zone()) } else { None };
            // The filter as a constant, so that the PIC path's loop is compiled without it.
            if pass.velocity_star.is_some() {
                isa.run(
                    #[inline(always)]
                    || unsafe { gather::<F, S, true>(&pass, particles, tile.range(), cache, zone, v, dx, false) },
                );
            } else {
                isa.run(
                    #[inline(always)]
                    || unsafe { gather::<F, S, false>(&pass, particles, tile.range(), cache, zone, v, dx, false) },
                );
            }
        });
        if musl {
            // The particles that left their tile's zone re-map on this thread, in array order.
            let serial_start = std::time::Instant::now();
            for (tile, reach) in order.tiles[range.clone()].iter().zip(&order.reach[range]) {
                if reach.overflow {
                    // SAFETY: nothing else runs now.
                    let (v, dx) = unsafe { (velocities.slice(tile.range()), displacements.slice(tile.range())) };
                    isa.run(
                        #[inline(always)]
                        || unsafe { gather::<F, S, false>(&pass, particles, tile.range(), cache, Some(tile.zone()), v, dx, true) },
                    );
                }
            }
            serial += serial_start.elapsed();
        }
    }
    state.timings.serial += serial.as_secs_f64();
    if musl {
        remap_velocity(state, dt);
    }
}

/// Velocity and position increment of the particles `range` (with `overflow` false), and the
/// MUSL re-map of those whose stencil stays in `zone` (`None`: all of them stay). With
/// `overflow` true: only the re-map of the others, after the colour's parallel part.
/// SAFETY: no other thread writes to the nodes this call writes to (see [`super::tiles`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
unsafe fn gather<F: Formulation, S: ShapeFunction, const XPIC: bool>(
    pass: &Pass,
    particles: &Particles,
    range: std::ops::Range<usize>,
    cache: &[S::Cache],
    zone: Option<NodeBox>,
    velocity_io: &mut [[f64; 2]],
    displacement_out: &mut [[f64; 2]],
    overflow: bool,
) {
    // Local copies and slices, kept in registers across the nodal stores (see P2G).
    let Pass { grid, flip, dt, velocity_new, velocity_old, velocity_star, momentum } = *pass;
    debug_assert!(velocity_new.len() == grid.num_nodes() && velocity_old.len() == grid.num_nodes());
    let corners: &[[[f64; 2]; 4]] = &particles.corners;
    // The tile's particles as slices of one length (no bounds checks in the loop).
    let n = velocity_io.len();
    let first = range.start;
    let position = &particles.position[first..first + n];
    let initial_half_width = &particles.initial_half_width[first..first + n];
    let deformation_gradient = &particles.deformation_gradient[first..first + n];
    let mass = &particles.mass[first..first + n];
    let cache = &cache[first..first + n];
    for (i, (v_io, dx)) in velocity_io.iter_mut().zip(displacement_out[..n].iter_mut()).enumerate() {
        let domain = ParticleDomain {
            position: position[i],
            initial_half_width: initial_half_width[i],
            deformation_gradient: &deformation_gradient[i],
            corners: corners.get(first + i),
        };
        let in_zone = zone.is_none_or(|z| inside(S::node_box(&grid, &cache[i], &domain), z));
        if !overflow {
            let mut v_grid = [0.0; 2];
            let mut dv = [0.0; 2];
            S::visit_entries(&grid, &cache[i], &domain, F::AXISYMMETRIC, |node, w, _| {
                debug_assert!(node < velocity_new.len() && node < velocity_old.len());
                // SAFETY: a stencil visits only nodes of the grid (`ShapeFunction::visit_entries`),
                // and both nodal velocity fields have one entry per node.
                let (vn, vo) = unsafe { (*velocity_new.get_unchecked(node), *velocity_old.get_unchecked(node)) };
                v_grid[0] += w * vn[0];
                v_grid[1] += w * vn[1];
                dv[0] += w * (vn[0] - vo[0]);
                dv[1] += w * (vn[1] - vo[1]);
            });
            // The non-FLIP share: PIC, or XPIC(m) with Σ S (v* − v) added.
            let v_pic = match velocity_star {
                Some(velocity_star) if XPIC => {
                    let mut filtered = v_grid;
                    S::visit_entries(&grid, &cache[i], &domain, F::AXISYMMETRIC, |node, w, _| {
                        let (vs, vo) = (velocity_star[node], velocity_old[node]);
                        filtered[0] += w * (vs[0] - vo[0]);
                        filtered[1] += w * (vs[1] - vo[1]);
                    });
                    filtered
                }
                _ => v_grid,
            };
            let v = *v_io;
            *v_io = [
                flip * (v[0] + dv[0]) + (1.0 - flip) * v_pic[0],
                flip * (v[1] + dv[1]) + (1.0 - flip) * v_pic[1],
            ];
            *dx = [dt * v_grid[0], dt * v_grid[1]];
        }
        if let Some(momentum) = momentum {
            if in_zone != overflow {
                let m = mass[i];
                let mv = [m * v_io[0], m * v_io[1]];
                S::visit_entries(&grid, &cache[i], &domain, F::AXISYMMETRIC, move |node, w, _| {
                    let p = momentum.at(node);
                    p[0] += w * mv[0];
                    p[1] += w * mv[1];
                });
            }
        }
    }
}
