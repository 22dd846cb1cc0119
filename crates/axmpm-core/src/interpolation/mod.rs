//! Interpolation schemes: the weights S_ip and gradients ∇S_ip that connect particle p to the
//! grid nodes i (docs/physics.md §3).
//!
//! Each scheme is a zero-sized type implementing [`ShapeFunction`]; the solver is generic over
//! it, so the inner loops are compiled once per scheme. A scheme's stencil is a short list of
//! (node, weight, gradient) entries, visited one by one ([`ShapeFunction::visit_entries`]) or
//! written into a [`Stencil`]. Entries may repeat a node (CPDI2 sums corner contributions);
//! every consumer simply accumulates, so repeats are harmless.
//!
//! Truncation rules shared by all schemes:
//! - nodes outside the grid are dropped (a particle domain reaching past the grid edge loses
//!   that part of its weight; bodies should keep one cell away from open edges);
//! - in axisymmetry a particle domain never reaches r < 0: GIMP schemes shrink the radial
//!   half-width to R_p, CPDI2 clamps corners to r ≥ 0.

pub use crate::grid::NodeBox;
use crate::grid::GridGeometry;
use crate::particles::{DeformationGradient, Particles};

pub mod cpdi2;
pub mod cpgimp;
pub mod linear;
pub mod ugimp;

pub use cpdi2::Cpdi2;
pub use cpgimp::CpGimp;
pub use linear::Linear;
pub use ugimp::UGimp;

/// Largest number of entries any scheme writes (CPDI2: 4 corners × 4 nodes).
pub const MAX_STENCIL: usize = 16;

/// Weights and gradients of one particle on its nodes.
#[derive(Clone, Copy, Debug)]
pub struct Stencil {
    pub len: usize,
    pub node: [u32; MAX_STENCIL],
    pub weight: [f64; MAX_STENCIL],
    pub gradient: [[f64; 2]; MAX_STENCIL],
    /// A box of grid nodes containing every entry (it may be larger than the entries need).
    pub node_box: NodeBox,
}

impl Default for Stencil {
    fn default() -> Self {
        Self {
            len: 0,
            node: [0; MAX_STENCIL],
            weight: [0.0; MAX_STENCIL],
            gradient: [[0.0; 2]; MAX_STENCIL],
            node_box: NodeBox { columns: [0; 2], rows: [0; 2] },
        }
    }
}

impl Stencil {
    #[inline(always)]
    pub fn clear(&mut self) {
        self.len = 0;
    }

    #[inline(always)]
    pub fn push(&mut self, node: usize, weight: f64, gradient: [f64; 2]) {
        debug_assert!(self.len < MAX_STENCIL);
        // A scheme never writes more than MAX_STENCIL (a power of two) entries, so the mask
        // changes nothing; it lets the compiler drop the three bounds checks of every push.
        let k = self.len & (MAX_STENCIL - 1);
        self.node[k] = node as u32;
        self.weight[k] = weight;
        self.gradient[k] = gradient;
        self.len += 1;
    }

    /// The entries (node, S_ip, ∇S_ip) in order, as one iterator over exact-length slices
    /// (no bounds check per entry in the solver loops).
    #[inline(always)]
    pub fn entries(&self) -> impl Iterator<Item = (usize, f64, [f64; 2])> + '_ {
        let n = self.len.min(MAX_STENCIL);
        self.node[..n].iter().zip(&self.weight[..n]).zip(&self.gradient[..n]).map(|((&node, &w), &g)| (node as usize, w, g))
    }

    /// Σ_i S_ip, 1 wherever the particle's support lies inside the grid (partition of unity).
    pub fn weight_sum(&self) -> f64 {
        self.weight[..self.len].iter().sum()
    }

    /// Σ_i ∇S_ip, zero wherever partition of unity holds.
    pub fn gradient_sum(&self) -> [f64; 2] {
        let mut g = [0.0; 2];
        for k in 0..self.len {
            g[0] += self.gradient[k][0];
            g[1] += self.gradient[k][1];
        }
        g
    }
}

