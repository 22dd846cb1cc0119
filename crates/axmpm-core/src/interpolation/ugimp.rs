//! uGIMP, the uniform generalised interpolation material point method (Bardenhagen & Kober
//! 2004): each particle is a square-ish domain of fixed half-widths `initial_half_width[p]`
//! (per direction) and S_ip is the average of the bilinear hat of node i over that domain.
//!
//! - 1D weight: [`gimp_weight`], the exact average (1/(2 l)) ∫ N_i over [x_p − l, x_p + l]. For
//!   l ≤ h/2 it is the five-piece formula of docs/physics.md §3; it stays valid up to l = h.
//! - 2D: tensor product S = S_x S_y, ∇S = (S_x' S_y, S_x S_y') in physical units.
//! - Stencil: the nodes whose support (|x − x_i| < h) overlaps the domain, i.e. the integers
//!   strictly inside (x_p − l − h, x_p + l + h)/h: at most 3 per direction for l ≤ h/2 and 4
//!   for l ≤ h. Half-widths are clamped to [0, h] so the stencil never exceeds 4 × 4 =
//!   [`MAX_STENCIL`](super::MAX_STENCIL) entries. Entries of zero weight are not written.
//! - Grid edges: nodes outside the grid are dropped (the shared convention of [`super`]).
//! - Axis (axisymmetric runs): the radial half-width is shrunk to
//!   l_r = min(l_r, R_p − origin_r), keeping the domain centred on the particle, so the
//!   domain ends at the axis at worst and never reaches r < 0 (the grid origin is r = 0 in
//!   axisymmetry). Partition of unity therefore still holds next to the axis. The axial
//!   half-width is untouched.

#[cfg(doc)]
use super::gimp_weight;
use super::{fast_floor, ParticleDomain, ShapeFunction, NodeBox};
#[cfg(test)]
use super::Stencil;
use crate::grid::GridGeometry;

pub struct UGimp;

impl ShapeFunction for UGimp {
    const NAME: &'static str = "ugimp";

    type Cache = GimpCache;

    #[inline(always)]
    fn prepare(grid: &GridGeometry, domain: &ParticleDomain, axisymmetric: bool, cache: &mut GimpCache) {
        gimp_axes(grid, domain.position, domain.initial_half_width, axisymmetric, cache)
    }

    #[inline(always)]
    fn visit_entries(
        grid: &GridGeometry,
        cache: &GimpCache,
        _: &ParticleDomain,
        _: bool,
        visit: impl FnMut(usize, f64, [f64; 2]),
    ) {
        gimp_entries(grid, cache, visit)
    }

    #[inline(always)]
    fn node_box(_: &GridGeometry, cache: &GimpCache, _: &ParticleDomain) -> NodeBox {
        gimp_box(cache)
    }
}

/// Nodes and 1D weights of one direction: up to 4 consecutive nodes `first .. first + len`
/// with S and dS/dx (physical units). Compact, because the solver keeps one pair per particle
/// between the passes of a step (see [`GimpCache`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Axis1d {
    first: u32,
    len: u8,
    weight: [f64; 4],
    derivative: [f64; 4],
}

/// The two directions' 1D GIMP weights of one particle: everything its 2D stencil is made of.
pub type GimpCache = [Axis1d; 2];

