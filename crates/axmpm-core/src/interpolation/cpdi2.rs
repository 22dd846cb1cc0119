//! CPDI2, the second-order convected particle domain interpolation (Sadeghirad, Brannon &
//! Guilkey 2013, IJNME): each particle is a quadrilateral whose corners x_c (c = 1..4,
//! counter-clockwise from the lower left, `particles.corners[p]`) move with the grid velocity.
//! The hat N_i is replaced on the domain by its bilinear interpolant through the corners,
//! N_i ≈ Σ_c N_i(x_c) M_c(ξ, η), and averaged exactly over the quadrilateral:
//!
//!   S_ip = Σ_c w_c N_i(x_c),   ∇S_ip = Σ_c w̃_c N_i(x_c),
//!
//! with V the shoelace area and, for corners 1..4,
//!
//!   a = (x4−x1)(y2−y3) − (x2−x3)(y4−y1),   b = (x3−x4)(y1−y2) − (x1−x2)(y3−y4),
//!   w = [6V−a−b, 6V−a+b, 6V+a+b, 6V+a−b] / (24V),
//!   w̃1 = (y2−y4, x4−x2)/(2V), w̃2 = (y3−y1, x1−x3)/(2V), w̃3 = −w̃1, w̃4 = −w̃2.
//!
//! These are docs/physics.md §3's formulas; they are verified (not assumed) by the unit test
//! `weights_equal_gauss_quadrature_of_the_corner_interpolant`, which integrates the corner
//! interpolant of every N_i and its gradient over random convex quadrilaterals with 4 × 4
//! Gauss points. (The gradient weights follow from the divergence theorem: along each edge
//! the interpolant is linear, so ∫ ∇f dA = Σ_edges (f_c + f_c+1)/2 · n_edge |edge|.)
//!
//! Each corner contributes the 4 nodes of its cell (`bilinear_nodes`), so the stencil has up
//! to 16 entries and may repeat nodes. Truncation:
//! - nodes outside the grid are dropped; [`Cpdi2::advect_corners`] clamps corners to the grid
//!   box, so a domain never loses weight to the outside;
//! - axisymmetry: corners are clamped to r ≥ 0 when advected, and also (defensively) when
//!   the stencil is evaluated, so the quadrilateral never reaches across the axis.
//! - A degenerate or inverted quadrilateral (V ≤ 0 or not finite) falls back to the linear
//!   hat at the particle position, so the solver does not divide by zero.

use super::{at_least, bilinear_nodes, clamp_between, CellPoint, ParticleDomain, ShapeFunction, NodeBox};
#[cfg(test)]
use super::Stencil;
use crate::grid::GridGeometry;

pub struct Cpdi2;

/// Shoelace area of a quadrilateral (positive for counter-clockwise corners).
#[inline(always)]
fn shoelace(c: &[[f64; 2]; 4]) -> f64 {
    // 2V = (x3 − x1)(y4 − y2) − (x4 − x2)(y3 − y1) for a quadrilateral (diagonal form).
    0.5 * ((c[2][0] - c[0][0]) * (c[3][1] - c[1][1]) - (c[3][0] - c[1][0]) * (c[2][1] - c[0][1]))
}

/// CPDI2 corner weights w_c, gradient weights w̃_c and the area V.
#[inline(always)]
fn corner_weights(c: &[[f64; 2]; 4]) -> ([f64; 4], [[f64; 2]; 4], f64) {
    let [[x1, y1], [x2, y2], [x3, y3], [x4, y4]] = *c;
    let v = shoelace(c);
    let a = (x4 - x1) * (y2 - y3) - (x2 - x3) * (y4 - y1);
    let b = (x3 - x4) * (y1 - y2) - (x1 - x2) * (y3 - y4);
    let inv24 = 1.0 / (24.0 * v);
    let six = 6.0 * v;
    let w = [(six - a - b) * inv24, (six - a + b) * inv24, (six + a + b) * inv24, (six + a - b) * inv24];
    let inv2 = 0.5 / v;
    let g1 = [(y2 - y4) * inv2, (x4 - x2) * inv2];
    let g2 = [(y3 - y1) * inv2, (x1 - x3) * inv2];
    (w, [g1, g2, [-g1[0], -g1[1]], [-g2[0], -g2[1]]], v)
}