/// What a scheme may read of one particle's domain (borrowed from the particle arrays, so
/// the solver can evaluate the stencil while it updates the same particle).
#[derive(Clone, Copy, Debug)]
pub struct ParticleDomain<'a> {
    pub position: [f64; 2],
    pub initial_half_width: [f64; 2],
    pub deformation_gradient: &'a DeformationGradient,
    /// CPDI2 corners; `None` for schemes without corners.
    pub corners: Option<&'a [[f64; 2]; 4]>,
}

impl<'a> ParticleDomain<'a> {
    #[inline(always)]
    pub fn of(particles: &'a Particles, p: usize) -> Self {
        Self {
            position: particles.position[p],
            initial_half_width: particles.initial_half_width[p],
            deformation_gradient: &particles.deformation_gradient[p],
            corners: particles.corners.get(p),
        }
    }
}

/// An interpolation scheme.
pub trait ShapeFunction: Send + Sync + 'static {
    /// Name selected by `simulation.shape_function`.
    const NAME: &'static str;
    /// Whether particles carry domain corners that move with the grid (CPDI2).
    const USES_CORNERS: bool = false;

    /// What the solver keeps per particle between the passes of one step, so that the
    /// expensive part of the stencil is computed once per step (GIMP: the 1D weights).
    type Cache: Copy + Default + Send + Sync + 'static;

    /// Writes the cacheable part of the stencil of a particle domain into `cache` (in place:
    /// a GIMP or CPDI2 cache is 150–200 bytes, and returning it by value costs a memcpy call).
    fn prepare(grid: &GridGeometry, domain: &ParticleDomain, axisymmetric: bool, cache: &mut Self::Cache);

    /// Visits the stencil entries (node, S_ip, ∇S_ip) from `cache`, made by
    /// [`ShapeFunction::prepare`] for the same domain at the start of the step, in a fixed
    /// order. The solver's loops consume the entries as they are made (the closure is inlined
    /// into each loop, so a loop that needs no gradient never computes it) instead of writing
    /// and re-reading a [`Stencil`]. Every node visited is a node of `grid` (index below
    /// `grid.num_nodes()`): the passes index the nodal fields with it without bounds checks.
    fn visit_entries(
        grid: &GridGeometry,
        cache: &Self::Cache,
        domain: &ParticleDomain,
        axisymmetric: bool,
        visit: impl FnMut(usize, f64, [f64; 2]),
    );

    /// A box of grid nodes containing every entry of the stencil from `cache`.
    fn node_box(grid: &GridGeometry, cache: &Self::Cache, domain: &ParticleDomain) -> NodeBox;

    /// Writes the stencil from `cache` (its node box and the entries of
    /// [`ShapeFunction::visit_entries`], in order).
    #[inline(always)]
    fn expand(grid: &GridGeometry, cache: &Self::Cache, domain: &ParticleDomain, axisymmetric: bool, out: &mut Stencil) {
        out.clear();
        out.node_box = Self::node_box(grid, cache, domain);
        Self::visit_entries(grid, cache, domain, axisymmetric, |node, w, g| out.push(node, w, g));
    }

    /// Writes S_ip and ∇S_ip of a particle domain into `out` (cleared first).
    /// `axisymmetric` asks for domains truncated at the axis r = 0.
    #[inline(always)]
    fn stencil_at(grid: &GridGeometry, domain: &ParticleDomain, axisymmetric: bool, out: &mut Stencil) {
        let mut cache = Self::Cache::default();
        Self::prepare(grid, domain, axisymmetric, &mut cache);
        Self::expand(grid, &cache, domain, axisymmetric, out)
    }

    /// [`ShapeFunction::stencil_at`] for particle `p` of `particles`.
    #[inline(always)]
    fn stencil(grid: &GridGeometry, particles: &Particles, p: usize, axisymmetric: bool, out: &mut Stencil) {
        Self::stencil_at(grid, &ParticleDomain::of(particles, p), axisymmetric, out)
    }

    /// In-plane area of the particle domain when the scheme tracks it (CPDI2: the
    /// quadrilateral's area from its corners); `None` means the area follows from F.
    #[inline(always)]
    fn domain_area(_corners: &[[f64; 2]; 4]) -> Option<f64> {
        None
    }

    /// Moves the domain corners with the nodal velocity field (CPDI2 only). `cache` is the
    /// one [`ShapeFunction::prepare`] made for the corners at the start of the step (or a
    /// default cache, which has nothing to reuse).
    #[inline(always)]
    fn advect_corners(
        _grid: &GridGeometry,
        _cache: &Self::Cache,
        _nodal_velocity: &[[f64; 2]],
        _dt: f64,
        _corners: &mut [[f64; 2]; 4],
        _axisymmetric: bool,
    ) {
    }
}

