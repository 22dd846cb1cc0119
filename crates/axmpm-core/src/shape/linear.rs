//! Original MPM: the bilinear hat function of the cell containing the particle
//! (Sulsky, Chen & Schreyer 1994). Cheapest, and noisy when particles cross cell faces.

use super::{bilinear_nodes, ParticleDomain, ShapeFunction, Stencil};
use crate::grid::GridGeometry;

pub struct Linear;

impl ShapeFunction for Linear {
    const NAME: &'static str = "linear";

    #[inline(always)]
    fn stencil_at(grid: &GridGeometry, domain: &ParticleDomain, _axisymmetric: bool, out: &mut Stencil) {
        out.clear();
        bilinear_nodes(grid, domain.position, |node, w, g| out.push(node, w, g));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::testing::*;

    #[test]
    fn partition_of_unity_and_zero_gradient_sum() {
        check_partition_of_unity::<Linear>([0.025, 0.025], false);
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