/// What CPDI2 keeps of a particle between the passes of a step: the cell of each corner
/// (start of the step, clamped to the axis) and the corner weights, so the 16-entry stencil
/// is expanded without recomputing them. The corners themselves move only at the end of the
/// step ([`Cpdi2::advect_corners`]), after every pass has used the stencil, so each expansion
/// recomputes the corners' fractional positions in their cells from the corners, with the
/// arithmetic of [`CellPoint::locate`] (bit for bit): two subtractions and a multiplication per
/// coordinate cost less than keeping 64 bytes per particle (the memory budget is 400 B per particle).
#[derive(Clone, Copy, Debug, Default)]
pub struct Cpdi2Cache {
    /// Lower-left node (column, row) of each corner's cell, as [`CellPoint::cell`].
    cells: [[i32; 2]; 4],
    weight: [f64; 4],
    /// w̃1 and w̃2; w̃3 = −w̃1 and w̃4 = −w̃2 (negation is exact).
    gradient_weight: [[f64; 2]; 2],
    layout: CornerLayout,
}

/// Where a particle's corner cells lie, decided once per step in [`Cpdi2::prepare`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum CornerLayout {
    /// No corners, or a degenerate quadrilateral: the linear hat at the particle position.
    #[default]
    LinearFallback,
    /// Every node of every corner cell is inside the grid and no corner lies on or across the
    /// axis (the usual case): no test per node, and the corners are used as they are
    /// ([`stencil_corners`] would leave them unchanged).
    Interior,
    /// Some corner cell reaches past the grid edge: nodes outside are dropped.
    Edge,
}

/// The 16 entries w_c N_i(x_c), w̃_c N_i(x_c) of the corners `corners` (as the stencil
/// evaluates them), corner by corner; `INTERIOR`: every node of every corner cell is inside
/// the grid ([`CornerLayout::Interior`]), so no node is tested.
#[inline(always)]
fn corner_entries<const INTERIOR: bool>(
    grid: &GridGeometry,
    cache: &Cpdi2Cache,
    corners: &[[f64; 2]; 4],
    mut visit: impl FnMut(usize, f64, [f64; 2]),
) {
    let [g1, g2] = cache.gradient_weight;
    let gradient_weight = [g1, g2, [-g1[0], -g1[1]], [-g2[0], -g2[1]]];
    for k in 0..4 {
        let (wk, gk) = (cache.weight[k], gradient_weight[k]);
        let point = CellPoint::in_cell(grid, corners[k], cache.cells[k]);
        let corner_entry = |node, n: f64, _| visit(node, wk * n, [gk[0] * n, gk[1] * n]);
        if INTERIOR {
            point.visit_interior_nodes(grid, corner_entry);
        } else {
            point.visit_nodes(grid, corner_entry);
        }
    }
}

/// The corners a stencil is evaluated at: the particle's corners, clamped to r ≥ 0 in
/// axisymmetry.
#[inline(always)]
fn stencil_corners(corners: &[[f64; 2]; 4], axisymmetric: bool) -> [[f64; 2]; 4] {
    let mut c = *corners;
    if axisymmetric {
        for corner in c.iter_mut() {
            corner[0] = at_least(corner[0], 0.0);
        }
    }
    c
}

impl ShapeFunction for Cpdi2 {
    const NAME: &'static str = "cpdi2";
    const USES_CORNERS: bool = true;

    type Cache = Cpdi2Cache;

    #[inline(always)]
    fn prepare(grid: &GridGeometry, domain: &ParticleDomain, axisymmetric: bool, cache: &mut Cpdi2Cache) {
        // Written field by field, in place; the other fields are only read without fallback.
        cache.layout = CornerLayout::LinearFallback;
        let Some(corners) = domain.corners else {
            return;
        };
        let c = stencil_corners(corners, axisymmetric);
        let (w, wg, v) = corner_weights(&c);
        // 0 < V < ∞ (false for NaN): the same test as `v > 0.0 && v.is_finite()`, in two compares.
        if v > 0.0 && v < f64::INFINITY {
            // r > 0 strictly: `at_least(r, 0)` then returns r itself (−0 could become +0).
            let off_axis = !axisymmetric || corners.iter().all(|x| x[0] > 0.0);
            for (cell, x) in cache.cells.iter_mut().zip(c) {
                *cell = CellPoint::locate(grid, x).cell;
            }
            // Every node of every corner cell is inside the grid exactly when the range of the
            // cells is (`CellPoint::all_nodes_inside` of the lowest and highest cell indices).
            let [c0, c1, c2, c3] = cache.cells;
            let lowest = [c0[0].min(c1[0]).min(c2[0]).min(c3[0]), c0[1].min(c1[1]).min(c2[1]).min(c3[1])];
            let highest = [c0[0].max(c1[0]).max(c2[0]).max(c3[0]), c0[1].max(c1[1]).max(c2[1]).max(c3[1])];
            let inside = |cell: [i32; 2]| CellPoint { cell, fraction: [0.0; 2] }.all_nodes_inside(grid);
            let interior = off_axis & inside(lowest) & inside(highest);
            cache.weight = w;
            cache.gradient_weight = [wg[0], wg[1]];
            cache.layout = if interior { CornerLayout::Interior } else { CornerLayout::Edge };
        }
    }