/// 1D linear hat N(ξ) = 1 − |ξ|/h and its derivative, with ξ in cell units (so the
/// derivative is returned per unit cell and must be multiplied by 1/h).
#[inline(always)]
pub fn hat(xi: f64) -> (f64, f64) {
    let a = xi.abs();
    if a >= 1.0 {
        (0.0, 0.0)
    } else {
        (1.0 - a, if xi >= 0.0 { -1.0 } else { 1.0 })
    }
}

/// Linear (bilinear in 2D) weights of a point on the 4 nodes of its cell, with gradients in
/// physical units. Nodes outside the grid are skipped. Shared by the original MPM and by the
/// corner evaluation of CPDI2.
#[inline(always)]
pub fn bilinear_nodes(grid: &GridGeometry, x: [f64; 2], visit: impl FnMut(usize, f64, [f64; 2])) {
    CellPoint::locate(grid, x).visit_nodes(grid, visit)
}

/// A point located in the grid: the lower-left node (i, j) of its cell, possibly outside the
/// grid, and its fractional position in the cell. It is all [`bilinear_nodes`] needs, so a
/// located point can be kept (CPDI2 caches its corners) and its nodes visited later with the
/// same arithmetic, bit for bit.
#[derive(Clone, Copy, Debug, Default)]
pub struct CellPoint {
    pub cell: [i32; 2],
    pub fraction: [f64; 2],
}

impl CellPoint {
    #[inline(always)]
    pub fn locate(grid: &GridGeometry, x: [f64; 2]) -> Self {
        let l = grid.local(x);
        let ci = fast_floor(l[0]);
        let cj = fast_floor(l[1]);
        // The cell index only decides which nodes exist; clamping it to [−2, nodes] keeps it in
        // i32 and drops the same nodes (both nodes of a cell outside that range are off-grid).
        // `max` maps a NaN to −2; the clamped value is then a whole number in [−2, 2³¹), so its
        // truncation fits an i32 and needs no saturation handling.
        // SAFETY: see above (grid node counts are below 2³¹).
        let clamp = |c: f64, n: usize| unsafe { c.max(-2.0).min(n as f64).to_int_unchecked::<i32>() };
        Self { cell: [clamp(ci, grid.nodes[0]), clamp(cj, grid.nodes[1])], fraction: [l[0] - ci, l[1] - cj] }
    }

    /// A point known to lie in the cell with lower-left node `cell` (one [`CellPoint::locate`]
    /// gave): the same fraction, bit for bit, without locating it again. (Where `locate`
    /// clamped the cell, every node of the cell is off the grid and the fraction is never used.)
    #[inline(always)]
    pub fn in_cell(grid: &GridGeometry, x: [f64; 2], cell: [i32; 2]) -> Self {
        let l = grid.local(x);
        Self { cell, fraction: [l[0] - cell[0] as f64, l[1] - cell[1] as f64] }
    }

    /// Whether all 4 nodes of the cell are inside the grid.
    #[inline(always)]
    pub fn all_nodes_inside(&self, grid: &GridGeometry) -> bool {
        let [ci, cj] = self.cell;
        ci >= 0 && cj >= 0 && (ci as usize) + 1 < grid.nodes[0] && (cj as usize) + 1 < grid.nodes[1]
    }

