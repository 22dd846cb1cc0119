//! cpGIMP, contiguous-particle GIMP (Bardenhagen & Kober 2004; half-width update after
//! Wallstedt & Guilkey 2008): the uGIMP weights of [`super::ugimp`] with the particle
//! half-widths following the deformation,
//!
//!   l_x = l_x0 · F11,   l_y = l_y0 · F22,
//!
//! from `initial_half_width[p]` and `deformation_gradient[p]` (`[F11, F12, F21, F22, F33]`).
//!
//! Cap rule: the stretched half-widths are clamped to [0, h] (h the cell size). The 1D weight
//! ([`super::gimp_weight`]) is the exact average of the hat over the domain for any l ≤ h, and
//! a domain of half-width ≤ h overlaps at most 4 node supports per direction, so the stencil
//! stays within 4 × 4 = [`MAX_STENCIL`](super::MAX_STENCIL) entries. A particle stretched
//! beyond 2h in one direction therefore interpolates as if it were 2h wide (its weights stay
//! a partition of unity; only its reach is limited). A non-positive stretch (inverted
//! particle) degenerates to the linear hat in that direction.
//!
//! Axis truncation and grid edges are as in uGIMP: in axisymmetry the radial half-width is
//! shrunk to min(l_r, R_p − origin_r) after the update and the cap, keeping the domain
//! centred; nodes outside the grid are dropped.

use super::ugimp::{gimp_axes, gimp_box, gimp_entries, GimpCache};
use super::{ParticleDomain, ShapeFunction, NodeBox};
#[cfg(test)]
use super::Stencil;
use crate::grid::GridGeometry;

pub struct CpGimp;

impl ShapeFunction for CpGimp {
    const NAME: &'static str = "cpgimp";

    type Cache = GimpCache;