    #[inline(always)]
    fn visit_entries(
        grid: &GridGeometry,
        cache: &Cpdi2Cache,
        domain: &ParticleDomain,
        axisymmetric: bool,
        visit: impl FnMut(usize, f64, [f64; 2]),
    ) {
        match (cache.layout, domain.corners) {
            (CornerLayout::LinearFallback, _) | (_, None) => bilinear_nodes(grid, domain.position, visit),
            // The corners as they are, by reference (the usual case).
            (CornerLayout::Interior, Some(corners)) => corner_entries::<true>(grid, cache, corners, visit),
            (_, Some(corners)) => corner_entries::<false>(grid, cache, &stencil_corners(corners, axisymmetric), visit),
        }
    }

    #[inline(always)]
    fn node_box(grid: &GridGeometry, cache: &Cpdi2Cache, domain: &ParticleDomain) -> NodeBox {
        if cache.layout == CornerLayout::LinearFallback || domain.corners.is_none() {
            return NodeBox::of_cell(grid, CellPoint::locate(grid, domain.position).cell);
        }
        if cache.layout == CornerLayout::Interior {
            // Every corner cell lies inside the grid: no clamping, the box is the cells' range
            // and one more node.
            let [c0, c1, c2, c3] = cache.cells;
            let (i0, i1) = (c0[0].min(c1[0]).min(c2[0]).min(c3[0]), c0[0].max(c1[0]).max(c2[0]).max(c3[0]));
            let (j0, j1) = (c0[1].min(c1[1]).min(c2[1]).min(c3[1]), c0[1].max(c1[1]).max(c2[1]).max(c3[1]));
            return NodeBox { columns: [i0 as u32, i1 as u32 + 1], rows: [j0 as u32, j1 as u32 + 1] };
        }
        // Unrolled by hand: `array::map` is not always inlined, and this runs once per particle.
        let of = |k: usize| NodeBox::of_cell(grid, cache.cells[k]);
        of(0).union(of(1)).union(of(2)).union(of(3))
    }

    #[inline(always)]
    fn domain_area(corners: &[[f64; 2]; 4]) -> Option<f64> {
        Some(shoelace(corners))
    }

    /// x_c ← x_c + dt Σ_i N_i(x_c) v_i, with the corner first clamped into the grid box (so a
    /// corner that left the grid is brought back and sees the velocity of the edge cell) and
    /// the moved corner clamped into the box again; in axisymmetry also r ≥ 0.
    ///
    /// A corner that the clamp leaves bit for bit where the stencil evaluated it (the usual
    /// case) lies in the cell `cache` located it in, so it is not located again.
    #[inline(always)]
    fn advect_corners(
        grid: &GridGeometry,
        cache: &Cpdi2Cache,
        nodal_velocity: &[[f64; 2]],
        dt: f64,
        corners: &mut [[f64; 2]; 4],
        axisymmetric: bool,
    ) {
        let lo = grid.origin;
        let hi = grid.upper();
        // Where the stencil evaluated the corners (unchanged by the axis clamp when Interior).
        let located = if cache.layout == CornerLayout::Interior { *corners } else { stencil_corners(corners, axisymmetric) };
        let same = |a: [f64; 2], b: [f64; 2]| a[0].to_bits() == b[0].to_bits() && a[1].to_bits() == b[1].to_bits();
        for (k, c) in corners.iter_mut().enumerate() {
            let q = [clamp_between(c[0], lo[0], hi[0]), clamp_between(c[1], lo[1], hi[1])];
            let mut v = [0.0; 2];
            let interpolate = |node: usize, n: f64, _| {
                let vi = nodal_velocity[node];
                v[0] += n * vi[0];
                v[1] += n * vi[1];
            };
            if cache.layout == CornerLayout::Interior && same(q, located[k]) {
                CellPoint::in_cell(grid, q, cache.cells[k]).visit_interior_nodes(grid, interpolate);
            } else {
                bilinear_nodes(grid, q, interpolate);
            }
            c[0] = clamp_between(q[0] + dt * v[0], lo[0], hi[0]);
            c[1] = clamp_between(q[1] + dt * v[1], lo[1], hi[1]);
            if axisymmetric {
                c[0] = at_least(c[0], 0.0);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interpolation::testing::*;
    use crate::interpolation::{hat, Linear};
    use crate::particles::Particles;

    /// xorshift64*: deterministic random numbers in [0, 1) without a dependency.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
        }
        fn range(&mut self, a: f64, b: f64) -> f64 {
            a + (b - a) * self.next()
        }
    }

    /// A random strictly convex counter-clockwise quadrilateral centred near `centre`:
    /// a rotated, stretched square with each corner perturbed, rejected until convex.
    fn random_convex_quad(rng: &mut Rng, centre: [f64; 2], size: f64) -> [[f64; 2]; 4] {
        loop {
            let th = rng.range(0.0, std::f64::consts::TAU);
            let (s, c) = th.sin_cos();
            let (hx, hy) = (size * rng.range(0.2, 1.0), size * rng.range(0.2, 1.0));
            let shear = rng.range(-0.8, 0.8);
            let mut q = [[0.0; 2]; 4];
            for (k, (u, v)) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].into_iter().enumerate() {
                let u = u + rng.range(-0.45, 0.45);
                let v = v + rng.range(-0.45, 0.45);
                let (px, py) = (hx * (u + shear * v), hy * v);
                q[k] = [centre[0] + c * px - s * py, centre[1] + s * px + c * py];
            }
            let convex = (0..4).all(|k| {
                let (a, b, d) = (q[k], q[(k + 1) % 4], q[(k + 2) % 4]);
                (b[0] - a[0]) * (d[1] - b[1]) - (b[1] - a[1]) * (d[0] - b[0]) > 1e-3 * size * size
            });
            if convex {
                return q;
            }
        }
    }