/// 1D GIMP nodes of one direction: `l` the particle position in cell units, `lam` the
/// half-width in cell units (already in [0, 1]), `n` the number of nodes in that direction.
///
/// Cell by cell: the domain [α, β] = [l − lam, l + lam] meets at most 3 cells; on cell k the
/// clipped part [p, q] (local coordinates in [0, 1]) adds (q − p)(1 − m) to node k and
/// (q − p) m to node k + 1, m = (p + q)/2 (the exact integral of the two hats), and the total
/// is divided by β − α. This equals [`gimp_weight`] for every node (tested) at a fraction of
/// the cost. The derivative is (N_i(β) − N_i(α)) / (β − α) · 1/h, which only touches the
/// cells of the two domain ends.
#[inline(always)]
fn axis_weights(l: f64, lam: f64, n: usize, ih: f64, ax: &mut Axis1d) {
    // Written in place (`first` and `len` once, on the path taken); entries at and beyond
    // `ax.len` are never read.
    let mut w = [0.0; 4];
    let mut d = [0.0; 4];
    let k0: i64;
    let count: usize;
    if lam > 0.0 {
        let alpha = l - lam;
        let beta = l + lam;
        let k0f = fast_floor(alpha);
        k0 = node_index(k0f, n);
        // β − α ≤ 2 cells, so at most 3 cells and 4 nodes. Clamped to [0, 2] (a NaN to 0)
        // before the conversion, which then needs no saturation handling.
        let span = fast_floor(beta) - k0f;
        let span = if span > 0.0 { span } else { 0.0 };
        let span = if span < 2.0 { span } else { 2.0 };
        // SAFETY: a whole number in [0, 2].
        let cells = unsafe { span.to_int_unchecked::<u32>() } as usize;
        let inv = 1.0 / (beta - alpha);
        // All three cells, without a loop of variable length (the compiler vectorises it): a
        // cell beyond β's has q < p, and its length is taken as 0, so it adds exact zeros.
        let (mut lower, mut upper) = ([0.0; 3], [0.0; 3]);
        for c in 0..3 {
            let k = k0f + c as f64;
            // max(α, k) and min(β, k + 1) as selects (α and β are never −0, and a NaN gives
            // the bound, as `f64::max`/`min` do, without their NaN handling).
            let p = (if alpha > k { alpha } else { k }) - k;
            let q = (if beta < k + 1.0 { beta } else { k + 1.0 }) - k;
            let len = q - p;
            let len = if len > 0.0 { len } else { 0.0 };
            let m = 0.5 * (p + q);
            lower[c] = len * (1.0 - m);
            upper[c] = len * m;
        }
        w = [lower[0] * inv, (upper[0] + lower[1]) * inv, (upper[1] + lower[2]) * inv, upper[2] * inv];
        // Hats at the ends: N(β) on the nodes of β's cell, N(α) on those of α's cell.
        let fa = alpha - k0f;
        let cb = cells; // β lies in the last cell
        let fb = beta - (k0f + cb as f64);
        let s = inv * ih;
        d[0] -= (1.0 - fa) * s;
        d[1] -= fa * s;
        d[cb] += (1.0 - fb) * s;
        d[cb + 1] += fb * s;
        count = cells + 2;
    } else {
        // Point particle: the linear hat on the two nodes of the cell (as `bilinear_nodes`).
        let c = fast_floor(l);
        let f = l - c;
        k0 = node_index(c, n);
        w[0] = 1.0 - f;
        w[1] = f;
        d[0] = -ih;
        d[1] = ih;
        count = 2;
    }
    // The usual case: every node on the grid and no zero weight at the first node, so the
    // nodes are kept as they are, but for the last one where its weight is zero (a domain
    // ending on a grid line, as every particle placed 2 per cell does): what the loop below
    // would do, without its tests.
    if k0 >= 0 && k0 + count as i64 <= n as i64 && !(w[0] <= 0.0 && lam > 0.0) {
        let drop_last = w[count - 1] <= 0.0 && lam > 0.0;
        ax.first = k0 as u32;
        ax.len = (count - drop_last as usize) as u8;
        ax.weight = w;
        ax.derivative = d;
        return;
    }
    ax.first = 0;
    ax.len = 0;
    for c in 0..count {
        let i = k0 + c as i64;
        if i < 0 || i >= n as i64 || (w[c] <= 0.0 && lam > 0.0) {
            continue;
        }
        if ax.len == 0 {
            ax.first = i as u32;
        }
        // Zero weights and off-grid nodes only occur at the ends, so the kept nodes are consecutive.
        debug_assert_eq!(i as u32, ax.first + ax.len as u32);
        let k = ax.len as usize;
        ax.weight[k] = w[c];
        ax.derivative[k] = d[c];
        ax.len += 1;
    }
}

