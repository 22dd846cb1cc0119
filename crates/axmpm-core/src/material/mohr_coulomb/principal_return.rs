//! The principal-stress return of Mohr–Coulomb with a tension cut-off (Clausen, Damkilde &
//! Andersen 2006, 2007; references in the parent module): functions of the sorted principal
//! trial stresses σ1 ≥ σ2 ≥ σ3 (tension positive) and of the model's precomputed constants.
//!
//! # Yield surfaces and flow (sorted principal space σ1 ≥ σ2 ≥ σ3)
//!
//! Mohr–Coulomb:  f = k σ1 − σ3 − 2c√k ≤ 0, k = (1 + sin φ)/(1 − sin φ),
//! plastic potential g = m σ1 − σ3, m = (1 + sin ψ)/(1 − sin ψ), i.e. the flow direction of the
//! main plane is b = (m, 0, −1) (gradient a = (k, 0, −1)).
//! Its apex is σ_a (1, 1, 1) with σ_a = 2c√k/(k − 1) = c cot φ (0 for c = 0).
//!
//! Tension cut-off (Rankine, associated): σ1 ≤ σ_t, flow (1, 0, 0). `tension_cutoff` is clamped
//! to σ_a (a cut-off above the apex is never active); with σ_t = σ_a (always the case for c = 0)
//! there is no cut-off and the apex return takes care of tension.
//!
//! In principal space the elastic stiffness is D = λ 1 1ᵀ + 2μ I, the compliance C = D⁻¹.
//! A plastic corrector is σ_B − σ_C = D Σ Δλ_i b_i over the active planes, Δλ_i ≥ 0.
//!
//! ## Mohr–Coulomb returns (Clausen et al. 2007, §3–4)
//!
//! * **Plane**: σ_C = σ_B − f(σ_B) r_p, r_p = D b / (aᵀ D b).
//! * **Edges** (lines through the apex, in the sorted sector):
//!   l1 (σ1 = σ2, triaxial compression), direction r_l1 = −(1, 1, k);
//!   l2 (σ2 = σ3, triaxial extension),  direction r_l2 = −(1, k, k).
//!   σ_C = σ_a + t r_l with t = r_gᵀ C (σ_B − σ_a) / (r_gᵀ C r_l), where r_g is the matching edge
//!   of the plastic potential, r_g1 = (1, 1, m), r_g2 = (1, m, m) (r_g = b × b' of the two
//!   planes meeting at the edge; C r_g is the normal of the plane spanned by the two return
//!   directions D b, D b', so σ_B − σ_C lies in that span). t ≥ 0 is the valid part of the line.
//! * **Apex**: σ_C = σ_a (1, 1, 1).
//!
//! Region tests (all linear in σ_B): with σ_C^p the plane return,
//! p1 = σ_C1^p − σ_C2^p and p2 = σ_C2^p − σ_C3^p (the signed distances to the boundary planes
//! between the plane region and the edge regions, which contain the edge and r_p), and t1, t2 the
//! line parameters above (t = 0 is the boundary plane between an edge region and the apex region,
//! spanned by the two return directions of that edge):
//!
//! ```text
//! f(σ_B) ≤ 0                 elastic
//! t1 ≤ 0 and t2 ≤ 0          apex
//! p1 ≥ 0 and p2 ≥ 0          plane
//! p1 < 0 and t1 > 0          edge l1 (σ1 = σ2)
//! otherwise                  edge l2 (σ2 = σ3)
//! ```
//!
//! For ψ < φ the apex return is not a flow-rule return (for ψ = 0 a trial stress whose mean
//! stress exceeds σ_a cannot be reached with isochoric flow at all); as in Clausen et al. the
//! stress is put at the apex and the difference is booked as plastic strain.
//!
//! ## Tension cut-off combined with Mohr–Coulomb
//!
//! With an active cut-off (σ_t < σ_a) the candidates are tried in this order; each accepted one
//! satisfies both criteria, and for associated flow this order yields the closest-point
//! projection (a return that already satisfies the other criterion is the combined return):
//!
//! 1. Mohr–Coulomb return as above, if f(σ_B) > 0; accepted if σ1 ≤ σ_t.
//! 2. Rankine return (Clausen et al. 2006): plane σ1 = σ_t,
//!    σ_C = σ_B − (σ_B1 − σ_t)/(λ + 2μ) · (λ + 2μ, λ, λ); if then σ_C2 > σ_t (σ2 would exceed the
//!    cut-off, the docs/physics.md §5 pitfall) the edge σ1 = σ2 = σ_t with σ_C3 = σ_B3 − ν (σ_B1 + σ_B2 − 2σ_t);
//!    if also σ_C3 > σ_t the corner σ_t (1, 1, 1). Accepted if f(σ_C) ≤ 0.
//! 3. The Mohr–Coulomb/tension edge σ1 = σ_t, σ3 = kσ_t − 2c√k, whose return (span of D b and
//!    D e1, normal C e2) gives σ_C2 = σ_B2 − ν (σ_B1 − σ_t + σ_B3 − σ_C3); if σ_C2 > σ_t the corner
//!    (σ_t, σ_t, kσ_t − 2c√k), if σ_C2 < σ_C3 the corner (σ_t, kσ_t − 2c√k, kσ_t − 2c√k).
//!
//! ## Tresca: φ = 0 (undrained clay, total stress; docs/physics.md §8)
//!
//! With `friction_angle = 0` (allowed when `cohesion > 0`; the dilation angle is then 0) the
//! same formulas give Tresca, f = σ1 − σ3 − 2c: k = m = 1, the plane return moves σ1 and σ3 by
//! ∓f/2 (r_p = (1, 0, −1)/2), and the edge directions r_l1 = −(1, 1, 1), r_l2 = −(1, 1, 1) are
//! parallel to the hydrostatic axis: the prism has no apex (σ_a = c cot 0 = ∞). The edges are then
//! measured from finite points on them instead of the apex, o1 = (2c/3, 2c/3, −4c/3) on l1 and
//! o2 = (4c/3, −2c/3, −2c/3) on l2 (mean stress 0), σ_C = o + t r_l with the same t = n·(σ_B − o);
//! with ψ = 0 that keeps the mean stress of the trial (isochoric flow). Without an apex the apex
//! region and the half-line limits t ≥ 0 do not exist: p1 < 0 means edge l1, p2 < 0 edge l2 (both
//! cannot be negative, since p1 + p2 = σ_C1^p − σ_C3^p = 2c > 0). Closed-form strengths:
//! uniaxial compression or tension and plane-strain compression all fail at |σ1 − σ3| = 2c (in
//! plane strain σ_zz stays intermediate because the flow (1, 0, −1) has no out-of-plane part),
//! simple shear at τ = c, independent of the mean stress.
//!
//! An undrained total-stress analysis has no tension cut-off: for φ = 0 an unset
//! `tension_cutoff` means none (σ_t = ∞); a given value is honoured. For φ > 0 the unset value
//! stays 0.