    fn particle_with_corners(c: [[f64; 2]; 4]) -> Particles {
        let centre = [(c[0][0] + c[1][0] + c[2][0] + c[3][0]) / 4.0, (c[0][1] + c[1][1] + c[2][1] + c[3][1]) / 4.0];
        let mut p = single_particle(centre, [0.01, 0.01]);
        p.corners[0] = c;
        p
    }

    fn cpdi2(c: [[f64; 2]; 4], axisymmetric: bool) -> Stencil {
        let mut st = Stencil::default();
        Cpdi2::stencil(&grid(), &particle_with_corners(c), 0, axisymmetric, &mut st);
        st
    }

    /// (1/A) ∫_Ω f_i dA and (1/A) ∫_Ω ∇f_i dA for the corner interpolant
    /// f_i = Σ_c N_i(x_c) M_c(ξ, η), by 4 × 4 Gauss quadrature on the bilinear map.
    fn gauss_reference(g: &GridGeometry, c: &[[f64; 2]; 4], i: usize, j: usize) -> (f64, [f64; 2]) {
        let gp = [-0.861_136_311_594_052_6, -0.339_981_043_584_856_3, 0.339_981_043_584_856_3, 0.861_136_311_594_052_6];
        let gw = [0.347_854_845_137_453_9, 0.652_145_154_862_546_1, 0.652_145_154_862_546_1, 0.347_854_845_137_453_9];
        let signs = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        let nc: Vec<f64> = c
            .iter()
            .map(|&x| {
                let l = g.local(x);
                hat(l[0] - i as f64).0 * hat(l[1] - j as f64).0
            })
            .collect();
        let (mut area, mut s, mut grad) = (0.0, 0.0, [0.0; 2]);
        for (a, &xi) in gp.iter().enumerate() {
            for (b, &eta) in gp.iter().enumerate() {
                let (mut m, mut dxi, mut deta) = ([0.0; 4], [0.0; 4], [0.0; 4]);
                for (k, &(sx, sy)) in signs.iter().enumerate() {
                    m[k] = 0.25 * (1.0 + sx * xi) * (1.0 + sy * eta);
                    dxi[k] = 0.25 * sx * (1.0 + sy * eta);
                    deta[k] = 0.25 * (1.0 + sx * xi) * sy;
                }
                let mut jac = [[0.0; 2]; 2]; // jac[r][s] = ∂x_r/∂ξ_s
                for k in 0..4 {
                    for r in 0..2 {
                        jac[r][0] += dxi[k] * c[k][r];
                        jac[r][1] += deta[k] * c[k][r];
                    }
                }
                let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
                let wq = gw[a] * gw[b] * det;
                let (mut f, mut df) = (0.0, [0.0; 2]);
                for k in 0..4 {
                    f += nc[k] * m[k];
                    // ∇M = J⁻ᵀ (∂M/∂ξ, ∂M/∂η)
                    let gx = (jac[1][1] * dxi[k] - jac[1][0] * deta[k]) / det;
                    let gy = (-jac[0][1] * dxi[k] + jac[0][0] * deta[k]) / det;
                    df[0] += nc[k] * gx;
                    df[1] += nc[k] * gy;
                }
                area += wq;
                s += wq * f;
                grad[0] += wq * df[0];
                grad[1] += wq * df[1];
            }
        }
        (s / area, [grad[0] / area, grad[1] / area])
    }