    /// [`CellPoint::visit_nodes`] for a cell whose 4 nodes are all inside the grid
    /// ([`CellPoint::all_nodes_inside`]): no test per node, same entries in the same order.
    #[inline(always)]
    pub fn visit_interior_nodes(&self, grid: &GridGeometry, mut visit: impl FnMut(usize, f64, [f64; 2])) {
        debug_assert!(self.all_nodes_inside(grid));
        let [fx, fy] = self.fraction;
        let ih = grid.inverse_cell_size;
        let wx = [1.0 - fx, fx];
        let wy = [1.0 - fy, fy];
        let dx = [-ih, ih];
        let base = grid.node_index(self.cell[0] as usize, self.cell[1] as usize);
        let nodes = [[base, base + 1], [base + grid.nodes[0], base + grid.nodes[0] + 1]];
        for b in 0..2 {
            for a in 0..2 {
                visit(nodes[b][a], wx[a] * wy[b], [dx[a] * wy[b], wx[a] * dx[b]]);
            }
        }
    }

    /// Visits the nodes of the cell inside the grid, row by row: (node, weight, gradient).
    #[inline(always)]
    pub fn visit_nodes(&self, grid: &GridGeometry, mut visit: impl FnMut(usize, f64, [f64; 2])) {
        if self.all_nodes_inside(grid) {
            // The usual case: no test per node.
            self.visit_interior_nodes(grid, visit);
            return;
        }
        let [fx, fy] = self.fraction;
        let ih = grid.inverse_cell_size;
        let wx = [1.0 - fx, fx];
        let wy = [1.0 - fy, fy];
        let dx = [-ih, ih];
        for b in 0..2 {
            let j = self.cell[1] as i64 + b as i64;
            if j < 0 || j >= grid.nodes[1] as i64 {
                continue;
            }
            for a in 0..2 {
                let i = self.cell[0] as i64 + a as i64;
                if i < 0 || i >= grid.nodes[0] as i64 {
                    continue;
                }
                let node = grid.node_index(i as usize, j as usize);
                visit(node, wx[a] * wy[b], [dx[a] * wy[b], wx[a] * dx[b]]);
            }
        }
    }
}

/// `x.max(lo)`: x where x > lo, else lo (so a NaN gives `lo`, and −0 against a bound of +0
/// gives +0). Written as a select, which is one `maxsd` on x86-64 (`f64::max` adds the NaN
/// handling of IEEE maxNum, about six instructions on the baseline target).
#[inline(always)]
pub fn at_least(x: f64, lo: f64) -> f64 {
    if x > lo {
        x
    } else {
        lo
    }
}

/// `x.max(lo).min(hi)` for lo ≤ hi, as two selects ([`at_least`], then the same for `hi`):
/// one `maxsd` and one `minsd`, no branch. A NaN gives `lo`.
#[inline(always)]
pub fn clamp_between(x: f64, lo: f64, hi: f64) -> f64 {
    let x = at_least(x, lo);
    if x < hi {
        x
    } else {
        hi
    }
}

/// `x.floor()` without the libm call (on the baseline x86-64 target `f64::floor` is a call,
/// there is no SSE4.1 `roundsd`) and without float ↔ integer conversions: adding and
/// subtracting 2⁵² (with the sign of x) rounds |x| < 2⁵² to the nearest whole number, and one
/// is taken off where that rounded up. Larger |x| are whole numbers already and pass through.
/// Exact for every finite x, except that −0 gives +0; NaN stays NaN. Seven vector-friendly
/// operations (the compiler keeps them in SIMD registers) instead of the ten to fourteen of a
/// saturating truncation and its fix-up.
#[inline(always)]
pub fn fast_floor(x: f64) -> f64 {
    const TWO_POW_52: f64 = 4_503_599_627_370_496.0;
    let magic = TWO_POW_52.copysign(x);
    let nearest = (x + magic) - magic;
    let nearest = if x.abs() < TWO_POW_52 { nearest } else { x };
    nearest - if nearest > x { 1.0 } else { 0.0 }
}