use super::MohrCoulomb;

/// Which part of the yield surface a return went to (sorted principal space).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReturnRegion {
    /// Inside both criteria: the trial stress stands.
    Elastic,
    /// Mohr–Coulomb plane k σ1 − σ3 = 2c√k.
    Plane,
    /// Mohr–Coulomb edge σ1 = σ2 (triaxial compression).
    EdgeCompression,
    /// Mohr–Coulomb edge σ2 = σ3 (triaxial extension).
    EdgeExtension,
    /// Mohr–Coulomb apex σ_a (1, 1, 1).
    Apex,
    /// Tension cut-off plane σ1 = σ_t.
    TensionPlane,
    /// Tension cut-off edge σ1 = σ2 = σ_t.
    TensionEdge,
    /// Tension cut-off corner σ1 = σ2 = σ3 = σ_t.
    TensionCorner,
    /// Intersection line of the Mohr–Coulomb plane and the cut-off: σ1 = σ_t, σ3 = kσ_t − 2c√k.
    TensionShearEdge,
    /// Corner (σ_t, σ_t, kσ_t − 2c√k): cut-off edge meets the compression edge.
    TensionShearCornerCompression,
    /// Corner (σ_t, kσ_t − 2c√k, kσ_t − 2c√k): cut-off meets the extension edge.
    TensionShearCornerExtension,
}