    #[test]
    fn weights_equal_gauss_quadrature_of_the_corner_interpolant() {
        let g = grid();
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let (mut worst_w, mut worst_g) = (0.0f64, 0.0f64);
        for _ in 0..500 {
            let centre = [rng.range(0.3, 0.7), rng.range(0.3, 0.7)];
            let size = rng.range(0.005, 0.12);
            let c = random_convex_quad(&mut rng, centre, size);
            let st = cpdi2(c, false);
            let nodes = per_node(&st);
            let gscale = 1.0 / size; // gradients scale like 1/size
            for i in 0..g.nodes[0] {
                for j in 0..g.nodes[1] {
                    let (s_ref, g_ref) = gauss_reference(&g, &c, i, j);
                    let n = g.node_index(i, j) as u32;
                    let (s, gr) = nodes.iter().find(|e| e.0 == n).map(|e| (e.1, e.2)).unwrap_or((0.0, [0.0; 2]));
                    worst_w = worst_w.max((s - s_ref).abs());
                    worst_g = worst_g.max((gr[0] - g_ref[0]).abs().max((gr[1] - g_ref[1]).abs()) / gscale);
                }
            }
        }
        eprintln!("CPDI2 vs Gauss: max |ΔS| = {worst_w:e}, max |Δ∇S|·size = {worst_g:e}");
        assert!(worst_w < 1e-12, "weights differ from quadrature by {worst_w}");
        assert!(worst_g < 1e-12, "gradients differ from quadrature by {worst_g} (relative to 1/size)");
    }

    #[test]
    fn partition_of_unity_and_zero_gradient_sum() {
        check_partition_of_unity::<Cpdi2>([0.025, 0.025], false);
        check_partition_of_unity::<Cpdi2>([0.05, 0.0125], false);
        check_partition_of_unity::<Cpdi2>([0.025, 0.025], true);
        let mut rng = Rng(42);
        for _ in 0..2000 {
            let ctr = [rng.range(0.3, 0.7), rng.range(0.3, 0.7)];
            let sz = rng.range(0.001, 0.2);
            let c = random_convex_quad(&mut rng, ctr, sz);
            if !c.iter().all(|&x| grid().contains(x)) {
                continue; // partition of unity only holds for domains inside the grid
            }
            let st = cpdi2(c, false);
            assert!((st.weight_sum() - 1.0).abs() < 1e-12, "ΣS = {} for {c:?}", st.weight_sum());
            let gs = st.gradient_sum();
            assert!(gs[0].abs() < 1e-9 && gs[1].abs() < 1e-9, "Σ∇S = {gs:?} for {c:?}");
        }
    }

    /// In axisymmetry a domain reaching across the axis is evaluated at its corners clamped to
    /// r = 0 in every pass, exactly as if those corners lay on the axis (partition of unity
    /// alone cannot tell: bilinear weights extrapolated to r < 0 still sum to one).
    #[test]
    fn corners_across_the_axis_are_evaluated_on_the_axis() {
        for (centre, half) in [([0.01, 0.5], [0.025, 0.025]), ([0.004, 0.33], [0.01, 0.02]), ([0.02, 0.61], [0.03, 0.01])] {
            let c = Particles::rectangle_corners(centre, half);
            assert!(c.iter().any(|x| x[0] < 0.0), "the test needs a corner across the axis");
            let on_axis = c.map(|x| [x[0].max(0.0), x[1]]);
            let (a, b) = (cpdi2(c, true), cpdi2(on_axis, true));
            assert_eq!(a.len, b.len);
            for k in 0..a.len {
                assert_eq!(a.node[k], b.node[k]);
                assert_eq!(a.weight[k].to_bits(), b.weight[k].to_bits(), "{centre:?} entry {k}");
                assert_eq!(a.gradient[k][0].to_bits(), b.gradient[k][0].to_bits(), "{centre:?} entry {k}");
                assert_eq!(a.gradient[k][1].to_bits(), b.gradient[k][1].to_bits(), "{centre:?} entry {k}");
            }
        }
    }

    #[test]
    fn partition_of_unity_near_the_axis() {
        let mut xs = Vec::new();
        for r in [0.001, 0.01, 0.0125, 0.02, 0.025, 0.03, 0.05, 0.07, 0.1, 0.11] {
            for z in [0.3, 0.3125, 0.347] {
                xs.push([r, z]);
            }
        }
        // Rectangles reaching across the axis are clamped to r ≥ 0.
        check_partition_of_unity_at::<Cpdi2>(&xs, [0.025, 0.025], true);
        check_partition_of_unity_at::<Cpdi2>(&xs, [0.05, 0.05], true);
        // Quads touching the axis.
        let mut rng = Rng(7);
        for _ in 0..500 {
            let mut c = {
                let ctr = [rng.range(0.0, 0.1), rng.range(0.3, 0.7)];
                let sz = rng.range(0.005, 0.05);
                random_convex_quad(&mut rng, ctr, sz)
            };
            let shift = c.iter().map(|x| x[0]).fold(f64::INFINITY, f64::min).min(0.0);
            for x in c.iter_mut() {
                x[0] -= shift; // min r = 0 at worst
            }
            let st = cpdi2(c, true);
            assert!((st.weight_sum() - 1.0).abs() < 1e-12);
            let gs = st.gradient_sum();
            assert!(gs[0].abs() < 1e-9 && gs[1].abs() < 1e-9);
        }
        // Without the clamp (plane strain) a domain across the axis loses weight.
        let st = cpdi2(Particles::rectangle_corners([0.01, 0.5], [0.025, 0.025]), false);
        assert!(st.weight_sum() < 1.0 - 1e-3);
    }

