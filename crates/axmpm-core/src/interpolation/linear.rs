//! Original MPM: the bilinear hat function of the cell containing the particle
//! (Sulsky, Chen & Schreyer 1994). Cheapest, and noisy when particles cross cell faces.

#[cfg(doc)]
use super::bilinear_nodes;
use super::{clamped_floor, NodeBox, ParticleDomain, ShapeFunction};
#[cfg(test)]
use super::Stencil;
use crate::grid::GridGeometry;

pub struct Linear;

impl ShapeFunction for Linear {
    const NAME: &'static str = "linear";

    /// The particle's cell and its position in it, located once per step.
    type Cache = LinearCache;

    #[inline(always)]
    fn prepare(grid: &GridGeometry, domain: &ParticleDomain, _: bool, cache: &mut LinearCache) {
        // Particles are always inside the grid (the step fails as soon as one leaves it), so the
        // cell index is clamped to the grid instead of testing every node: all 4 nodes exist.
        // The clamp only matters for a particle exactly on the upper edge, which then gets
        // weight 1 and a one-sided gradient from the last cell instead of a dropped node.
        let l = grid.local(domain.position);
        let ci = clamped_floor(l[0], (grid.cells[0] - 1) as f64);
        let cj = clamped_floor(l[1], (grid.cells[1] - 1) as f64);
        *cache = LinearCache { cell: [ci, cj], fraction: [l[0] - ci as f64, l[1] - cj as f64] };
    }

    /// The 4 nodes of the particle's cell, in the order of [`bilinear_nodes`] (row by row),
    /// with the same arithmetic, so the two agree bit for bit for any point inside the grid.
    #[inline(always)]
    fn visit_entries(
        grid: &GridGeometry,
        cache: &LinearCache,
        _: &ParticleDomain,
        _: bool,
        mut visit: impl FnMut(usize, f64, [f64; 2]),
    ) {
        let [ci, cj] = cache.cell;
        let [fx, fy] = cache.fraction;
        let ih = grid.inverse_cell_size;
        let wx = [1.0 - fx, fx];
        let wy = [1.0 - fy, fy];
        let dx = [-ih, ih];
        let nx = grid.nodes[0];
        let base = cj as usize * nx + ci as usize;
        let nodes = [[base, base + 1], [base + nx, base + nx + 1]];
        for b in 0..2 {
            for a in 0..2 {
                visit(nodes[b][a], wx[a] * wy[b], [dx[a] * wy[b], wx[a] * dx[b]]);
            }
        }
    }

    #[inline(always)]
    fn node_box(_: &GridGeometry, cache: &LinearCache, _: &ParticleDomain) -> NodeBox {
        let [ci, cj] = cache.cell;
        NodeBox { columns: [ci, ci + 1], rows: [cj, cj + 1] }
    }
}

/// A particle located in its cell: the lower-left node (i, j) and the fractional position.
#[derive(Clone, Copy, Debug, Default)]
pub struct LinearCache {
    cell: [u32; 2],
    fraction: [f64; 2],
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interpolation::testing::*;

    #[test]
    fn partition_of_unity_and_zero_gradient_sum() {
        check_partition_of_unity::<Linear>([0.025, 0.025], false);
    }