    #[inline(always)]
    fn prepare(grid: &GridGeometry, domain: &ParticleDomain, axisymmetric: bool, cache: &mut GimpCache) {
        let l0 = domain.initial_half_width;
        let f = domain.deformation_gradient;
        gimp_axes(grid, domain.position, [l0[0] * f[0], l0[1] * f[3]], axisymmetric, cache)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interpolation::testing::*;
    use crate::interpolation::UGimp;

    fn both(x: [f64; 2], l0: [f64; 2], f11: f64, f22: f64, axisymmetric: bool) -> (Stencil, Stencil) {
        let g = grid();
        let mut p = single_particle(x, l0);
        p.deformation_gradient[0] = [f11, 0.07, -0.03, f22, 1.0];
        let q = single_particle(x, [l0[0] * f11, l0[1] * f22]);
        let (mut a, mut b) = (Stencil::default(), Stencil::default());
        CpGimp::stencil(&g, &p, 0, axisymmetric, &mut a);
        UGimp::stencil(&g, &q, 0, axisymmetric, &mut b);
        (a, b)
    }

    fn positions() -> Vec<[f64; 2]> {
        let mut xs = Vec::new();
        for a in 0..29 {
            for b in 0..23 {
                xs.push([0.21 + 0.6 * a as f64 / 28.0 + 1e-4 * (a % 3) as f64, 0.2 + 0.6 * b as f64 / 22.0]);
            }
        }
        xs.push([0.3, 0.4]);
        xs
    }

    #[test]
    fn partition_of_unity_and_zero_gradient_sum() {
        check_partition_of_unity::<CpGimp>([0.025, 0.025], false);
        check_partition_of_unity::<CpGimp>([0.05, 0.0125], true);
    }

    #[test]
    fn identity_deformation_equals_ugimp() {
        let g = grid();
        for x in positions() {
            for axi in [false, true] {
                let p = single_particle(x, [0.025, 0.0125]);
                let (mut a, mut b) = (Stencil::default(), Stencil::default());
                CpGimp::stencil(&g, &p, 0, axi, &mut a);
                UGimp::stencil(&g, &p, 0, axi, &mut b);
                assert_eq!(a.len, b.len);
                assert_eq!(stencil_difference(&a, &b), (0.0, 0.0));
            }
        }
    }

    #[test]
    fn stretched_half_widths_equal_ugimp_with_scaled_widths() {
        let xs = positions();
        for (f11, f22) in [(1.5, 1.0), (1.0, 1.5), (1.5, 0.6), (0.3, 1.9)] {
            let mut changed = 0;
            for &x in &xs {
                let (a, b) = both(x, [0.025, 0.025], f11, f22, false);
                assert_eq!(stencil_difference(&a, &b), (0.0, 0.0), "at {x:?}, F = ({f11}, {f22})");
                let (c, _) = both(x, [0.025, 0.025], 1.0, 1.0, false);
                let (dw, dg) = stencil_difference(&a, &c);
                if dw > 1e-6 || dg > 1e-6 {
                    changed += 1;
                }
            }
            // The deformation really changes the weights (except where the particle domain
            // sits in the linear part of every hat, where GIMP equals linear for any l).
            assert!(changed * 4 > xs.len(), "F = ({f11}, {f22}) changed only {changed} of {}", xs.len());
        }
    }

    #[test]
    fn partition_of_unity_for_domains_larger_than_half_a_cell() {
        // l = 0.05 · 1.8 = 0.09 > h/2 in x; l = 0.05 · 0.4 in y. Up to 4 × 3 nodes.
        for x in positions() {
            for (f11, f22) in [(1.8, 0.4), (2.0, 2.0), (1.3, 1.7)] {
                let (a, _) = both(x, [0.05, 0.05], f11, f22, false);
                assert!(a.len <= 16);
                assert!((a.weight_sum() - 1.0).abs() < 1e-12, "ΣS = {} at {x:?}", a.weight_sum());
                let gs = a.gradient_sum();
                assert!(gs[0].abs() < 1e-10 && gs[1].abs() < 1e-10, "Σ∇S = {gs:?} at {x:?}");
            }
        }
        // A domain straddling 4 nodes per direction uses the full 4 × 4 stencil.
        let (a, _) = both([0.43, 0.57], [0.05, 0.05], 1.8, 1.8, false);
        assert_eq!(a.len, 16);
    }

    #[test]
    fn half_widths_beyond_one_cell_are_capped_at_h() {
        for x in positions() {
            let (a, _) = both(x, [0.05, 0.05], 5.0, 1.0, false);
            let (b, _) = both(x, [0.05, 0.05], 2.0, 1.0, false); // l_x = 0.1 = h exactly
            assert_eq!(stencil_difference(&a, &b), (0.0, 0.0));
            assert!((a.weight_sum() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn partition_of_unity_near_the_axis_with_stretched_domains() {
        let g = grid();
        let mut st = Stencil::default();
        for r in [1e-6, 0.002, 0.01, 0.03, 0.05, 0.07, 0.09, 0.1, 0.13, 0.17] {
            for (f11, f22) in [(1.0, 1.0), (1.9, 0.5), (0.5, 1.9), (3.0, 3.0)] {
                let mut p = single_particle([r, 0.461], [0.05, 0.05]);
                p.deformation_gradient[0] = [f11, 0.0, 0.0, f22, 1.0];
                CpGimp::stencil(&g, &p, 0, true, &mut st);
                assert!((st.weight_sum() - 1.0).abs() < 1e-12, "ΣS = {} at r = {r}", st.weight_sum());
                let gs = st.gradient_sum();
                assert!(gs[0].abs() < 1e-10 && gs[1].abs() < 1e-10, "Σ∇S = {gs:?} at r = {r}");
            }
        }
    }

    #[test]
    fn weights_are_continuous_across_cell_faces_for_large_domains() {
        for (f11, f22) in [(1.6, 1.6), (1.0, 1.0), (0.5, 1.9)] {
            for face in [0.3, 0.5] {
                for dir in 0..2 {
                    let mut lo = [0.437, 0.562];
                    let mut hi = lo;
                    lo[dir] = face - 1e-9;
                    hi[dir] = face + 1e-9;
                    let (a, _) = both(lo, [0.05, 0.05], f11, f22, false);
                    let (b, _) = both(hi, [0.05, 0.05], f11, f22, false);
                    let (dw, dg) = stencil_difference(&a, &b);
                    assert!(dw < 1e-7 && dg < 1e-5, "jump ({dw}, {dg}) at face {face} dir {dir}");
                }
            }
        }
    }
}