#[inline(always)]
pub(super) fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl MohrCoulomb {
    /// Mohr–Coulomb yield function f = k σ1 − σ3 − 2c√k of sorted principal stresses.
    #[inline(always)]
    pub fn yield_function(&self, s: &[f64; 3]) -> f64 {
        self.k * s[0] - s[2] - self.two_c_sqrt_k
    }

    /// Apex stress c cot φ and effective tension cut-off min(σ_t, c cot φ) (∞ when absent).
    pub fn apex_and_cutoff(&self) -> (f64, f64) {
        (self.apex, self.sigma_t)
    }

    /// Mohr–Coulomb part of the return for a sorted trial with f(s) > 0 (Clausen et al. 2007).
    #[inline(always)]
    fn return_mohr_coulomb(&self, s: &[f64; 3]) -> ([f64; 3], ReturnRegion) {
        let f = self.yield_function(s);
        // Edge parameters from the apex (φ > 0) or from a point on each edge (Tresca).
        let [o1, o2] = &self.edge_origin;
        let t1 = dot(&self.n_l1, &[s[0] - o1[0], s[1] - o1[1], s[2] - o1[2]]);
        let t2 = dot(&self.n_l2, &[s[0] - o2[0], s[1] - o2[1], s[2] - o2[2]]);
        if self.has_apex && t1 <= 0.0 && t2 <= 0.0 {
            let sa = self.apex;
            return ([sa, sa, sa], ReturnRegion::Apex);
        }
        let sc = [s[0] - f * self.r_p[0], s[1] - f * self.r_p[1], s[2] - f * self.r_p[2]];
        let p1 = sc[0] - sc[1];
        let p2 = sc[1] - sc[2];
        if p1 >= 0.0 && p2 >= 0.0 {
            return (sc, ReturnRegion::Plane);
        }
        if p1 < 0.0 && (t1 > 0.0 || !self.has_apex) {
            let r = &self.r_l1;
            return ([o1[0] + t1 * r[0], o1[1] + t1 * r[1], o1[2] + t1 * r[2]], ReturnRegion::EdgeCompression);
        }
        let t2 = if self.has_apex { t2.max(0.0) } else { t2 };
        let r = &self.r_l2;
        ([o2[0] + t2 * r[0], o2[1] + t2 * r[1], o2[2] + t2 * r[2]], ReturnRegion::EdgeExtension)
    }

    /// Rankine (tension cut-off) return of a sorted trial with σ1 > σ_t (Clausen et al. 2006).
    #[inline(always)]
    fn return_tension(&self, s: &[f64; 3]) -> ([f64; 3], ReturnRegion) {
        let st = self.sigma_t;
        let d1 = s[0] - st;
        let nu_p = self.lambda / (self.lambda + 2.0 * self.mu);
        let s2 = s[1] - nu_p * d1;
        if s2 <= st {
            return ([st, s2, s[2] - nu_p * d1], ReturnRegion::TensionPlane);
        }
        let s3 = s[2] - self.poisson_ratio * (d1 + (s[1] - st));
        if s3 <= st {
            ([st, st, s3], ReturnRegion::TensionEdge)
        } else {
            ([st, st, st], ReturnRegion::TensionCorner)
        }
    }

    /// Return to the Mohr–Coulomb/tension intersection line or its end corners.
    #[inline(always)]
    fn return_tension_shear(&self, s: &[f64; 3]) -> ([f64; 3], ReturnRegion) {
        let st = self.sigma_t;
        let s3 = self.k * st - self.two_c_sqrt_k;
        let s2 = s[1] - self.poisson_ratio * ((s[0] - st) + (s[2] - s3));
        if s2 > st {
            ([st, st, s3], ReturnRegion::TensionShearCornerCompression)
        } else if s2 < s3 {
            ([st, s3, s3], ReturnRegion::TensionShearCornerExtension)
        } else {
            ([st, s2, s3], ReturnRegion::TensionShearEdge)
        }
    }

    /// Full return mapping of sorted principal trial stresses `s` (σ1 ≥ σ2 ≥ σ3).
    pub fn return_principal(&self, s: &[f64; 3]) -> ([f64; 3], ReturnRegion) {
        let scale = s[0].abs() + s[1].abs() + s[2].abs() + self.two_c_sqrt_k + self.sigma_t_scale;
        let tol = 1e-14 * self.k * scale;
        let f = self.yield_function(s);
        let shear = f > tol;
        let tension = self.cutoff && s[0] > self.sigma_t + tol;
        if !shear && !tension {
            return (*s, ReturnRegion::Elastic);
        }
        if shear {
            let r = self.return_mohr_coulomb(s);
            if !self.cutoff || r.0[0] <= self.sigma_t + tol {
                return r;
            }
        }
        let r = self.return_tension(s);
        if self.yield_function(&r.0) <= tol {
            return r;
        }
        self.return_tension_shear(s)
    }

    /// Principal plastic strain increment C (σ_B − σ_C).
    #[inline(always)]
    pub(super) fn plastic_strain(&self, trial: &[f64; 3], ret: &[f64; 3]) -> [f64; 3] {
        let d = [trial[0] - ret[0], trial[1] - ret[1], trial[2] - ret[2]];
        let nu = self.poisson_ratio;
        let s = nu * (d[0] + d[1] + d[2]);
        let e = self.youngs_modulus;
        [((1.0 + nu) * d[0] - s) / e, ((1.0 + nu) * d[1] - s) / e, ((1.0 + nu) * d[2] - s) / e]
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::*;
    use super::*;
    use crate::material::testing::{random_sorted, solve, Lcg};

    /// Test 2: trial stresses built as σ_C + D Σ Δλ_i b_i (Δλ_i > 0) from a point σ_C on each
    /// part of the surface; the return must name that part and recover σ_C.
    #[test]
    fn each_return_region_is_reached_and_lands_on_the_surface() {
        use ReturnRegion::*;
        for &psi in &[30.0, 0.0, 12.0] {
            let f = flows(psi);
            let (phi, c, st) = (30.0, 20e3, 10e3);
            let k = kk(phi);
            let b = 2.0 * c * k.sqrt();
            let with_cut = mc(phi, psi, c, st);
            let no_cut = mc(phi, psi, c, 1e12);
            let (apex, stc) = no_cut.apex_and_cutoff();
            assert!((apex - c / f64::to_radians(phi).tan()).abs() < 1e-9 * apex);
            assert!(!no_cut.cutoff && stc == apex && with_cut.cutoff);
            let s3l = k * st - b;
            let on = |s1: f64| k * s1 - b;
            let l = 4e-4;
            let mut cases: Vec<(&MohrCoulomb, [f64; 3], [f64; 3], ReturnRegion)> = vec![
                (&no_cut, [-50e3, -100e3, on(-50e3)], add_flow([-50e3, -100e3, on(-50e3)], &[(l, f[0])]), Plane),
                (
                    &no_cut,
                    [-50e3, -50e3, on(-50e3)],
                    add_flow([-50e3, -50e3, on(-50e3)], &[(l, f[0]), (0.5 * l, f[1])]),
                    EdgeCompression,
                ),
                (
                    &no_cut,
                    [-50e3, on(-50e3), on(-50e3)],
                    add_flow([-50e3, on(-50e3), on(-50e3)], &[(l, f[0]), (0.3 * l, f[2])]),
                    EdgeExtension,
                ),
                (&with_cut, [-5e3, -50e3, on(-5e3)], add_flow([-5e3, -50e3, on(-5e3)], &[(l, f[0])]), Plane),
                (&with_cut, [st, 0.0, -20e3], add_flow([st, 0.0, -20e3], &[(l, f[3])]), TensionPlane),
                (&with_cut, [st, st, -20e3], add_flow([st, st, -20e3], &[(l, f[3]), (0.2 * l, f[4])]), TensionEdge),
                (
                    &with_cut,
                    [st, st, st],
                    add_flow([st, st, st], &[(l, f[3]), (0.5 * l, f[4]), (0.1 * l, f[5])]),
                    TensionCorner,
                ),
                (&with_cut, [st, -10e3, s3l], add_flow([st, -10e3, s3l], &[(l, f[0]), (l, f[3])]), TensionShearEdge),
                (
                    &with_cut,
                    [st, st, s3l],
                    add_flow([st, st, s3l], &[(l, f[0]), (0.5 * l, f[1]), (l, f[3]), (0.5 * l, f[4])]),
                    TensionShearCornerCompression,
                ),
                (
                    &with_cut,
                    [st, s3l, s3l],
                    add_flow([st, s3l, s3l], &[(l, f[0]), (0.5 * l, f[2]), (0.2 * l, f[3])]),
                    TensionShearCornerExtension,
                ),
            ];
            if psi == phi {
                let a = [apex; 3];
                cases.push((&no_cut, a, add_flow(a, &[(l, f[0]), (0.5 * l, f[1]), (0.3 * l, f[2])]), Apex));
            } else {
                // Non-associated: beyond the apex in hydrostatic tension.
                cases.push((&no_cut, [apex; 3], [apex + 30e3; 3], Apex));
                cases.push((&no_cut, [apex; 3], [apex + 30e3, apex + 20e3, apex - 10e3], Apex));
            }
            // Cohesionless: the apex is the origin.
            let sand = mc(phi, psi, 0.0, 0.0);
            cases.push((&sand, [0.0; 3], [30e3, 10e3, 5e3], Apex));
            for (m, target, trial, region) in cases {
                assert!(trial[0] >= trial[1] && trial[1] >= trial[2], "psi {psi} {region:?}: {trial:?}");
                assert!(target[0] >= target[1] && target[1] >= target[2], "psi {psi} {region:?}: {target:?}");
                let (ret, got) = m.return_principal(&trial);
                let sc = scale(&trial, m);
                assert_eq!(got, region, "psi {psi}: trial {trial:?} -> {ret:?}");
                for i in 0..3 {
                    assert!((ret[i] - target[i]).abs() <= 1e-9 * sc, "psi {psi} {region:?}: {ret:?} vs {target:?}");
                }
                assert!(ret[0] >= ret[1] && ret[1] >= ret[2]);
                assert!(worst(m, &ret).abs() <= 1e-9 * sc, "{region:?}: not on the surface, {}", worst(m, &ret));
            }
        }
    }

    /// Test 2 (sweep): for random trial stresses in every region and several parameter sets, the
    /// return is sorted, admissible, on the surface, and obeys the flow rule of the region it
    /// names (non-negative multipliers; corners of non-associated flow excepted).
    #[test]
    fn random_returns_are_admissible_and_obey_the_flow_rule() {
        let mut rng = Lcg(12345);
        let mut seen = std::collections::BTreeSet::new();
        for &(phi, psi, c, st) in &[
            (30.0, 0.0, 0.0, 0.0),
            (30.0, 30.0, 20e3, 10e3),
            (40.0, 10.0, 20e3, 0.0),
            (20.0, 5.0, 50e3, 1e3),
            (45.0, 45.0, 0.0, 0.0),
        ] {
            let m = mc(phi, psi, c, st);
            for _ in 0..40000 {
                let trial = random_sorted(&mut rng, -300e3, 150e3);
                let (ret, region) = m.return_principal(&trial);
                seen.insert(format!("{region:?}"));
                let sc = scale(&trial, &m);
                assert!(ret[0] >= ret[1] && ret[1] >= ret[2], "{trial:?} -> {ret:?} {region:?}");
                let w = worst(&m, &ret);
                if region == ReturnRegion::Elastic {
                    assert!(w <= 1e-12 * sc && ret == trial);
                    continue;
                }
                assert!(w.abs() <= 1e-9 * sc, "{trial:?} -> {ret:?} {region:?}: {w}");
                let corner = matches!(
                    region,
                    ReturnRegion::Apex
                        | ReturnRegion::TensionShearCornerCompression
                        | ReturnRegion::TensionShearCornerExtension
                );
                if psi == phi || !corner {
                    assert!(
                        flow_rule_holds(&trial, &ret, &active_flows(region, psi)),
                        "phi {phi} psi {psi} c {c} st {st}: {trial:?} -> {ret:?} {region:?}"
                    );
                }
            }
        }
        assert_eq!(seen.len(), 11, "regions reached: {seen:?}");
    }

    /// Associated flow (ψ = φ) makes the return the closest point in the energy norm
    /// (σ − σ_B)ᵀ C (σ − σ_B); checked against a brute-force projection onto every face,
    /// edge and corner of the sorted-sector yield polytope.
    #[test]
    fn associated_return_is_the_closest_point_projection() {
        let mut rng = Lcg(777);
        for &(phi, c, st) in &[
            (30.0, 20e3, 10e3),
            (30.0, 0.0, 0.0),
            (40.0, 30e3, 0.0),
            (15.0, 10e3, 1e9),
            // Tresca (φ = ψ = 0 is associated): without and with a cut-off.
            (0.0, 20e3, f64::INFINITY),
            (0.0, 20e3, 5e3),
        ] {
            let m = mc(phi, phi, c, st);
            let k = m.k;
            let b = m.two_c_sqrt_k;
            let ts = m.sigma_t;
            // (gradients, right-hand sides) of affine hulls.
            let mut faces: Vec<(Vec<[f64; 3]>, Vec<f64>)> = vec![
                (vec![[k, 0.0, -1.0]], vec![b]),
                (vec![[k, 0.0, -1.0], [0.0, k, -1.0]], vec![b, b]),
                (vec![[k, 0.0, -1.0], [k, -1.0, 0.0]], vec![b, b]),
            ];
            let mut vertices = vec![];
            if m.cutoff {
                faces.push((vec![[1.0, 0.0, 0.0]], vec![ts]));
                faces.push((vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![ts, ts]));
                faces.push((vec![[k, 0.0, -1.0], [1.0, 0.0, 0.0]], vec![b, ts]));
                let s3 = k * ts - b;
                vertices.extend([[ts, ts, s3], [ts, s3, s3], [ts, ts, ts]]);
            } else if m.has_apex {
                vertices.push([m.apex; 3]);
            }
            for _ in 0..20000 {
                let trial = random_sorted(&mut rng, -300e3, 150e3);
                let (ret, _) = m.return_principal(&trial);
                let sc = scale(&trial, &m);
                let dist = |s: &[f64; 3]| {
                    let d = [s[0] - trial[0], s[1] - trial[1], s[2] - trial[2]];
                    dot(&d, &comply(d))
                };
                let mut best = if worst(&m, &trial) <= 0.0 { Some((0.0, trial)) } else { None };
                let mut consider = |s: [f64; 3]| {
                    if worst(&m, &s) <= 1e-10 * sc {
                        let d = dist(&s);
                        if best.is_none_or(|(bd, _)| d < bd) {
                            best = Some((d, s));
                        }
                    }
                };
                for v in &vertices {
                    consider(*v);
                }
                for (n, h) in &faces {
                    let dn: Vec<[f64; 3]> = n.iter().map(|g| stiff(*g)).collect();
                    let a: Vec<Vec<f64>> = n.iter().map(|gi| dn.iter().map(|dj| dot(gi, dj)).collect()).collect();
                    let r: Vec<f64> = n.iter().zip(h).map(|(gi, hi)| dot(gi, &trial) - hi).collect();
                    let l = solve(a, r).unwrap();
                    let mut s = trial;
                    for (q, d) in dn.iter().enumerate() {
                        for c in 0..3 {
                            s[c] -= l[q] * d[c];
                        }
                    }
                    consider(s);
                }
                let (_, want) = best.unwrap();
                for i in 0..3 {
                    assert!(
                        (ret[i] - want[i]).abs() <= 1e-8 * sc,
                        "phi {phi} c {c} st {st}: {trial:?} -> {ret:?}, closest {want:?}"
                    );
                }
            }
        }
    }

    /// Trial stresses σ_C + D Σ Δλ_i b_i from a point σ_C on each part of the Tresca prism (and
    /// of its cut-off): the return names that part and recovers σ_C.
    #[test]
    fn tresca_each_return_region_is_reached_and_lands_on_the_surface() {
        use ReturnRegion::*;
        let f = flows(0.0);
        let (c, st) = (20e3, 10e3);
        let no_cut = tresca(c, f64::INFINITY);
        let with_cut = tresca(c, st);
        assert!(!no_cut.cutoff && no_cut.apex_and_cutoff() == (f64::INFINITY, f64::INFINITY));
        assert!(with_cut.cutoff && with_cut.apex_and_cutoff().1 == st);
        let b = 2.0 * c;
        let s3l = st - b;
        let l = 4e-4;
        let cases: Vec<(&MohrCoulomb, [f64; 3], Vec<(f64, [f64; 3])>, ReturnRegion)> = vec![
            (&no_cut, [-50e3, -70e3, -50e3 - b], vec![(l, f[0])], Plane),
            (&no_cut, [-50e3, -50e3, -50e3 - b], vec![(l, f[0]), (0.5 * l, f[1])], EdgeCompression),
            (&no_cut, [-50e3, -50e3 - b, -50e3 - b], vec![(l, f[0]), (0.3 * l, f[2])], EdgeExtension),
            // Far in hydrostatic tension and compression: the prism is open both ways.
            (&no_cut, [5e6, 5e6, 5e6 - b], vec![(2.0 * l, f[0]), (l, f[1])], EdgeCompression),
            (&no_cut, [-5e6, -5e6 - b, -5e6 - b], vec![(l, f[0]), (0.1 * l, f[2])], EdgeExtension),
            (&no_cut, [8e6, 8e6 - 0.5 * b, 8e6 - b], vec![(3.0 * l, f[0])], Plane),
            (&with_cut, [-5e3, -20e3, -5e3 - b], vec![(l, f[0])], Plane),
            (&with_cut, [st, 0.0, -20e3], vec![(l, f[3])], TensionPlane),
            (&with_cut, [st, st, -20e3], vec![(l, f[3]), (0.2 * l, f[4])], TensionEdge),
            (&with_cut, [st, st, st], vec![(l, f[3]), (0.5 * l, f[4]), (0.1 * l, f[5])], TensionCorner),
            (&with_cut, [st, -10e3, s3l], vec![(l, f[0]), (l, f[3])], TensionShearEdge),
            (
                &with_cut,
                [st, st, s3l],
                vec![(l, f[0]), (0.5 * l, f[1]), (l, f[3]), (0.5 * l, f[4])],
                TensionShearCornerCompression,
            ),
            (&with_cut, [st, s3l, s3l], vec![(l, f[0]), (0.5 * l, f[2]), (0.2 * l, f[3])], TensionShearCornerExtension),
        ];
        for (m, target, flow, region) in cases {
            let trial = add_flow(target, &flow);
            assert!(trial[0] >= trial[1] && trial[1] >= trial[2], "{region:?}: {trial:?}");
            let (ret, got) = m.return_principal(&trial);
            let sc = scale(&trial, m);
            assert_eq!(got, region, "trial {trial:?} -> {ret:?}");
            for i in 0..3 {
                assert!((ret[i] - target[i]).abs() <= 1e-9 * sc, "{region:?}: {ret:?} vs {target:?}");
            }
            assert!(worst(m, &ret).abs() <= 1e-9 * sc, "{region:?}: not on the surface, {}", worst(m, &ret));
            // ψ = 0: the shear returns keep the mean stress (isochoric plastic flow).
            if matches!(region, Plane | EdgeCompression | EdgeExtension) {
                let mean = |s: &[f64; 3]| s[0] + s[1] + s[2];
                assert!((mean(&ret) - mean(&trial)).abs() <= 1e-9 * sc, "{region:?}: mean stress changed");
            }
        }
    }

    /// Random trials for Tresca: sorted, admissible, on the surface, associated flow rule; the
    /// regions reached are exactly those the prism (and its cut-off) has: no apex.
    #[test]
    fn tresca_random_returns_are_admissible_and_obey_the_flow_rule() {
        use ReturnRegion::*;
        let mut rng = Lcg(4242);
        for &(c, st) in &[(20e3, f64::INFINITY), (20e3, 10e3), (50e3, 0.0)] {
            let m = tresca(c, st);
            let mut seen = std::collections::BTreeSet::new();
            for _ in 0..40000 {
                let trial = random_sorted(&mut rng, -300e3, 150e3);
                let (ret, region) = m.return_principal(&trial);
                seen.insert(format!("{region:?}"));
                let sc = scale(&trial, &m);
                assert!(ret[0] >= ret[1] && ret[1] >= ret[2], "{trial:?} -> {ret:?} {region:?}");
                let w = worst(&m, &ret);
                if region == Elastic {
                    assert!(w <= 1e-12 * sc && ret == trial);
                    continue;
                }
                assert!(w.abs() <= 1e-9 * sc, "{trial:?} -> {ret:?} {region:?}: {w}");
                assert!(flow_rule_holds(&trial, &ret, &active_flows(region, 0.0)), "c {c} st {st}: {trial:?} {region:?}");
            }
            let mut want: Vec<&str> = vec!["Elastic", "Plane", "EdgeCompression", "EdgeExtension"];
            if st.is_finite() {
                want.extend([
                    "TensionPlane",
                    "TensionEdge",
                    "TensionCorner",
                    "TensionShearEdge",
                    "TensionShearCornerCompression",
                    "TensionShearCornerExtension",
                ]);
            }
            let want: std::collections::BTreeSet<String> = want.into_iter().map(String::from).collect();
            assert_eq!(seen, want, "c {c} st {st}");
        }
    }
}