    #[test]
    fn rectangle_inside_one_cell_gives_the_bilinear_value_at_its_centroid() {
        let g = grid();
        let mut lin = Stencil::default();
        for (x, half) in
            [([0.137, 0.262], [0.02, 0.03]), ([0.45, 0.55], [0.049, 0.049]), ([0.71, 0.33], [0.001, 0.015])]
        {
            let st = cpdi2(Particles::rectangle_corners(x, half), false);
            Linear::stencil(&g, &single_particle(x, half), 0, false, &mut lin);
            let (dw, dg) = stencil_difference(&st, &lin);
            assert!(dw < 1e-14 && dg < 1e-11, "at {x:?}: Δw = {dw}, Δ∇ = {dg}");
        }
    }

    #[test]
    fn weights_are_continuous_across_cell_faces() {
        let mut rng = Rng(99);
        for _ in 0..50 {
            let c0 = {
                let ctr = [0.5, 0.5];
                let sz = rng.range(0.01, 0.08);
                random_convex_quad(&mut rng, ctr, sz)
            };
            for dir in 0..2 {
                // Put each corner, then the centroid, on the face x = 0.4 (or y = 0.4).
                let mut targets: Vec<f64> = c0.iter().map(|x| x[dir]).collect();
                targets.push(c0.iter().map(|x| x[dir]).sum::<f64>() / 4.0);
                for t in targets {
                    let shifted = |d: f64| {
                        let mut c = c0;
                        for x in c.iter_mut() {
                            x[dir] += 0.4 - t + d;
                        }
                        cpdi2(c, false)
                    };
                    let (dw, _) = stencil_difference(&shifted(-1e-9), &shifted(1e-9));
                    assert!(dw < 1e-7, "weight jump {dw}");
                }
            }
        }
    }

