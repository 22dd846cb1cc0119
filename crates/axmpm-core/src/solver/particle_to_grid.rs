//! Particle → grid: the nodal mass m_i = Σ_p S_ip m_p, momentum p_i = Σ_p S_ip m_p v_p and
//! force f_i = f_int + f_ext (docs/physics.md §1–2), with
//! f_int = −Σ_p V_p σ_p·∇S_ip (plus the hoop term −V_p σ_θθ S_ip / R_p in axisymmetry) and
//! f_ext = Σ_p S_ip m_p g.

use super::tiles::{inside, scatter_by_colour, zero_box, Shared, TileReach};
use super::State;
use crate::formulation::Formulation;
use crate::grid::{GridGeometry, NodeBox};
use crate::interpolation::{ParticleDomain, ShapeFunction};
use crate::particles::Particles;

/// The grid fields particle → grid adds to, shared by the tiles of one colour (disjoint zones).
#[derive(Clone, Copy)]
struct NodalTargets {
    mass: Shared<f64>,
    momentum: Shared<[f64; 2]>,
    force: Shared<[f64; 2]>,
}

/// Scatters mass, momentum, internal and gravity forces to the nodes tile by tile, colour by
/// colour (see [`super::tiles`]). Computes each particle's stencil cache for the step.
#[inline(never)] // one call per step; a symbol of its own for profiles (callgrind --toggle-collect)
pub(super) fn particle_to_grid<F: Formulation, S: ShapeFunction>(state: &mut State, gravity: [f64; 2], cache: &mut [S::Cache]) {
    let grid = state.grid;
    let nodes_x = grid.nodes[0];
    // Every field is +0 outside the nodes the particles reached last step.
    let previous = state.scratch.grid_reached;
    zero_box(&mut state.fields.mass, nodes_x, previous);
    zero_box(&mut state.fields.momentum, nodes_x, previous);
    zero_box(&mut state.fields.force, nodes_x, previous);
    let targets = NodalTargets {
        mass: Shared::new(&mut state.fields.mass),
        momentum: Shared::new(&mut state.fields.momentum),
        force: Shared::new(&mut state.fields.force),
    };
    let particles = &state.particles;
    let order = &mut state.tiles;
    let caches = Shared::new(cache);
    let isa = state.parameters.isa;
    let (mut reached, mut serial) = scatter_by_colour(order, |tile, overflow| {
        // SAFETY: tiles are disjoint particle ranges; within a colour, a tile writes only to
        // nodes inside its zone, and zones of one colour are disjoint; the overflow pass runs
        // alone.
        let cache = unsafe { caches.slice(tile.range()) };
        // Two call sites with `overflow` a constant, so that each is compiled for its case: the
        // zone test and the cache preparation then leave the hot (parallel) loop's code when not
        // needed (passed as a variable, they cost the dry bench 5 % more instructions).
        if overflow {
            isa.run(
                #[inline(always)]
                || unsafe { scatter::<F, S>(&grid, gravity, particles, tile.range(), tile.zone(), cache, targets, true) },
            )
        } else {
            isa.run(
                #[inline(always)]
                || unsafe { scatter::<F, S>(&grid, gravity, particles, tile.range(), tile.zone(), cache, targets, false) },
            )
        }
    });
    if !particles.external_force.is_empty() {
        let serial_start = std::time::Instant::now();
        let loads = super::surface_load::add_surface_loads(&grid, particles, state.load_factor, &mut state.fields.force);
        reached = reached.union(loads);
        serial += serial_start.elapsed();
    }
    state.scratch.grid_region = reached.union(previous);
    state.scratch.grid_reached = reached;
    state.timings.serial += serial.as_secs_f64();
}

/// Adds the particles `range` to the nodes: with `overflow` false, prepares each particle's
/// stencil cache and adds the particles whose stencil stays in `zone`; with `overflow` true
/// (after the colour's parallel part), adds the others.
/// SAFETY: no other thread writes to the nodes this call writes to (see [`super::tiles`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
unsafe fn scatter<F: Formulation, S: ShapeFunction>(
    grid: &GridGeometry,
    gravity: [f64; 2],
    particles: &Particles,
    range: std::ops::Range<usize>,
    zone: NodeBox,
    cache: &mut [S::Cache],
    targets: NodalTargets,
    overflow: bool,
) -> TileReach {
    let mut reach = TileReach::default();
    // Local copies of what the loop reads: the compiler then keeps them in registers instead
    // of reloading them after every nodal store (which it cannot prove does not alias them).
    let (grid, gravity) = (*grid, gravity);
    let corners = &particles.corners[..];
    // The tile's particles as slices of one length, so the loop indexes without bounds checks.
    let n = cache.len();
    let first = range.start;
    let position = &particles.position[range.clone()];
    let initial_half_width = &particles.initial_half_width[range.clone()];
    let deformation_gradient = &particles.deformation_gradient[range.clone()];
    let mass = &particles.mass[range.clone()];
    let velocity = &particles.velocity[range.clone()];
    let volume = &particles.volume[range.clone()];
    let stress = &particles.stress[range];
    for (i, c) in cache[..n].iter_mut().enumerate() {
        let domain = ParticleDomain {
            position: position[i],
            initial_half_width: initial_half_width[i],
            deformation_gradient: &deformation_gradient[i],
            corners: corners.get(first + i),
        };
        if !overflow {
            S::prepare(&grid, &domain, F::AXISYMMETRIC, c);
        }
        // Read-only from here (a shared reborrow measured 4 instructions per particle-step
        // fewer for cpGIMP than the mutable one).
        let c = &*c;
        let node_box = S::node_box(&grid, c, &domain);
        let in_zone = inside(node_box, zone);
        if !overflow {
            reach.reached = reach.reached.union(node_box);
            reach.overflow |= !in_zone;
        }
        if in_zone == overflow {
            continue;
        }
        // What every node of the particle shares, formed once per particle: m v, −V σ and
        // the body force m g (with the hoop term −V σ_θθ S / R_p, also linear in S).
        let m = mass[i];
        let v = velocity[i];
        let vol = volume[i];
        let s = stress[i];
        let momentum = [m * v[0], m * v[1]];
        let minus_vs = [-vol * s[0], -vol * s[1], -vol * s[3]];
        // (No hoop term in plane strain, where it would be −V σ_θθ · 0.)
        let hoop = if F::AXISYMMETRIC { vol * s[2] * F::hoop_factor(position[i]) } else { 0.0 };
        let body = [m * gravity[0] - hoop, m * gravity[1]];
        // `move`: the closure holds its own copies of the pointers and values, which the
        // compiler keeps in registers (captured by reference, it reloads them after every
        // store through the pointers, which it cannot prove do not alias them).
        S::visit_entries(&grid, c, &domain, F::AXISYMMETRIC, move |node, w, g| {
            *targets.mass.at(node) += w * m;
            let p = targets.momentum.at(node);
            p[0] += w * momentum[0];
            p[1] += w * momentum[1];
            // Internal force −V σ·∇S (Sulsky & Schreyer 1996, docs/physics.md §2) plus gravity.
            let f = targets.force.at(node);
            f[0] += minus_vs[0] * g[0] + minus_vs[2] * g[1] + w * body[0];
            f[1] += minus_vs[2] * g[0] + minus_vs[1] * g[1] + w * body[1];
        });
    }
    reach
}
