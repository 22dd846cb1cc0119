//! Surface loads: the surcharges of a dry or saturated body and a saturated body's surface
//! load, carried by the particles of the loaded surface (`Particles::external_force`, set up
//! in `setup.rs`) and added to the nodal forces f_ext at the surface point each particle
//! carries (docs/physics.md §11).

use crate::grid::{GridGeometry, NodeBox};
use crate::particles::Particles;

/// Adds each loaded particle's surface load to the nodes at the point of the surface it
/// carries, its upper edge (x_p, y_p + l_y F22): the bilinear weights of that point's cell, so
/// that the load reaches the surface's nodes, as a traction does, and not the particle's
/// centre (where the material above it would carry none of it). One thread, in array order.
/// The loads are scaled by `factor` (the ramp shared with gravity). Returns the nodes it
/// added to.
pub(super) fn add_surface_loads(grid: &GridGeometry, particles: &Particles, factor: f64, force: &mut [[f64; 2]]) -> NodeBox {
    let mut reached = NodeBox::EMPTY;
    for (p, load) in particles.external_force.iter().enumerate() {
        if *load == [0.0; 2] {
            continue;
        }
        let load = [factor * load[0], factor * load[1]];
        let x = particles.position[p];
        let point = [x[0], x[1] + particles.initial_half_width[p][1] * particles.deformation_gradient[p][3]];
        let [i, j] = grid.cell_of(point);
        let local = grid.local(point);
        let (fx, fy) = ((local[0] - i as f64).clamp(0.0, 1.0), (local[1] - j as f64).clamp(0.0, 1.0));
        for (di, dj, w) in [(0, 0, (1.0 - fx) * (1.0 - fy)), (1, 0, fx * (1.0 - fy)), (0, 1, (1.0 - fx) * fy), (1, 1, fx * fy)] {
            if w > 0.0 {
                let node = grid.node_index(i + di, j + dj);
                force[node][0] += w * load[0];
                force[node][1] += w * load[1];
                let (c, r) = ((i + di) as u32, (j + dj) as u32);
                reached = reached.union(NodeBox { columns: [c, c], rows: [r, r] });
            }
        }
    }
    reached
}