/// The whole number `k` as a node index of an axis of `n` nodes, clamped to [−8, n + 8] (a NaN
/// to −8): a domain reaches at most 4 nodes from its first, so a first node beyond either bound
/// has every node off the grid, as has the clamped one. Clamped first, the conversion needs no
/// saturation handling (the `as` cast's extra compares and selects).
#[inline(always)]
fn node_index(k: f64, n: usize) -> i64 {
    let k = k.max(-8.0).min(n as f64 + 8.0);
    // SAFETY: k is a whole number in [−8, n + 8], n < 2⁶³.
    unsafe { k.to_int_unchecked::<i64>() }
}

/// 1D GIMP weights of both directions for a particle at `x` with half-widths `half`
/// (physical units). Shared by uGIMP and cpGIMP. Half-widths are clamped to [0, h]; in
/// axisymmetry the radial one is further shrunk to the distance R_p − origin_r from the axis
/// (see the module docs).
#[inline(always)]
#[allow(clippy::manual_clamp)] // `clamp` would propagate NaN; see below
pub(crate) fn gimp_axes(grid: &GridGeometry, x: [f64; 2], half: [f64; 2], axisymmetric: bool, out: &mut GimpCache) {
    let ih = grid.inverse_cell_size;
    let l = grid.local(x);
    // `max` before `min` maps NaN to 0 (a point particle) instead of propagating it.
    let mut lam = [(half[0] * ih).max(0.0).min(1.0), (half[1] * ih).max(0.0).min(1.0)];
    if axisymmetric {
        // R_p − origin_r in cell units is l[0].
        lam[0] = lam[0].min(l[0].max(0.0));
    }
    axis_weights(l[0], lam[0], grid.nodes[0], ih, &mut out[0]);
    axis_weights(l[1], lam[1], grid.nodes[1], ih, &mut out[1]);
}

/// The 2D stencil entries as the tensor product of the 1D weights: S = S_x S_y,
/// ∇S = (S_x' S_y, S_x S_y'), row by row.
///
/// The usual node counts (2 or 3 per direction: a domain of at most one cell) go through
/// loops of constant length, which the compiler unrolls: same entries, same order, same
/// arithmetic, without the loop counting of the general case.
#[inline(always)]
pub(crate) fn gimp_entries(grid: &GridGeometry, axes: &GimpCache, visit: impl FnMut(usize, f64, [f64; 2])) {
    let [ax, ay] = axes;
    match (ax.len, ay.len) {
        (2, 2) => gimp_entries_of::<2, 2>(grid, axes, visit),
        (3, 2) => gimp_entries_of::<3, 2>(grid, axes, visit),
        (2, 3) => gimp_entries_of::<2, 3>(grid, axes, visit),
        (3, 3) => gimp_entries_of::<3, 3>(grid, axes, visit),
        (nx, ny) => gimp_entries_general(grid, axes, (nx as usize).min(4), (ny as usize).min(4), visit),
    }
}

/// [`gimp_entries`] for `NX` × `NY` nodes.
#[inline(always)]
fn gimp_entries_of<const NX: usize, const NY: usize>(
    grid: &GridGeometry,
    axes: &GimpCache,
    visit: impl FnMut(usize, f64, [f64; 2]),
) {
    gimp_entries_general(grid, axes, NX, NY, visit)
}

/// [`gimp_entries`] for `nx` × `ny` nodes (at most 4 × 4).
#[inline(always)]
fn gimp_entries_general(
    grid: &GridGeometry,
    axes: &GimpCache,
    nx: usize,
    ny: usize,
    mut visit: impl FnMut(usize, f64, [f64; 2]),
) {
    let [ax, ay] = axes;
    for b in 0..ny {
        let row = (ay.first as usize + b) * grid.nodes[0];
        let (wy, dy) = (ay.weight[b], ay.derivative[b]);
        for a in 0..nx {
            let (wx, dx) = (ax.weight[a], ax.derivative[a]);
            visit(row + ax.first as usize + a, wx * wy, [dx * wy, wx * dy]);
        }
    }
}