    #[test]
    fn equals_bilinear_nodes_bit_for_bit_inside_the_grid() {
        let g = grid();
        let mut st = Stencil::default();
        for a in 0..=50 {
            for b in 0..=50 {
                // Includes the origin edges and points on cell faces.
                let x = [a as f64 * 0.0199 + 1e-3 * (b % 3) as f64, b as f64 * 0.0199];
                let p = single_particle(x, [0.025; 2]);
                Linear::stencil(&g, &p, 0, false, &mut st);
                let mut reference = Stencil::default();
                crate::interpolation::bilinear_nodes(&g, x, |node, w, d| reference.push(node, w, d));
                assert_eq!(st.len, reference.len, "at {x:?}");
                for k in 0..st.len {
                    assert_eq!(st.node[k], reference.node[k]);
                    assert_eq!(st.weight[k].to_bits(), reference.weight[k].to_bits());
                    assert_eq!(st.gradient[k][0].to_bits(), reference.gradient[k][0].to_bits());
                    assert_eq!(st.gradient[k][1].to_bits(), reference.gradient[k][1].to_bits());
                }
            }
        }
        // On the upper edge the last cell is used: weight 1 on the edge node.
        Linear::stencil(&g, &single_particle([1.0, 0.55], [0.025; 2]), 0, false, &mut st);
        assert_eq!(st.len, 4);
        assert!((st.weight_sum() - 1.0).abs() < 1e-15);
    }

    /// A particle exactly on the upper grid edge (x = 1.0, and at the corner) is located in the
    /// last cell, not in the one beyond: the 4 nodes of that cell, weight 1 on the edge node and
    /// the one-sided gradient of the last cell, +1/h towards the edge.
    #[test]
    fn a_particle_on_the_upper_edge_uses_the_last_cell() {
        let g = grid(); // 10 × 10 cells of 0.1
        let mut st = Stencil::default();
        Linear::stencil(&g, &single_particle([1.0, 0.55], [0.025; 2]), 0, false, &mut st);
        let nodes: Vec<usize> = (0..st.len).map(|k| st.node[k] as usize).collect();
        assert_eq!(nodes, [g.node_index(9, 5), g.node_index(10, 5), g.node_index(9, 6), g.node_index(10, 6)]);
        assert_eq!(st.node_box, NodeBox { columns: [9, 10], rows: [5, 6] });
        // Node (10, 5): S = 1 · 0.5, ∂S/∂x = +10 · 0.5, ∂S/∂y = 1 · (−10).
        assert!((st.weight[1] - 0.5).abs() < 1e-12 && st.weight[0].abs() < 1e-12);
        assert!((st.gradient[1][0] - 5.0).abs() < 1e-12 && (st.gradient[1][1] + 10.0).abs() < 1e-12);
        assert!((st.gradient[0][0] + 5.0).abs() < 1e-12);
        Linear::stencil(&g, &single_particle([1.0, 1.0], [0.025; 2]), 0, false, &mut st);
        let nodes: Vec<usize> = (0..st.len).map(|k| st.node[k] as usize).collect();
        assert_eq!(nodes, [g.node_index(9, 9), g.node_index(10, 9), g.node_index(9, 10), g.node_index(10, 10)]);
        assert_eq!(st.weight[3], 1.0);
        assert_eq!(st.gradient[3], [10.0, 10.0]);
    }

    #[test]
    fn weights_match_hat_function_by_hand() {
        // Particle at (0.13, 0.27) in a 0.1 grid: local (1.3, 2.7), cell (1, 2).
        let g = grid();
        let p = single_particle([0.13, 0.27], [0.025; 2]);
        let mut st = Stencil::default();
        Linear::stencil(&g, &p, 0, false, &mut st);
        assert_eq!(st.len, 4);
        let expect = [(1usize, 2usize, 0.7 * 0.3), (2, 2, 0.3 * 0.3), (1, 3, 0.7 * 0.7), (2, 3, 0.3 * 0.7)];
        for (i, j, w) in expect {
            let node = g.node_index(i, j);
            let k = (0..st.len).find(|&k| st.node[k] as usize == node).unwrap();
            assert!((st.weight[k] - w).abs() < 1e-12);
        }
        // ∂S/∂x for node (1,2) = −(1/h)·0.3 = −3
        let k = (0..st.len).find(|&k| st.node[k] as usize == g.node_index(1, 2)).unwrap();
        assert!((st.gradient[k][0] + 3.0).abs() < 1e-12);
        assert!((st.gradient[k][1] + 7.0).abs() < 1e-12);
    }
}