/// ⌊x⌋ clamped to [0, top] (a NaN gives 0), for a cell index: equals
/// `fast_floor(x).max(0.0).min(top)` bit for bit, but x is clamped first and then truncated,
/// which is the floor on [0, top]: a max, a min and one conversion instead of a floor with its
/// fix-up, two clamps and the saturation handling of `as`. `top` is a whole number of cells,
/// 0 ≤ top < 2³¹.
#[inline(always)]
pub fn clamped_floor(x: f64, top: f64) -> u32 {
    debug_assert!((0.0..2147483648.0).contains(&top) && top.fract() == 0.0);
    // `x > 0.0` is false for a NaN, so the NaN becomes 0 (one `maxsd`, one `minsd`).
    let c = if x > 0.0 { x } else { 0.0 };
    let c = if c < top { c } else { top };
    // SAFETY: 0 ≤ c ≤ top < 2³¹ and c is not NaN, so its truncation fits an i32.
    unsafe { c.to_int_unchecked::<i32>() as u32 }
}

/// Generalised GIMP 1D weight and its derivative (Bardenhagen & Kober 2004):
/// S(ξ) = (1/(2 l)) ∫_{ξ−l}^{ξ+l} N(s) ds, the exact average of the hat N over the particle
/// domain, with `u = ξ/h = (x_p − x_i)/h` and `lam = l/h` both in cell units. Returns
/// (S, dS/du); multiply the derivative by 1/h for physical units.
///
/// Valid for any 0 ≤ lam ≤ 1 (a domain of half-width up to one cell); for lam ≤ 1/2 it equals
/// the five-piece formula of docs/physics.md §3, and lam = 0 gives the hat itself. The integral is
/// evaluated piece by piece over the two linear branches of the hat (length × midpoint value;
/// derivative = Σ slope × length / (2 lam)), so there is no cancellation for small lam: at
/// lam → 0 the result tends to the hat to rounding.
#[inline(always)]
pub fn gimp_weight(u: f64, lam: f64) -> (f64, f64) {
    if lam <= 0.0 {
        return hat(u);
    }
    let a = u - lam;
    let b = u + lam;
    let mut s = 0.0;
    let mut d = 0.0;
    // Rising branch N = 1 + s on [−1, 0].
    if a < 0.0 && b > -1.0 {
        let lo = a.max(-1.0);
        let hi = b.min(0.0);
        let len = if a >= -1.0 && b <= 0.0 { 2.0 * lam } else { hi - lo };
        s += len * (1.0 + 0.5 * (lo + hi));
        d += len;
    }
    // Falling branch N = 1 − s on [0, 1].
    if b > 0.0 && a < 1.0 {
        let lo = a.max(0.0);
        let hi = b.min(1.0);
        let len = if a >= 0.0 && b <= 1.0 { 2.0 * lam } else { hi - lo };
        s += len * (1.0 - 0.5 * (lo + hi));
        d -= len;
    }
    let inv = 0.5 / lam;
    (s * inv, d * inv)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `clamped_floor` is the cell index the previous floor-then-clamp gave, on the edges that
    /// matter: negative, −0, exact integers, just below and above `top`, far beyond, ±∞, NaN.
    #[test]
    fn clamped_floor_equals_floor_then_clamp() {
        let reference = |x: f64, top: f64| fast_floor(x).max(0.0).min(top);
        let tops = [0.0, 1.0, 7.0, 499.0];
        let mut xs = vec![-9.2e18, -3.5, -1.0, -1e-300, -0.0, 0.0, 1e-300, 0.5, 0.999999, 1.0, 1.5, 6.999999, 7.0,
                          7.000001, 498.5, 499.0, 499.5, 500.0, 1e18, 1e300, f64::INFINITY, f64::NAN];
        xs.extend((0..2000).map(|k| -3.0 + k as f64 * 0.2537));
        for &top in &tops {
            for &x in &xs {
                let want = reference(x, top);
                let got = clamped_floor(x, top);
                assert_eq!((got as f64).to_bits(), want.to_bits(), "x = {x}, top = {top}");
            }
            assert_eq!(clamped_floor(-1e300, top), 0);
            assert_eq!(clamped_floor(f64::NEG_INFINITY, top), 0);
        }
    }

    /// The clamps are `max`/`min` on ordinary values, give the lower bound for a NaN, and +0
    /// for −0 against a bound of +0 (the axis); the upper bound is the same select, so a zero
    /// against an upper bound of the other zero gives the bound (`f64::min` leaves it open).
    #[test]
    fn clamps_are_max_and_min_with_nan_and_signed_zero_defined() {
        for x in [-2.0, -1e-300, 0.25, 0.5, 0.999, 1.0, 1.5, 1e300, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(at_least(x, 0.0).to_bits(), x.max(0.0).to_bits(), "x = {x}");
            assert_eq!(clamp_between(x, 0.25, 1.0).to_bits(), x.max(0.25).min(1.0).to_bits(), "x = {x}");
        }
        assert_eq!(at_least(f64::NAN, 0.5), 0.5);
        assert_eq!(clamp_between(f64::NAN, 0.25, 1.0), 0.25);
        assert_eq!(at_least(-0.0, 0.0).to_bits(), 0.0_f64.to_bits());
        assert_eq!(clamp_between(-0.0, 0.0, 1.0).to_bits(), 0.0_f64.to_bits());
        assert_eq!(clamp_between(-0.0, -1.0, 0.0).to_bits(), 0.0_f64.to_bits());
        assert_eq!(clamp_between(0.0, -1.0, -0.0).to_bits(), (-0.0_f64).to_bits());
    }

    /// `fast_floor` is `f64::floor` bit for bit (but for −0, which gives +0), on both sides of
    /// the 2⁵² threshold of its rounding trick, on halves (the ties of round-to-nearest-even),
    /// just below whole numbers, at ±∞, and NaN stays NaN.
    #[test]
    fn fast_floor_equals_floor() {
        let two52 = 4_503_599_627_370_496.0_f64;
        let mut xs = vec![0.0, 1e-300, 0.5, 1.5, 2.5, -0.5, -1.5, -2.5, 0.49999999999999994, 1.0 - f64::EPSILON / 2.0,
                          -1e-300, -(1.0 - f64::EPSILON / 2.0), two52 - 0.5, two52, two52 + 1.0, two52 + 2.0,
                          2.0 * two52 + 2.0, -(two52 - 0.5), -two52, -(two52 + 1.0), 9.3e18, -9.3e18, 1e300, -1e300,
                          f64::MAX, f64::MIN, f64::INFINITY, f64::NEG_INFINITY];
        xs.extend((0..4000).map(|k| -1000.0 + k as f64 * 0.5003));
        xs.extend((0..200).map(|k| (k as f64 - 100.0) * 0.25));
        for x in xs {
            assert_eq!(fast_floor(x).to_bits(), x.floor().to_bits(), "x = {x:e}");
        }
        assert_eq!(fast_floor(-0.0).to_bits(), 0.0_f64.to_bits());
        assert!(fast_floor(f64::NAN).is_nan());
    }
}