/// The node box of the 2D stencil: the 1D node ranges of both directions.
#[inline(always)]
pub(crate) fn gimp_box(axes: &GimpCache) -> NodeBox {
    let [ax, ay] = axes;
    // An axis keeps at least one node for a particle inside the grid; `max(1)` only guards
    // the box arithmetic.
    NodeBox {
        columns: [ax.first, ax.first + (ax.len.max(1) - 1) as u32],
        rows: [ay.first, ay.first + (ay.len.max(1) - 1) as u32],
    }
}

/// GIMP stencil of a particle at `x` with half-widths `half` (physical units).
#[cfg(test)]
pub(crate) fn gimp_stencil(grid: &GridGeometry, x: [f64; 2], half: [f64; 2], axisymmetric: bool, out: &mut Stencil) {
    let mut axes = GimpCache::default();
    gimp_axes(grid, x, half, axisymmetric, &mut axes);
    out.clear();
    out.node_box = gimp_box(&axes);
    gimp_entries(grid, &axes, |node, w, g| out.push(node, w, g));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interpolation::testing::*;
    use crate::interpolation::{gimp_weight, Linear};

    /// `node_index` is the truncation of a whole number within [−8, n + 8] and clamps beyond,
    /// where a first node and the three after it are all off the grid either way.
    #[test]
    fn node_index_clamps_only_where_no_node_is_on_the_grid() {
        let n = 11;
        for k in -40..=60 {
            let got = node_index(k as f64, n);
            if (-8..=n as i64 + 8).contains(&k) {
                assert_eq!(got, k);
            } else {
                let off_grid = |first: i64| (first..first + 4).all(|i| i < 0 || i >= n as i64);
                assert!(off_grid(k) && off_grid(got), "k = {k}, clamped to {got}");
            }
        }
        assert_eq!(node_index(f64::NAN, n), -8);
        assert_eq!(node_index(f64::INFINITY, n), n as i64 + 8);
    }

    /// The five-piece 1D formula of docs/physics.md §3 (physical units) and its derivative.
    fn piecewise(xi: f64, l: f64, h: f64) -> (f64, f64) {
        if xi <= -h - l || xi > h + l {
            (0.0, 0.0)
        } else if xi <= -h + l {
            ((h + l + xi).powi(2) / (4.0 * h * l), (h + l + xi) / (2.0 * h * l))
        } else if xi <= -l {
            (1.0 + xi / h, 1.0 / h)
        } else if xi <= l {
            (1.0 - (xi * xi + l * l) / (2.0 * h * l), -xi / (h * l))
        } else if xi <= h - l {
            (1.0 - xi / h, -1.0 / h)
        } else {
            ((h + l - xi).powi(2) / (4.0 * h * l), -(h + l - xi) / (2.0 * h * l))
        }
    }

    fn ugimp(x: [f64; 2], half: [f64; 2], axisymmetric: bool) -> Stencil {
        let mut st = Stencil::default();
        UGimp::stencil(&grid(), &single_particle(x, half), 0, axisymmetric, &mut st);
        st
    }

    #[test]
    fn partition_of_unity_and_zero_gradient_sum() {
        for half in [[0.025, 0.025], [0.05, 0.05], [0.0125, 0.05], [0.05, 0.01]] {
            check_partition_of_unity::<UGimp>(half, false);
            check_partition_of_unity::<UGimp>(half, true);
        }
    }

    #[test]
    fn partition_of_unity_near_the_axis() {
        let mut xs = Vec::new();
        for r in [1e-6, 0.001, 0.005, 0.0125, 0.02, 0.025, 0.03, 0.049, 0.05, 0.051, 0.07, 0.099, 0.1, 0.11] {
            for z in [0.3, 0.3125, 0.347, 0.55] {
                xs.push([r, z]);
            }
        }
        for half in [[0.025, 0.025], [0.05, 0.05], [0.0125, 0.0125]] {
            check_partition_of_unity_at::<UGimp>(&xs, half, true);
        }
    }

    #[test]
    fn axis_truncation_shrinks_the_radial_half_width_only() {
        // R_p = 0.005 < l_r = 0.025: the domain becomes [0, 0.01] × [z − 0.025, z + 0.025].
        let a = ugimp([0.005, 0.43], [0.025, 0.025], true);
        let b = ugimp([0.005, 0.43], [0.005, 0.025], false);
        assert_eq!(stencil_difference(&a, &b), (0.0, 0.0));
        // Without truncation the domain crosses the axis and loses weight to the dropped
        // node at r = −h: partition of unity fails in plane strain, as it should.
        let c = ugimp([0.005, 0.43], [0.025, 0.025], false);
        assert!(c.weight_sum() < 1.0 - 1e-4);
        // Away from the axis nothing changes.
        let d = ugimp([0.3, 0.43], [0.025, 0.025], true);
        let e = ugimp([0.3, 0.43], [0.025, 0.025], false);
        assert_eq!(stencil_difference(&d, &e), (0.0, 0.0));
    }

    #[test]
    fn nodes_outside_the_grid_are_dropped() {
        let g = grid();
        for x in [[0.01, 0.5], [0.5, 0.99], [0.0, 0.0], [1.0, 1.0]] {
            let st = ugimp(x, [0.05, 0.05], false);
            for k in 0..st.len {
                assert!((st.node[k] as usize) < g.num_nodes());
            }
        }
    }

    #[test]
    fn weights_are_continuous_across_cell_faces_and_breakpoints() {
        // GIMP is C¹: both the weight and its gradient are continuous, also across the
        // breakpoints x_i ± l_p and x_i ± (h ∓ l_p) of the piecewise formula.
        for half in [0.025, 0.05, 0.0125] {
            for face in [0.3, 0.4, 0.6] {
                for offset in [0.0, half, -half, 0.1 - half, half - 0.1] {
                    let x0 = face + offset;
                    for dir in 0..2 {
                        let mut lo = [0.437, 0.562];
                        let mut hi = lo;
                        lo[dir] = x0 - 1e-9;
                        hi[dir] = x0 + 1e-9;
                        let (dw, dg) = stencil_difference(&ugimp(lo, [half; 2], false), &ugimp(hi, [half; 2], false));
                        assert!(dw < 1e-7, "weight jump {dw} at {x0} dir {dir}");
                        assert!(dg < 1e-5, "gradient jump {dg} at {x0} dir {dir}");
                    }
                }
            }
        }
    }

    #[test]
    fn tends_to_linear_as_the_half_width_vanishes() {
        let g = grid();
        let mut lin = Stencil::default();
        for a in 0..23 {
            for b in 0..19 {
                let x = [0.1234 + 0.031 * a as f64, 0.1567 + 0.037 * b as f64];
                let p = single_particle(x, [1e-6 * g.cell_size; 2]);
                let mut st = Stencil::default();
                UGimp::stencil(&g, &p, 0, false, &mut st);
                Linear::stencil(&g, &p, 0, false, &mut lin);
                let (dw, dg) = stencil_difference(&st, &lin);
                assert!(dw < 1e-10 && dg < 1e-8, "at {x:?}: Δw = {dw}, Δ∇ = {dg}");
            }
        }
    }

    /// A point particle (zero half-width, or R_p = 0 on the axis) takes the zero-width branch:
    /// exactly the linear hat, gradient signs included (−1/h on the lower node, +1/h on the
    /// upper one in each direction).
    #[test]
    fn zero_width_is_the_linear_hat_with_its_gradient() {
        let g = grid();
        let mut lin = Stencil::default();
        for x in [[0.13, 0.27], [0.4567, 0.8123], [0.05, 0.95]] {
            let st = ugimp(x, [0.0, 0.0], false);
            Linear::stencil(&g, &single_particle(x, [0.0; 2]), 0, false, &mut lin);
            assert_eq!(stencil_difference(&st, &lin), (0.0, 0.0), "at {x:?}");
        }
        // By hand at (0.13, 0.27): node (1, 2) has ∇S = (−10 · 0.3, 0.7 · (−10)).
        let st = ugimp([0.13, 0.27], [0.0, 0.0], false);
        let k = (0..st.len).find(|&k| st.node[k] as usize == g.node_index(1, 2)).unwrap();
        assert!((st.gradient[k][0] + 3.0).abs() < 1e-12 && (st.gradient[k][1] + 7.0).abs() < 1e-12);
        let k = (0..st.len).find(|&k| st.node[k] as usize == g.node_index(2, 3)).unwrap();
        assert!((st.gradient[k][0] - 7.0).abs() < 1e-12 && (st.gradient[k][1] - 3.0).abs() < 1e-12);
    }

    /// A point particle exactly on a node (weight 1 there, 0 on the next node of its cell)
    /// keeps both nodes of the cell, as the linear hat does: the zero-weight node still has
    /// the gradient ±1/h. Only a domain of nonzero width drops its zero-weight end nodes.
    #[test]
    fn zero_width_on_a_node_keeps_the_zero_weight_node_and_its_gradient() {
        let g = grid();
        let mut lin = Stencil::default();
        for x in [[0.5, 0.5], [0.5, 0.27], [0.13, 0.5], [0.0, 0.0]] {
            let l = g.local(x);
            assert!(l.iter().any(|&c| c == c.floor()), "the test needs a coordinate on a node, {x:?}");
            let st = ugimp(x, [0.0, 0.0], false);
            Linear::stencil(&g, &single_particle(x, [0.0; 2]), 0, false, &mut lin);
            assert_eq!((st.len, stencil_difference(&st, &lin)), (lin.len, (0.0, 0.0)), "at {x:?}");
        }
    }

    /// A domain so narrow (2⁻⁵³ cells) that it starts one ulp below node 1: the weight of node
    /// 0 rounds to zero (its midpoint (p + q)/2 rounds to the node), and node 0 is dropped like
    /// any zero-weight end node, although every node is on the grid (the usual case's shortcut
    /// must not keep it). Every kept weight is positive and the kept weights sum to one.
    #[test]
    fn a_first_node_whose_weight_rounds_to_zero_is_dropped() {
        let lam = f64::EPSILON / 2.0;
        assert_eq!(1.0 - lam, 1.0_f64.next_down(), "the domain must start one ulp below node 1");
        for (l, n) in [(1.0, 11), (1.0, 3)] {
            let mut ax = Axis1d::default();
            axis_weights(l, lam, n, 10.0, &mut ax);
            let kept = &ax.weight[..ax.len as usize];
            assert!(ax.first >= 1 && ax.first as usize + kept.len() <= n, "l = {l}: nodes {} + {}", ax.first, ax.len);
            assert!(kept.iter().all(|&w| w > 0.0), "l = {l}: kept weights {kept:?}");
            assert!((kept.iter().sum::<f64>() - 1.0).abs() < 1e-15, "l = {l}: kept weights {kept:?}");
        }
    }

    #[test]
    fn one_d_weight_matches_the_piecewise_formula() {
        let h = 0.1;
        for l in [0.05, 0.025, 0.0125, 0.001] {
            for k in 0..=400 {
                let xi = -0.16 + 0.32 * k as f64 / 400.0 + 1e-7;
                let (s, d) = gimp_weight(xi / h, l / h);
                let (se, de) = piecewise(xi, l, h);
                assert!((s - se).abs() < 1e-13, "S({xi}, {l}) = {s} vs {se}");
                assert!((d / h - de).abs() < 1e-9 * (1.0 + de.abs()), "S'({xi}, {l}) = {} vs {de}", d / h);
            }
        }
        // Hand values, h = 0.1, l = 0.025.
        let s = |xi: f64| gimp_weight(xi / h, 0.25).0;
        assert!((s(-0.09) - 0.1225).abs() < 1e-14); // (0.035)² / 0.01
        assert!((s(-0.05) - 0.5).abs() < 1e-14); // 1 + ξ/h
        assert!((s(0.0) - 0.875).abs() < 1e-14); // 1 − l/(2h)
        assert!((s(0.01) - 0.855).abs() < 1e-14); // 1 − (1e-4 + 6.25e-4)/5e-3
        assert!((s(0.11) - 0.0225).abs() < 1e-14); // (0.015)² / 0.01
        assert_eq!(s(0.125), 0.0);
        assert_eq!(s(-0.2), 0.0);
    }

    #[test]
    fn two_d_stencil_is_the_tensor_product_by_hand() {
        // Particle at (0.13, 0.27), l = 0.025: x-nodes 1, 2 (ξ = 0.03, −0.07);
        // y-nodes 2, 3 (ξ = 0.07, −0.03). Node 0 in x: ξ = 0.13 ≥ h + l, zero.
        let g = grid();
        let st = ugimp([0.13, 0.27], [0.025; 2], false);
        assert_eq!(st.len, 4);
        let h = 0.1;
        for (i, j) in [(1usize, 2usize), (2, 2), (1, 3), (2, 3)] {
            let (sx, dx) = piecewise(0.13 - i as f64 * h, 0.025, h);
            let (sy, dy) = piecewise(0.27 - j as f64 * h, 0.025, h);
            let k = (0..st.len).find(|&k| st.node[k] as usize == g.node_index(i, j)).unwrap();
            assert!((st.weight[k] - sx * sy).abs() < 1e-14);
            assert!((st.gradient[k][0] - dx * sy).abs() < 1e-12);
            assert!((st.gradient[k][1] - sx * dy).abs() < 1e-12);
        }
        // Node (1, 2): ξ = (0.03, 0.07) → S_x = 1 − 0.3 = 0.7, S_y = 1 − 0.7 = 0.3.
        let k = (0..st.len).find(|&k| st.node[k] as usize == g.node_index(1, 2)).unwrap();
        assert!((st.weight[k] - 0.21).abs() < 1e-14);
    }

    #[test]
    fn stencil_equals_the_tensor_product_of_gimp_weight() {
        // The cell-by-cell evaluation in `axis_weights` against the reference 1D weight, for
        // half-widths up to one cell (the cpGIMP range) and positions all over a cell.
        let g = grid();
        let h = g.cell_size;
        let mut st = Stencil::default();
        for lam in [1e-9, 1e-3, 0.1, 0.25, 0.4999, 0.5, 0.5001, 0.75, 0.9, 1.0] {
            for a in 0..=40 {
                let x = [0.4 + h * a as f64 / 40.0, 0.6 - h * (a % 13) as f64 / 13.0];
                gimp_stencil(&g, x, [lam * h, (1.0 - 0.5 * lam) * h], false, &mut st);
                let l = g.local(x);
                let mut expected = Stencil::default();
                for j in 0..g.nodes[1] {
                    for i in 0..g.nodes[0] {
                        let (sx, dx) = gimp_weight(l[0] - i as f64, lam);
                        let (sy, dy) = gimp_weight(l[1] - j as f64, 1.0 - 0.5 * lam);
                        if sx * sy != 0.0 || dx * sy != 0.0 || sx * dy != 0.0 {
                            expected.push(g.node_index(i, j), sx * sy, [dx * sy / h, sx * dy / h]);
                        }
                    }
                }
                let (dw, dg) = stencil_difference(&st, &expected);
                // Where the domain straddles a node the derivative depends on how the node
                // splits it, known to rounding of x only: relative 1e-16 / lam.
                assert!(dw < 1e-14 && dg < 1e-11 + 1e-15 / lam, "lam = {lam}, x = {x:?}: Δw = {dw}, Δ∇ = {dg}");
            }
        }
    }

    #[test]
    fn half_width_of_half_a_cell_touches_three_nodes_per_direction() {
        let st = ugimp([0.13, 0.47], [0.05, 0.05], false);
        assert_eq!(st.len, 9);
        let st = ugimp([0.15, 0.45], [0.05, 0.05], false);
        assert_eq!(st.len, 4); // domain = one cell exactly: the outer nodes get zero weight
    }
}