    #[test]
    fn domain_area_is_the_shoelace_area() {
        let p = particle_with_corners(Particles::rectangle_corners([0.4, 0.6], [0.02, 0.03]));
        assert!((Cpdi2::domain_area(&p.corners[0]).unwrap() - 4.0 * 0.02 * 0.03).abs() < 1e-15);
        // Triangle-like quad (0,0), (2,0), (2,1), (0,3): area 2·1 + 2·2/2 = 4.
        let p = particle_with_corners([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 3.0]]);
        assert!((Cpdi2::domain_area(&p.corners[0]).unwrap() - 4.0).abs() < 1e-14);
        // Generic quad against the edge-sum shoelace formula.
        let mut rng = Rng(5);
        for _ in 0..100 {
            let c = {
                let ctr = [0.5, 0.5];
                let sz = 0.1;
                random_convex_quad(&mut rng, ctr, sz)
            };
            let edge: f64 =
                (0..4).map(|k| c[k][0] * c[(k + 1) % 4][1] - c[(k + 1) % 4][0] * c[k][1]).sum::<f64>() / 2.0;
            let p = particle_with_corners(c);
            assert!((Cpdi2::domain_area(&p.corners[0]).unwrap() - edge).abs() < 1e-15);
            assert!(edge > 0.0);
        }
    }

    #[test]
    fn advect_corners_with_uniform_velocity_translates_the_domain() {
        let g = grid();
        let v = [0.37, -1.3];
        let vel = vec![v; g.num_nodes()];
        let dt = 1e-3;
        let mut rng = Rng(11);
        for _ in 0..100 {
            let c0 = {
                let ctr = [rng.range(0.2, 0.8), rng.range(0.2, 0.8)];
                let sz = 0.1;
                random_convex_quad(&mut rng, ctr, sz)
            };
            for axi in [false, true] {
                let mut c = c0;
                Cpdi2::advect_corners(&g, &Cpdi2Cache::default(), &vel, dt, &mut c, axi);
                for k in 0..4 {
                    assert!((c[k][0] - (c0[k][0] + v[0] * dt)).abs() < 1e-15);
                    assert!((c[k][1] - (c0[k][1] + v[1] * dt)).abs() < 1e-15);
                }
            }
        }
    }

    #[test]
    fn advect_corners_reproduces_a_linear_velocity_field() {
        // Bilinear interpolation is exact for a linear field: each corner moves by dt v(x_c).
        let g = grid();
        let field = |x: [f64; 2]| [0.3 + 2.0 * x[0] - 0.7 * x[1], -0.1 + 0.4 * x[0] + 1.1 * x[1]];
        let vel: Vec<[f64; 2]> = (0..g.num_nodes()).map(|n| field(g.node_position(n))).collect();
        let mut rng = Rng(13);
        for _ in 0..100 {
            let c0 = {
                let ctr = [rng.range(0.2, 0.8), rng.range(0.2, 0.8)];
                let sz = 0.1;
                random_convex_quad(&mut rng, ctr, sz)
            };
            let mut c = c0;
            Cpdi2::advect_corners(&g, &Cpdi2Cache::default(), &vel, 0.01, &mut c, false);
            for k in 0..4 {
                let vk = field(c0[k]);
                assert!((c[k][0] - (c0[k][0] + 0.01 * vk[0])).abs() < 1e-14);
                assert!((c[k][1] - (c0[k][1] + 0.01 * vk[1])).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn advect_corners_with_the_step_cache_equals_locating_them_again() {
        // Quads inside the grid, across its edges and across the axis, in both formulations.
        let g = grid();
        let field = |x: [f64; 2]| [0.3 + 2.0 * x[0] - 0.7 * x[1].sin(), -0.1 + 0.4 * x[0] * x[0] + 1.1 * x[1]];
        let vel: Vec<[f64; 2]> = (0..g.num_nodes()).map(|n| field(g.node_position(n))).collect();
        let mut rng = Rng(17);
        for _ in 0..2000 {
            let c0 = {
                let ctr = [rng.range(-0.05, 1.05), rng.range(-0.05, 1.05)];
                let sz = rng.range(0.005, 0.15);
                random_convex_quad(&mut rng, ctr, sz)
            };
            for axi in [false, true] {
                let p = particle_with_corners(c0);
                let mut cache = Cpdi2Cache::default();
                Cpdi2::prepare(&g, &ParticleDomain::of(&p, 0), axi, &mut cache);
                let (mut a, mut b) = (c0, c0);
                Cpdi2::advect_corners(&g, &cache, &vel, 0.01, &mut a, axi);
                Cpdi2::advect_corners(&g, &Cpdi2Cache::default(), &vel, 0.01, &mut b, axi);
                for k in 0..4 {
                    assert_eq!(a[k][0].to_bits(), b[k][0].to_bits(), "{c0:?}");
                    assert_eq!(a[k][1].to_bits(), b[k][1].to_bits(), "{c0:?}");
                }
            }
        }
    }

    #[test]
    fn advect_corners_clamps_to_the_axis_and_the_grid_box() {
        let g = grid();
        let vel = vec![[-2.0, 3.0]; g.num_nodes()];
        // dt v = (−0.02, 0.03): r = 0.005 → 0 (axis), z = 0.99 → 1 (top of the grid).
        let mut c = [[0.005, 0.95], [0.05, 0.95], [0.05, 0.99], [0.005, 0.99]];
        Cpdi2::advect_corners(&g, &Cpdi2Cache::default(), &vel, 0.01, &mut c, true);
        assert_eq!(c[0][0], 0.0);
        assert!((c[0][1] - 0.98).abs() < 1e-15);
        assert!((c[1][0] - 0.03).abs() < 1e-15 && (c[1][1] - 0.98).abs() < 1e-15);
        assert!((c[2][0] - 0.03).abs() < 1e-15 && c[2][1] == 1.0);
        assert_eq!(c[3], [0.0, 1.0]);
        // In axisymmetry the axis clamp holds even when the grid starts left of r = 0.
        let g2 = GridGeometry::new([-0.2, 0.0], [1.2, 1.0], 0.1);
        let mut c = [[0.005, 0.5], [0.05, 0.5], [0.05, 0.6], [0.005, 0.6]];
        Cpdi2::advect_corners(&g2, &Cpdi2Cache::default(), &vec![[-2.0, 0.0]; g2.num_nodes()], 0.01, &mut c, true);
        assert_eq!(c[0][0], 0.0);
        assert!((c[1][0] - 0.03).abs() < 1e-15);
        // A corner already outside the grid is brought back into the box.
        let mut c = [[-0.2, 0.5], [1.3, 0.5], [0.5, 1.4], [0.5, -0.1]];
        Cpdi2::advect_corners(&g, &Cpdi2Cache::default(), &vec![[0.0; 2]; g.num_nodes()], 0.01, &mut c, false);
        assert_eq!(c, [[0.0, 0.5], [1.0, 0.5], [0.5, 1.0], [0.5, 0.0]]);
    }

    /// The layout `prepare` derives from the range of the corner cells is its per-corner
    /// definition: Interior exactly when every node of the cell of every corner (located where
    /// the stencil evaluates it) is inside the grid and, in axisymmetry, every corner lies
    /// strictly off the axis (r > 0; a corner on the axis is clamped, not used as it is); Edge
    /// otherwise; the linear fallback for a degenerate domain. Interior skips every node test,
    /// so calling an edge domain interior would read nodes off the grid, and the converse would
    /// only cost time. Random quads over and around the grid, by the edges and the axis, and
    /// rectangles with corners exactly on the axis, on a grid line and on the grid's edge.
    #[test]
    fn interior_layout_is_every_corner_cell_inside_the_grid_and_off_the_axis() {
        let g = grid();
        let layout = |c: [[f64; 2]; 4], axisymmetric: bool| {
            let (f, mut cache) = ([1.0, 0.0, 0.0, 1.0, 1.0], Cpdi2Cache::default());
            let domain = ParticleDomain { position: c[0], initial_half_width: [0.01; 2], deformation_gradient: &f, corners: Some(&c) };
            Cpdi2::prepare(&g, &domain, axisymmetric, &mut cache);
            cache.layout
        };
        let definition = |c: [[f64; 2]; 4], axisymmetric: bool| {
            let evaluated = stencil_corners(&c, axisymmetric);
            let area = shoelace(&evaluated);
            let off_axis = !axisymmetric || c.iter().all(|x| x[0] > 0.0);
            let cells_inside = evaluated.iter().all(|&x| CellPoint::locate(&g, x).all_nodes_inside(&g));
            if !(area > 0.0 && area.is_finite()) {
                CornerLayout::LinearFallback
            } else if off_axis && cells_inside {
                CornerLayout::Interior
            } else {
                CornerLayout::Edge
            }
        };
        let mut quads = vec![
            // Corners on the axis (r = 0 exactly), just off it, on grid lines, on the grid's
            // upper and lower edges.
            [[0.0, 0.45], [0.1, 0.45], [0.1, 0.55], [0.0, 0.55]],
            [[1e-12, 0.45], [0.1, 0.45], [0.1, 0.55], [1e-12, 0.55]],
            [[0.2, 0.4], [0.3, 0.4], [0.3, 0.5], [0.2, 0.5]],
            [[0.9, 0.45], [1.0, 0.45], [1.0, 0.55], [0.9, 0.55]],
            [[0.45, 0.0], [0.55, 0.0], [0.55, 0.1], [0.45, 0.1]],
        ];
        let mut rng = Rng(2024);
        for _ in 0..4000 {
            let centre = [rng.range(-0.15, 1.15), rng.range(-0.15, 1.15)];
            let size = rng.range(0.002, 0.3);
            quads.push(random_convex_quad(&mut rng, centre, size));
        }
        let mut count = [[0; 2]; 2];
        for (k, &c) in quads.iter().enumerate() {
            for axisymmetric in [false, true] {
                let want = definition(c, axisymmetric);
                assert_eq!(layout(c, axisymmetric), want, "quad {k} {c:?}, axisymmetric {axisymmetric}");
                if want != CornerLayout::LinearFallback {
                    count[axisymmetric as usize][(want == CornerLayout::Interior) as usize] += 1;
                }
            }
        }
        // The hand-made cases: on the axis, Edge in axisymmetry only; on the upper edge of the
        // grid the corner's cell is the one beyond it (Edge), on the lower edge the first one.
        use CornerLayout::{Edge, Interior};
        assert_eq!((layout(quads[0], false), layout(quads[0], true)), (Interior, Edge));
        assert_eq!((layout(quads[1], true), layout(quads[2], true)), (Interior, Interior));
        assert_eq!((layout(quads[3], false), layout(quads[4], false)), (Edge, Interior));
        // Both layouts many times in both formulations.
        assert!(count.iter().flatten().all(|&m| m > 500), "{count:?}");
        // Clockwise corners (V < 0): the linear fallback.
        let mut clockwise = quads[2];
        clockwise.reverse();
        assert_eq!(layout(clockwise, false), CornerLayout::LinearFallback);
    }

    #[test]
    fn degenerate_domain_falls_back_to_linear() {
        let g = grid();
        let mut p = particle_with_corners([[0.42, 0.5]; 4]);
        p.position[0] = [0.42, 0.5];
        let (mut st, mut lin) = (Stencil::default(), Stencil::default());
        Cpdi2::stencil(&g, &p, 0, false, &mut st);
        Linear::stencil(&g, &p, 0, false, &mut lin);
        assert_eq!(stencil_difference(&st, &lin), (0.0, 0.0));
    }
}