#[cfg(test)]
pub(crate) mod testing {
    //! Helpers shared by the per-scheme unit tests.
    use super::*;
    use crate::particles::IDENTITY_F;

    pub fn grid() -> GridGeometry {
        GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.1)
    }

    /// One particle at `x` with half-widths `half` and rectangular corners.
    pub fn single_particle(x: [f64; 2], half: [f64; 2]) -> Particles {
        let mut p = Particles::default();
        p.push(x, [0.0; 2], 1.0, 4.0 * half[0] * half[1], half, [0.0; 4], 0);
        p.corners.push(Particles::rectangle_corners(x, half));
        p.deformation_gradient[0] = IDENTITY_F;
        p
    }

    /// Asserts partition of unity and Σ∇S = 0 for scheme `S` at many positions inside the grid.
    pub fn check_partition_of_unity<S: ShapeFunction>(half: [f64; 2], axisymmetric: bool) {
        let g = grid();
        let mut st = Stencil::default();
        let mut k = 0;
        for a in 0..37 {
            for b in 0..37 {
                let x = [0.15 + 0.7 * a as f64 / 36.0 + 1e-3 * k as f64 % 0.01, 0.15 + 0.7 * b as f64 / 36.0];
                k += 1;
                let p = single_particle(x, half);
                S::stencil(&g, &p, 0, axisymmetric, &mut st);
                assert!((st.weight_sum() - 1.0).abs() < 1e-12, "{}: ΣS = {} at {:?}", S::NAME, st.weight_sum(), x);
                check_box(&g, &st);
                let gs = st.gradient_sum();
                assert!(gs[0].abs() < 1e-10 && gs[1].abs() < 1e-10, "{}: Σ∇S = {:?} at {:?}", S::NAME, gs, x);
            }
        }
    }

    /// Asserts partition of unity and Σ∇S = 0 for scheme `S` at the given positions.
    pub fn check_partition_of_unity_at<S: ShapeFunction>(positions: &[[f64; 2]], half: [f64; 2], axisymmetric: bool) {
        let g = grid();
        let mut st = Stencil::default();
        for &x in positions {
            let p = single_particle(x, half);
            S::stencil(&g, &p, 0, axisymmetric, &mut st);
            assert!((st.weight_sum() - 1.0).abs() < 1e-12, "{}: ΣS = {} at {:?}", S::NAME, st.weight_sum(), x);
            check_box(&g, &st);
            let gs = st.gradient_sum();
            assert!(gs[0].abs() < 1e-10 && gs[1].abs() < 1e-10, "{}: Σ∇S = {:?} at {:?}", S::NAME, gs, x);
        }
    }

    /// Asserts that the stencil's node box lies in the grid and contains every entry.
    pub fn check_box(g: &GridGeometry, st: &Stencil) {
        let b = st.node_box;
        assert!(b.columns[0] <= b.columns[1] && (b.columns[1] as usize) < g.nodes[0], "{:?}", b.columns);
        assert!(b.rows[0] <= b.rows[1] && (b.rows[1] as usize) < g.nodes[1], "{:?}", b.rows);
        for k in 0..st.len {
            let (i, j) = (st.node[k] as usize % g.nodes[0], st.node[k] as usize / g.nodes[0]);
            assert!((b.columns[0] as usize..=b.columns[1] as usize).contains(&i), "column {i} outside {:?}", b.columns);
            assert!((b.rows[0] as usize..=b.rows[1] as usize).contains(&j), "row {j} outside {:?}", b.rows);
        }
    }

    /// Stencil entries summed per node (CPDI2 repeats nodes), sorted by node.
    pub fn per_node(st: &Stencil) -> Vec<(u32, f64, [f64; 2])> {
        let mut v: Vec<(u32, f64, [f64; 2])> = Vec::new();
        for k in 0..st.len {
            match v.iter_mut().find(|e| e.0 == st.node[k]) {
                Some(e) => {
                    e.1 += st.weight[k];
                    e.2[0] += st.gradient[k][0];
                    e.2[1] += st.gradient[k][1];
                }
                None => v.push((st.node[k], st.weight[k], st.gradient[k])),
            }
        }
        v.sort_by_key(|e| e.0);
        v
    }

    /// Largest differences (weight, gradient) between two stencils, node by node; a node
    /// missing from one side counts as zero there.
    pub fn stencil_difference(a: &Stencil, b: &Stencil) -> (f64, f64) {
        let (pa, pb) = (per_node(a), per_node(b));
        let mut nodes: Vec<u32> = pa.iter().chain(pb.iter()).map(|e| e.0).collect();
        nodes.sort();
        nodes.dedup();
        let get = |v: &Vec<(u32, f64, [f64; 2])>, n: u32| {
            v.iter().find(|e| e.0 == n).map(|e| (e.1, e.2)).unwrap_or((0.0, [0.0; 2]))
        };
        let (mut dw, mut dg) = (0.0f64, 0.0f64);
        for n in nodes {
            let (wa, ga) = get(&pa, n);
            let (wb, gb) = get(&pb, n);
            dw = dw.max((wa - wb).abs());
            dg = dg.max((ga[0] - gb[0]).abs()).max((ga[1] - gb[1]).abs());
        }
        (dw, dg)
    }
}
