//! Mohr–Coulomb elasto-plasticity with non-associated flow and a tension cut-off
//! (docs/physics.md §5), integrated with the principal-stress return of
//! Clausen, Damkilde & Andersen:
//!
//! * J. Clausen, L. Damkilde, L. Andersen (2006), *Efficient return algorithms for associated
//!   plasticity with multiple yield planes*, Int. J. Numer. Meth. Engng 66:1036–1059.
//! * J. Clausen, L. Damkilde, L. Andersen (2007), *An efficient return algorithm for
//!   non-associated plasticity with linear yield criteria in principal stress space*,
//!   Computers & Structures 85:1795–1807.
//!
//! # Stress update (one step)
//!
//! 1. Hypoelastic trial with the Jaumann rate, exactly as [`LinearElastic`]:
//!    σ_B = σ + dt (W σ − σ W) + λ tr(dε) I + 2μ dε, dε = D dt.
//! 2. Principal stresses of σ_B: the in-plane 2×2 block in closed form
//!    (centre c = (σ11+σ22)/2, radius R = √(((σ11−σ22)/2)² + σ12²), eigenvalues c ± R, direction
//!    cos 2θ = (σ11−σ22)/(2R), sin 2θ = σ12/R; R = 0 takes θ = 0) plus σ33, which is always
//!    principal. They are sorted σ1 ≥ σ2 ≥ σ3 (tension positive) remembering where each came from.
//! 3. Return mapping in principal space ([`principal_return`]: the yield surfaces, the return
//!    regions and their formulas). Elastic isotropy makes the plastic corrector
//!    coaxial with σ_B, so the returned principal values are simply put back on the same axes:
//!    σ11 = c' + R' cos 2θ, σ22 = c' − R' cos 2θ, σ12 = R' sin 2θ, σ33 = its own returned value.
//!    The ordering is preserved by every return, so R' ≥ 0; equal principal values (any
//!    eigenvector basis) are returned equal, so the arbitrary basis of a degenerate pair is harmless.
//!
//! # State variables
//!
//! With the principal plastic strain increment Δε^p = C (σ_B − σ_C) (tensor strain; coaxial with
//! the stress):
//! * `plastic_shear_strain`: Σ √(2/3 Δe^p : Δe^p), Δe^p = dev Δε^p (accumulated equivalent
//!   deviatoric plastic strain, ≥ 0; in triaxial compression its rate is (2/3)|ε̇1^p − ε̇3^p|).
//! * `plastic_volumetric_strain`: Σ tr Δε^p (signed accumulated plastic volume change,
//!   dilation positive; identically zero for ψ = 0 except for apex / tension returns).
//! * `disconnection_work` (only with `critical_packing_fraction`): the elastic energy discarded
//!   by disconnection, J per m³ of reference volume (also counted in `plastic_work`), see
//!   "Disconnected material" below.
//!
//! # Dilute material and the time step
//!
//! The elastic moduli are those of the material as placed, whatever its density: with
//! ρ = ρ0/J the P-wave speed of a particle is c(J) = √((λ + 2μ) J/ρ0) = c0 √J. The explicit
//! step is computed for c0 (`cfl` h/c0), so a particle dilated beyond the step's stability
//! limit (c(J) Δt/h > 1/√2, [`crate::simulation::COURANT_LIMIT`]) and then re-loaded is
//! integrated unstably (material dilated stress-free by apex returns and compressed again).
//! Such material is a granular gas (packing φ0/J ≤ 0.2 at the
//! limit J ≈ 3 of `cfl` = 0.4): it has no contact network, so its true stiffness is nil (the
//! disconnected state below), and any stiffness below that of the material as placed is
//! physically admissible.
//!
//! The engine therefore tells the model the fastest wave speed its step keeps stable,
//! c_max = h/(√2 Δt) ([`Material::limit_wave_speed`]), and above
//! J_s = max(1, (c_max/c0)²) (3.125 at `cfl` = 0.4) the moduli of the trial are scaled by
//! s = J_s/J: σ_B = σ + Jaumann terms + s (λ tr dε I + 2μ dε), so that c(J) = c_max at any
//! J > J_s. The return mapping's directions are ratios of the moduli and do not change; the
//! plastic strain is that of the softer moduli, Δε^p = C (σ_B − σ_C)/s (C the compliance of the
//! material as placed), so a stress-free dilute particle books all of its strain as plastic.
//! `elastic_energy` still uses C (the stored energy of such particles is underestimated by
//! 1/s; they are stress-free but for their re-loading steps). Up to J_s the update is bit for
//! bit the one without the limit (tested), so runs in which no particle is re-loaded beyond
//! J_s are unchanged.
//!
//! # Disconnected material below the critical packing (`critical_packing_fraction`, experimental)
//!
//! The Dunatunga & Kamrin (2015) rule itself, with the threshold a property of the grains
//! instead of each particle's own separation density: a granular material whose packing
//! fraction φ = ρ/ρ_s has fallen below its critical (random-loose) packing φ_c has no
//! enduring contacts and carries no stress. With the bulk density `density` = ρ0 of the
//! material as placed and the grain density `grain_density` = ρ_s, the packing as placed is
//! φ0 = ρ0/ρ_s and a particle of J = det F = V/V0 has φ = φ0/J, so it is **disconnected**
//! when
//!
//! ```text
//! J > J_c = φ0/φ_c = ρ0/(φ_c ρ_s)      (φ_c ≤ φ0, so J_c ≥ 1)
//! ```
//!
//! J is the solver's det F at the end of the step ([`Kinematics::jacobian`]).
//!
//! 1. **Disconnected** (J > J_c, any c): σ = 0, whatever the trial stress σ_B (it can carry
//!    neither tension nor compression). The whole trial is booked as plastic strain,
//!    Δε^p = C σ_B (its deviatoric norm in `plastic_shear_strain`, its trace in
//!    `plastic_volumetric_strain`). The elastic energy it had, net of the work done in the
//!    step, is booked as dissipation in `disconnection_work` and in `plastic_work`: with the
//!    trapezoidal stress power ½(σ_n + σ_{n+1}) : dε, a return from σ_B to σ_{n+1}
//!    dissipates ½(σ_n + σ_{n+1}) : Δε^p (since W(σ_{n+1}) − W(σ_n) = ½(σ_n + σ_{n+1}) :
//!    C (σ_{n+1} − σ_n), W the complementary energy density, [`super::complementary_energy`]);
//!    for σ_{n+1} = 0 that is J ½ σ_n : C σ_B per unit reference volume (σ_n with the step's
//!    Jaumann rotation), = J W(σ_n) for a step without deformation, 0 for a point that was
//!    already stress-free, and clamped at 0 (a stressed point that unloads through zero
//!    within the step gives a negative trapezoidal value, while the exact elastic path
//!    dissipates nothing). The ordinary returns book the backward-Euler σ_{n+1} : Δε^p
//!    instead, which differs from this by a second-order term.
//! 2. **Re-connection** (J ≤ J_c at the end of a step that started with J_n > J_c): the
//!    compression done while still disconnected, ln(J_n/J_c) with ln J_n = ln J − tr dε
//!    (tr dε is the rate form of Δ ln J), is removed from the strain increment before the
//!    elastic trial, dε ← dε + (Δc/3) I, and booked as plastic compaction
//!    (`plastic_volumetric_strain` −= Δc). The material therefore re-connects at the critical
//!    packing with σ = 0: nothing of the volume it lost while disconnected is stored as
//!    elastic strain, so nothing of it rebounds (inelastic re-compaction). Only compression
//!    beyond J_c builds elastic stress.
//! 3. **Connected** (J ≤ J_c): the Mohr–Coulomb update above (tension returns to the apex,
//!    0 for c = 0).
//!
//! There is no per-particle memory: the state is a function of J alone, as in Dunatunga & Kamrin, and the deposit can be no looser than
//! φ_c where it was disconnected (J ≤ J_c) unless it was left disconnected. Absent (the
//! default), the update is bit for bit the one without this option.

pub mod principal_return;

use super::{jaumann_rotation, lame, p_wave_speed, rate_of_deformation, Kinematics, LinearElastic, Material, Parameters};
use crate::particles::Stress;
pub use principal_return::ReturnRegion;
use principal_return::dot;

/// State slots: accumulated plastic shear strain, plastic volumetric strain, (with
/// `critical_packing_fraction`) the energy discarded by disconnection, and the plastic work
/// (last).
const STATE_NAMES_PLAIN: [&str; 3] = ["plastic_shear_strain", "plastic_volumetric_strain", "plastic_work"];
const STATE_NAMES_DISCONNECTION: [&str; 4] =
    ["plastic_shear_strain", "plastic_volumetric_strain", "disconnection_work", "plastic_work"];
/// Slot of `disconnection_work` (with `critical_packing_fraction`).
const DISCONNECTION_WORK: usize = 2;

#[derive(Clone, Debug)]
pub struct MohrCoulomb {
    pub density: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    /// Degrees.
    pub friction_angle: f64,
    /// Degrees.
    pub dilation_angle: f64,
    /// Pa.
    pub cohesion: f64,
    /// Pa, as configured (the effective value is clamped to the apex); `f64::INFINITY` = none.
    pub tension_cutoff: f64,
    /// J_c = φ0/φ_c above which the material is disconnected (module doc); `None` = off.
    pub critical_jacobian: Option<f64>,
    /// J above which the elastic moduli are scaled by `stable_jacobian / J` so that the
    /// particle's P-wave speed stays within the time step's stability limit (module doc,
    /// "Dilute material and the time step"); ∞ = never (set by [`Material::limit_wave_speed`]).
    pub stable_jacobian: f64,
    elastic: LinearElastic,
    lambda: f64,
    mu: f64,
    /// k = (1 + sin φ)/(1 − sin φ).
    k: f64,
    /// 2c√k.
    two_c_sqrt_k: f64,
    /// Apex σ_a = c cot φ (∞ for Tresca, φ = 0).
    apex: f64,
    /// The yield surface has an apex (φ > 0); Tresca (φ = 0) is an open prism.
    has_apex: bool,
    /// Points the edge lines l1, l2 are measured from: the apex, or for Tresca the points of
    /// mean stress 0 on each edge (module doc).
    edge_origin: [[f64; 3]; 2],
    /// Effective cut-off min(σ_t, σ_a).
    sigma_t: f64,
    /// |σ_t| where finite, else 0: the cut-off's share of the stress scale of the tolerances.
    sigma_t_scale: f64,
    /// σ_t < σ_a: the cut-off is active.
    cutoff: bool,
    /// Plane return direction D b / (aᵀ D b).
    r_p: [f64; 3],
    /// Edge directions (valid part t ≥ 0).
    r_l1: [f64; 3],
    r_l2: [f64; 3],
    /// C r_g / (r_gᵀ C r_l): t = n · (σ_B − σ_a).
    n_l1: [f64; 3],
    n_l2: [f64; 3],
    /// 1e-9 (1 + |k|): the margin of [`Self::clearly_elastic`] per unit stress scale.
    elastic_margin: f64,
}

impl MohrCoulomb {
    /// Angles in degrees. Preconditions (checked by [`MohrCoulomb::from_parameters`]):
    /// 0 ≤ φ < 90 (φ = 0 only with c > 0: Tresca), 0 ≤ ψ ≤ φ, c ≥ 0, σ_t ≥ 0 (∞ = no cut-off),
    /// E > 0, −1 < ν < 0.5.
    pub fn new(
        density: f64,
        youngs_modulus: f64,
        poisson_ratio: f64,
        friction_angle: f64,
        dilation_angle: f64,
        cohesion: f64,
        tension_cutoff: f64,
    ) -> Self {
        let (lambda, mu) = lame(youngs_modulus, poisson_ratio);
        let sphi = friction_angle.to_radians().sin();
        let spsi = dilation_angle.to_radians().sin();
        let k = (1.0 + sphi) / (1.0 - sphi);
        let m = (1.0 + spsi) / (1.0 - spsi);
        let two_c_sqrt_k = 2.0 * cohesion * k.sqrt();
        let has_apex = k > 1.0;
        let apex = if has_apex { two_c_sqrt_k / (k - 1.0) } else { f64::INFINITY };
        let sigma_t = tension_cutoff.min(apex);
        let cutoff = sigma_t < apex;
        let sigma_t_scale = if sigma_t.is_finite() { sigma_t.abs() } else { 0.0 };
        let edge_origin = if has_apex {
            [[apex; 3]; 2]
        } else {
            let third = two_c_sqrt_k / 3.0; // 2c/3 (k = 1)
            [[third, third, -2.0 * third], [2.0 * third, -third, -third]]
        };

        let stiff = |v: [f64; 3]| -> [f64; 3] {
            let tr = lambda * (v[0] + v[1] + v[2]);
            [tr + 2.0 * mu * v[0], tr + 2.0 * mu * v[1], tr + 2.0 * mu * v[2]]
        };
        let comply = |v: [f64; 3]| -> [f64; 3] {
            let s = poisson_ratio * (v[0] + v[1] + v[2]);
            let e = youngs_modulus;
            [
                ((1.0 + poisson_ratio) * v[0] - s) / e,
                ((1.0 + poisson_ratio) * v[1] - s) / e,
                ((1.0 + poisson_ratio) * v[2] - s) / e,
            ]
        };
        let a = [k, 0.0, -1.0];
        let db = stiff([m, 0.0, -1.0]);
        let adb = dot(&a, &db);
        let r_p = [db[0] / adb, db[1] / adb, db[2] / adb];
        let r_l1 = [-1.0, -1.0, -k];
        let r_l2 = [-1.0, -k, -k];
        let cg1 = comply([1.0, 1.0, m]);
        let cg2 = comply([1.0, m, m]);
        let d1 = dot(&cg1, &r_l1);
        let d2 = dot(&cg2, &r_l2);
        let n_l1 = [cg1[0] / d1, cg1[1] / d1, cg1[2] / d1];
        let n_l2 = [cg2[0] / d2, cg2[1] / d2, cg2[2] / d2];

        Self {
            density,
            youngs_modulus,
            poisson_ratio,
            friction_angle,
            dilation_angle,
            cohesion,
            tension_cutoff,
            critical_jacobian: None,
            stable_jacobian: f64::INFINITY,
            elastic: LinearElastic::new(density, youngs_modulus, poisson_ratio),
            lambda,
            mu,
            k,
            two_c_sqrt_k,
            apex,
            has_apex,
            edge_origin,
            sigma_t,
            sigma_t_scale,
            cutoff,
            r_p,
            r_l1,
            r_l2,
            n_l1,
            n_l2,
            elastic_margin: 1e-9 * (1.0 + k.abs()),
        }
    }

    /// Switches the disconnected state on above J = `critical_jacobian` (φ0/φ_c, module doc)
    /// or off (`None`).
    pub fn with_disconnection(mut self, critical_jacobian: Option<f64>) -> Self {
        self.critical_jacobian = critical_jacobian;
        self
    }

    /// Scales the elastic moduli by `stable_jacobian / J` above J = `stable_jacobian` (module
    /// doc, "Dilute material and the time step"); ∞ = never.
    pub fn with_stable_jacobian(mut self, stable_jacobian: f64) -> Self {
        self.stable_jacobian = stable_jacobian;
        self
    }

    /// Factor s ≤ 1 on the elastic moduli of a particle of J = det F: 1 up to
    /// `stable_jacobian`, `stable_jacobian / J` above (module doc).
    #[inline(always)]
    pub fn stiffness_scale(&self, jacobian: f64) -> f64 {
        if jacobian > self.stable_jacobian {
            self.stable_jacobian / jacobian
        } else {
            1.0
        }
    }

    /// From a material table: the elastic keys, `friction_angle` (required; 0 = Tresca, then
    /// `cohesion` > 0), `dilation_angle`, `cohesion`, `tension_cutoff` (default 0; none for
    /// Tresca) and `critical_packing_fraction` (with `grain_density`).
    pub fn from_parameters(p: &Parameters) -> Result<Self, String> {
        let phi = p.optional_f64("friction_angle")?.ok_or_else(|| p.error("friction_angle", "is required for mohr_coulomb"))?;
        if !(phi >= 0.0 && phi < 90.0) {
            return Err(p.error("friction_angle", format!("must be in [0, 90) degrees for mohr_coulomb (got {phi})")));
        }
        let psi = p.f64_or("dilation_angle", 0.0)?;
        if !(psi >= 0.0 && psi <= phi) {
            return Err(p.error(
                "dilation_angle",
                format!("must be in [0, friction_angle] = [0, {phi}] degrees for mohr_coulomb (got {psi})"),
            ));
        }
        let coh = p.f64_or("cohesion", 0.0)?;
        if !(coh >= 0.0 && coh.is_finite()) {
            return Err(p.error("cohesion", format!("must be >= 0 for mohr_coulomb (got {coh})")));
        }
        if phi == 0.0 && !(coh > 0.0) {
            return Err(p.error(
                "friction_angle",
                format!("= 0 (Tresca) needs cohesion > 0 for mohr_coulomb (got cohesion = {coh})"),
            ));
        }
        // Tresca (undrained, total stress): no cut-off unless one is given (module doc).
        let given = p.optional_f64("tension_cutoff")?;
        let st = given.unwrap_or(if phi == 0.0 { f64::INFINITY } else { 0.0 });
        if !(st >= 0.0 && (st.is_finite() || given.is_none())) {
            return Err(p.error("tension_cutoff", format!("must be >= 0 for mohr_coulomb (got {st})")));
        }
        let youngs_modulus = p.f64("youngs_modulus")?;
        if !(youngs_modulus > 0.0 && youngs_modulus.is_finite()) {
            return Err(p.error("youngs_modulus", format!("must be > 0 for mohr_coulomb (got {youngs_modulus})")));
        }
        let poisson_ratio = p.f64("poisson_ratio")?;
        if !(poisson_ratio > -1.0 && poisson_ratio < 0.5) {
            return Err(p.error("poisson_ratio", format!("must be in (-1, 0.5) for mohr_coulomb (got {poisson_ratio})")));
        }
        let density = p.f64("density")?;
        if !(density > 0.0 && density.is_finite()) {
            return Err(p.error("density", format!("must be > 0 for mohr_coulomb (got {density})")));
        }
        let critical_jacobian = p.critical_jacobian(density)?;
        Ok(Self::new(density, youngs_modulus, poisson_ratio, phi, psi, coh, st).with_disconnection(critical_jacobian))
    }

    /// Index of `plastic_work` in this model's state (the last slot).
    #[inline(always)]
    pub fn plastic_work_slot(&self) -> usize {
        if self.critical_jacobian.is_some() {
            3
        } else {
            2
        }
    }

    /// Elastic trial stress σ + C : Δε + the Jaumann rotation `rot`, and the factor s on the
    /// moduli (dilute material: moduli s C, module doc "Dilute material and the time step").
    #[inline(always)]
    fn trial_stress(&self, stress: &Stress, de: &[f64; 4], rot: &Stress, jacobian: f64) -> (Stress, f64) {
        let scale = self.stiffness_scale(jacobian);
        let inc = if scale < 1.0 {
            self.elastic.elastic_increment(&[de[0] * scale, de[1] * scale, de[2] * scale, de[3] * scale])
        } else {
            self.elastic.elastic_increment(de)
        };
        let mut tr = *stress;
        for c in 0..4 {
            tr[c] += inc[c] + rot[c];
        }
        (tr, scale)
    }

    /// Fast elastic test (most particles, most steps): the test of [`Self::return_trial`] but
    /// with the in-plane radius from `sqrt` instead of `hypot` (a libm call) and a margin
    /// 1e-9 (1 + k)·scale, far larger than the few ulps by which the two evaluations of f and
    /// σ1 can differ, and than the tolerance of `return_principal`. A trial stress that passes
    /// is therefore also elastic for the exact test, which returns it unchanged: skipping that
    /// test gives the same result bit for bit. Anything else (near the surface, NaN,
    /// overflow) answers `false` and takes the exact path.
    #[inline(always)]
    fn clearly_elastic(&self, tr: &Stress) -> bool {
        let centre = 0.5 * (tr[0] + tr[1]);
        let half = 0.5 * (tr[0] - tr[1]);
        let r = (half * half + tr[3] * tr[3]).sqrt();
        // Plain comparisons instead of f64::max/min (no NaN handling needed: a NaN anywhere
        // makes `scale`, hence the margin, NaN, and the test false).
        let (a, b) = (centre + r, centre - r);
        let s1 = if a > tr[2] { a } else { tr[2] };
        let s3 = if b < tr[2] { b } else { tr[2] };
        let scale = centre.abs() + r + tr[2].abs() + self.two_c_sqrt_k + self.sigma_t_scale;
        // The absolute term covers the underflow of `half * half` for tiny stresses.
        let margin = self.elastic_margin * scale + 1e-140;
        self.yield_function(&[s1, 0.0, s3]) < -margin && (!self.cutoff || s1 < self.sigma_t - margin)
    }

    /// Re-connection (module doc, "Disconnected material", rule 2): the compaction done while J
    /// was still above J_c is taken out of `de` ([`super::take_out_disconnected_compaction`])
    /// and booked as plastic compaction.
    #[inline(always)]
    fn reconnect(de: &mut [f64; 4], state: &mut [f64], jacobian: f64, critical_jacobian: f64) {
        let closed = super::take_out_disconnected_compaction(de, jacobian, critical_jacobian);
        if closed > 0.0 {
            if let Some(vol) = state.get_mut(1) {
                *vol -= closed;
            }
        }
    }

    /// Disconnected material (module doc, rule 1): σ = 0; the trial `tr` is all plastic,
    /// Δε^p = C σ_B, and max(0, J ½ σ_n : Δε^p) (per unit reference volume; `start` = σ_n with
    /// the step's rotation) is booked as dissipation in `disconnection_work` and `plastic_work`.
    #[inline(always)]
    fn disconnect(&self, stress: &mut Stress, state: &mut [f64], tr: Stress, start: Stress, jacobian: f64, scale: f64) {
        *stress = [0.0; 4];
        if state.len() > self.plastic_work_slot() {
            let nu = self.poisson_ratio;
            // The compliance of the moduli in use, s C (module doc, "Dilute material").
            let e = self.youngs_modulus * scale;
            let s = nu * (tr[0] + tr[1] + tr[2]);
            let ep = [((1.0 + nu) * tr[0] - s) / e, ((1.0 + nu) * tr[1] - s) / e, ((1.0 + nu) * tr[2] - s) / e];
            // Tensor shear strain ε12 = σ12 / (2G) = (1 + ν) σ12 / E.
            let ep12 = (1.0 + nu) * tr[3] / e;
            let vol = ep[0] + ep[1] + ep[2];
            let m = vol / 3.0;
            let (e0, e1, e2) = (ep[0] - m, ep[1] - m, ep[2] - m);
            state[0] += (2.0 / 3.0 * (e0 * e0 + e1 * e1 + e2 * e2 + 2.0 * ep12 * ep12)).sqrt();
            state[1] += vol;
            let power = start[0] * ep[0] + start[1] * ep[1] + start[2] * ep[2] + 2.0 * start[3] * ep12;
            let discarded = (0.5 * jacobian * power).max(0.0);
            state[DISCONNECTION_WORK] += discarded;
            state[self.plastic_work_slot()] += discarded;
        }
    }

    /// Return mapping of the trial stress `tr` in principal space (the exact path).
    /// `jacobian` = J = V/V0 of the particle (scales the plastic work to reference volume).
    ///
    /// The last state slot, `plastic_work` (when the slice holds it), accumulates
    /// J σ_C : Δε^p, σ_C the returned stress and Δε^p = C⁻¹(σ_B − σ_C) the plastic strain
    /// increment: the plastic (frictional) dissipation in J per m³ of reference volume, ≥ 0
    /// for ψ ≤ φ and c ≥ 0 (zero at the apex of c = 0, where σ_C = 0). It is booked only and
    /// never feeds back into the stress update (it closes the run's energy budget).
    ///
    /// `scale` = s of [`Self::stiffness_scale`]: the trial was built with the moduli s C⁻¹, so
    /// the plastic strain is (s C⁻¹)⁻¹ (σ_B − σ_C) = C (σ_B − σ_C)/s. The return itself does
    /// not depend on s (its directions are ratios of the moduli).
    fn return_trial(&self, stress: &mut Stress, state: &mut [f64], tr: Stress, jacobian: f64, scale: f64) {
        // In-plane principal values a ≥ b and their axes; σ33 is principal.
        let centre = 0.5 * (tr[0] + tr[1]);
        let half = 0.5 * (tr[0] - tr[1]);
        let radius = half.hypot(tr[3]);
        let (cos2, sin2) = if radius > 0.0 { (half / radius, tr[3] / radius) } else { (1.0, 0.0) };
        let vals = [centre + radius, centre - radius, tr[2]];
        // order[i] = which of (a, b, 33) is σ_{i+1}.
        let order: [usize; 3] = if vals[2] > vals[0] {
            [2, 0, 1]
        } else if vals[2] >= vals[1] {
            [0, 2, 1]
        } else {
            [0, 1, 2]
        };
        let sorted = [vals[order[0]], vals[order[1]], vals[order[2]]];

        let (ret, region) = self.return_principal(&sorted);
        if region == ReturnRegion::Elastic {
            *stress = tr;
            return;
        }

        let mut new_vals = [0.0; 3];
        for i in 0..3 {
            new_vals[order[i]] = ret[i];
        }
        let c2 = 0.5 * (new_vals[0] + new_vals[1]);
        let r2 = 0.5 * (new_vals[0] - new_vals[1]);
        *stress = [c2 + r2 * cos2, c2 - r2 * cos2, new_vals[2], r2 * sin2];

        if state.len() >= 2 {
            let mut ep = self.plastic_strain(&sorted, &ret);
            if scale < 1.0 {
                ep = [ep[0] / scale, ep[1] / scale, ep[2] / scale];
            }
            let vol = ep[0] + ep[1] + ep[2];
            let m = vol / 3.0;
            let (e0, e1, e2) = (ep[0] - m, ep[1] - m, ep[2] - m);
            state[0] += (2.0 / 3.0 * (e0 * e0 + e1 * e1 + e2 * e2)).sqrt();
            state[1] += vol;
            if let Some(work) = state.get_mut(self.plastic_work_slot()) {
                *work += jacobian * dot(&ret, &ep);
            }
        }
    }
}

/// The registry's builder ([`super::MODELS`]).
pub fn build(p: &Parameters) -> Result<Box<dyn Material>, String> {
    Ok(Box::new(MohrCoulomb::from_parameters(p)?))
}

impl Material for MohrCoulomb {
    fn model(&self) -> &'static str {
        "mohr_coulomb"
    }
    fn density(&self) -> f64 {
        self.density
    }
    fn elastic_energy_density(&self, stress: &Stress) -> f64 {
        super::complementary_energy(stress, self.youngs_modulus, self.poisson_ratio)
    }
    fn wave_speed(&self) -> f64 {
        p_wave_speed(self.youngs_modulus, self.poisson_ratio, self.density)
    }
    fn state_names(&self) -> &'static [&'static str] {
        if self.critical_jacobian.is_some() {
            &STATE_NAMES_DISCONNECTION
        } else {
            &STATE_NAMES_PLAIN
        }
    }

    // Inlined into the trait's `update_stress_batch` and its AVX2 copy (solver::isa).
    #[inline(always)]
    fn update_stress(&self, stress: &mut Stress, state: &mut [f64], k: &Kinematics) {
        // Hypoelastic Jaumann trial, identical (bit for bit) to LinearElastic.
        let (d, spin) = rate_of_deformation(&k.velocity_gradient);
        let mut de = [d[0] * k.dt, d[1] * k.dt, d[2] * k.dt, d[3] * k.dt];
        let mut disconnected = false;
        if let Some(jc) = self.critical_jacobian {
            if k.jacobian > jc {
                disconnected = true;
            } else {
                Self::reconnect(&mut de, state, k.jacobian, jc);
            }
        }
        let rot = jaumann_rotation(stress, spin, k.dt);
        let (tr, scale) = self.trial_stress(stress, &de, &rot, k.jacobian);
        if disconnected {
            let mut start = *stress;
            for c in 0..4 {
                start[c] += rot[c];
            }
            self.disconnect(stress, state, tr, start, k.jacobian, scale);
            return;
        }

        if self.clearly_elastic(&tr) {
            *stress = tr;
            return;
        }
        self.return_trial(stress, state, tr, k.jacobian, scale);
    }

    /// The plain model (no disconnected state) in two passes over the run:
    /// first every particle's elastic trial and the fast elastic test ([`Self::clearly_elastic`]),
    /// in one branch-free loop that the compiler vectorises across particles; then the
    /// particles that are not clearly elastic are returned ([`Self::return_trial`]). Each
    /// particle's operations are those of [`Material::update_stress`], in the same order (same
    /// result bit for bit); the other variants, and runs longer than a batch, take that path.
    #[inline(always)]
    fn update_stress_batch(
        &self,
        stress: &mut [Stress],
        state: &mut [f64],
        stride: usize,
        state_length: usize,
        kinematics: &[Kinematics],
    ) {
        // The solver's update pass hands runs of at most its batch of 32 particles
        // (`solver::particle_update`); the trial stresses of a run stay on the stack.
        const BATCH: usize = 32;
        let n = stress.len();
        if self.critical_jacobian.is_some() || n > BATCH || kinematics.len() != n {
            return super::update_each(self, stress, state, stride, state_length, kinematics);
        }
        let mut trial = [[0.0; 4]; BATCH];
        let mut elastic = [false; BATCH];
        for ((s, k), (tr, clear)) in stress.iter().zip(kinematics).zip(trial.iter_mut().zip(elastic.iter_mut())) {
            let (d, spin) = rate_of_deformation(&k.velocity_gradient);
            let de = [d[0] * k.dt, d[1] * k.dt, d[2] * k.dt, d[3] * k.dt];
            let rot = jaumann_rotation(s, spin, k.dt);
            *tr = self.trial_stress(s, &de, &rot, k.jacobian).0;
            *clear = self.clearly_elastic(tr);
        }
        for (((s, k), slots), (tr, clear)) in
            stress.iter_mut().zip(kinematics).zip(state.chunks_exact_mut(stride)).zip(trial.iter().zip(&elastic))
        {
            if *clear {
                *s = *tr;
            } else {
                let scale = self.stiffness_scale(k.jacobian);
                self.return_trial(s, &mut slots[..state_length], *tr, k.jacobian, scale);
            }
        }
    }

    fn limit_wave_speed(&mut self, max_wave_speed: f64) {
        self.stable_jacobian = super::stable_jacobian(max_wave_speed, self.wave_speed());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::testing::{
        elastic_compliance, elastic_stiffness, kinematics, principal_stresses, Lcg,
    };

    pub(super) const E: f64 = 50e6;
    pub(super) const NU: f64 = 0.3;

    pub(super) fn mc(phi: f64, psi: f64, c: f64, st: f64) -> MohrCoulomb {
        MohrCoulomb::new(2000.0, E, NU, phi, psi, c, st)
    }

    pub(super) fn kin(l: [f64; 5], dt: f64) -> Kinematics {
        kinematics(l, dt)
    }

    pub(super) fn stiff(v: [f64; 3]) -> [f64; 3] {
        elastic_stiffness(E, NU, v)
    }

    pub(super) fn comply(v: [f64; 3]) -> [f64; 3] {
        elastic_compliance(E, NU, v)
    }

    pub(super) fn kk(phi: f64) -> f64 {
        let s = phi.to_radians().sin();
        (1.0 + s) / (1.0 - s)
    }

    /// Flow directions of the planes meeting in the sorted sector: main MC plane, its mirrors
    /// across σ1 = σ2 and σ2 = σ3, and the three cut-off planes.
    pub(super) fn flows(psi: f64) -> [[f64; 3]; 6] {
        let m = kk(psi);
        [[m, 0.0, -1.0], [0.0, m, -1.0], [m, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    }

    /// Largest constraint value over all six Mohr–Coulomb planes and the three cut-off planes.
    pub(super) fn worst(m: &MohrCoulomb, s: &[f64; 3]) -> f64 {
        let (k, b) = (m.k, m.two_c_sqrt_k);
        let mut w = f64::NEG_INFINITY;
        for i in 0..3 {
            for j in 0..3 {
                if i != j {
                    w = w.max(k * s[i] - s[j] - b);
                }
            }
            if m.cutoff {
                w = w.max(s[i] - m.sigma_t);
            }
        }
        w
    }

    pub(super) fn scale(s: &[f64; 3], m: &MohrCoulomb) -> f64 {
        s[0].abs() + s[1].abs() + s[2].abs() + m.two_c_sqrt_k + 1.0
    }

    pub(super) fn flow_rule_holds(trial: &[f64; 3], ret: &[f64; 3], g: &[[f64; 3]]) -> bool {
        super::super::testing::flow_rule_holds(comply, trial, ret, g)
    }

    pub(super) fn active_flows(region: ReturnRegion, psi: f64) -> Vec<[f64; 3]> {
        let f = flows(psi);
        use ReturnRegion::*;
        match region {
            Elastic => vec![],
            Plane => vec![f[0]],
            EdgeCompression => vec![f[0], f[1]],
            EdgeExtension => vec![f[0], f[2]],
            // All six Mohr–Coulomb planes meet at the apex.
            Apex => {
                let m = kk(psi);
                vec![f[0], f[1], f[2], [-1.0, m, 0.0], [-1.0, 0.0, m], [0.0, -1.0, m]]
            }
            TensionPlane => vec![f[3]],
            TensionEdge => vec![f[3], f[4]],
            TensionCorner => vec![f[3], f[4], f[5]],
            TensionShearEdge => vec![f[0], f[3]],
            TensionShearCornerCompression => vec![f[0], f[1], f[3], f[4]],
            TensionShearCornerExtension => vec![f[0], f[2], f[3]],
        }
    }

    pub(super) fn add_flow(s: [f64; 3], terms: &[(f64, [f64; 3])]) -> [f64; 3] {
        let mut out = s;
        for &(l, g) in terms {
            let d = stiff(g);
            for c in 0..3 {
                out[c] += l * d[c];
            }
        }
        out
    }

    /// Test 1: drained triaxial compression at constant lateral stress (axisymmetric kinematics:
    /// [rr, zz, θθ, rz], L = [ε̇_r, 0, 0, ε̇_z, ε̇_θ] with ε̇_θ = ε̇_r); the lateral strain rate is
    /// solved each step so that σ_rr = σ_θθ = −p.
    #[test]
    fn triaxial_compression_fails_at_closed_form_strength() {
        for &(phi, psi, c) in &[(30.0, 0.0, 0.0), (35.0, 10.0, 0.0), (25.0, 0.0, 15e3), (30.0, 30.0, 8e3)] {
            let m = mc(phi, psi, c, 0.0);
            let sphi = f64::to_radians(phi).sin();
            let cphi = f64::to_radians(phi).cos();
            let mk = kk(psi);
            for &p in &[20e3, 100e3, 400e3] {
                let qf = 2.0 * (c * cphi + p * sphi) / (1.0 - sphi);
                let mut s = [-p, -p, -p, 0.0];
                let mut st = [0.0, 0.0];
                let dt = 1.0;
                let dez = -2e-5;
                let mut peak: f64 = 0.0;
                let mut yielded_at = None;
                for step in 0..2000 {
                    let run = |er: f64| {
                        let mut s2 = s;
                        let mut st2 = st;
                        m.update_stress(&mut s2, &mut st2, &kin([er, 0.0, 0.0, dez, er], dt));
                        (s2, st2)
                    };
                    // Secant iteration on the lateral strain rate (piecewise linear response).
                    let (mut x0, mut x1) = (0.0, -NU * dez);
                    let mut g0 = run(x0).0[0] + p;
                    for _ in 0..60 {
                        let g1 = run(x1).0[0] + p;
                        if g1.abs() < 1e-11 * p || g1 == g0 {
                            break;
                        }
                        let x2 = x1 - g1 * (x1 - x0) / (g1 - g0);
                        x0 = x1;
                        g0 = g1;
                        x1 = x2;
                    }
                    let (s2, st2) = run(x1);
                    s = s2;
                    st = st2;
                    assert!((s[0] + p).abs() < 1e-9 * p && (s[2] + p).abs() < 1e-9 * p, "lateral control {s:?}");
                    let q = -s[1] - p;
                    peak = peak.max(q);
                    assert!(q <= qf * (1.0 + 1e-9), "q = {q} exceeds q_f = {qf} (phi {phi}, c {c}, p {p})");
                    if yielded_at.is_none() && st[0] > 0.0 {
                        yielded_at = Some(step);
                    }
                }
                let y = yielded_at.expect("never yielded");
                // Elastic until failure: q grows by (E dε_z) per step, so it yields at q_f.
                assert!((y as f64 - qf / (E * 2e-5)).abs() <= 1.0, "yield step {y}");
                let q = -s[1] - p;
                assert!((q - qf).abs() <= 1e-9 * qf, "final q {q} vs {qf}");
                assert!((peak - qf).abs() <= 1e-9 * qf);
                if c == 0.0 {
                    let ratio = s[1] / s[0];
                    assert!((ratio - (1.0 + sphi) / (1.0 - sphi)).abs() < 1e-9, "σ3/σ1 = {ratio}");
                }
                // Dilatancy on the compression edge: Δε_v^p / Δε̄^p = 3(m − 1)/(m + 2).
                assert!(st[0] > 1e-3, "plastic shear strain {st:?}");
                let expect = 3.0 * (mk - 1.0) / (mk + 2.0);
                assert!((st[1] / st[0] - expect).abs() < 1e-9, "dilatancy {} vs {expect}", st[1] / st[0]);
            }
        }
    }

    fn compliance4(d: &Stress) -> [f64; 4] {
        let tr = d[0] + d[1] + d[2];
        let g = E / (2.0 * (1.0 + NU));
        [
            ((1.0 + NU) * d[0] - NU * tr) / E,
            ((1.0 + NU) * d[1] - NU * tr) / E,
            ((1.0 + NU) * d[2] - NU * tr) / E,
            d[3] / (2.0 * g),
        ]
    }

    fn trial_of(s: &Stress, k: &Kinematics) -> Stress {
        let mut t = *s;
        LinearElastic::new(2000.0, E, NU).update_stress(&mut t, &mut [], k);
        t
    }

    /// Test 3: ψ = 0 returns from the plane region are isochoric: tr(C (σ_trial − σ)) = 0.
    #[test]
    fn zero_dilation_plane_return_has_no_plastic_volume_change() {
        let m = mc(35.0, 0.0, 5e3, 0.0);
        let mut count = 0;
        for &(s0, l) in &[
            ([-100e3, -60e3, -80e3, 20e3], [-1e-3, 4e-3, 1e-3, 2e-3, 0.0]),
            ([-50e3, -200e3, -120e3, -30e3], [2e-3, 0.0, -3e-3, -1e-3, 5e-4]),
            ([-80e3, -80e3, -300e3, 0.0], [0.0, 3e-3, 3e-3, 0.0, -2e-3]),
        ] {
            let k = kin(l, 1.0);
            let trial = trial_of(&s0, &k);
            let (_, region) = m.return_principal(&principal_stresses(&trial));
            assert_eq!(region, ReturnRegion::Plane, "{trial:?}");
            let mut s = s0;
            let mut state = [0.0, 0.0];
            m.update_stress(&mut s, &mut state, &k);
            let d = [trial[0] - s[0], trial[1] - s[1], trial[2] - s[2], trial[3] - s[3]];
            let ep = compliance4(&d);
            let norm = ep.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!(norm > 1e-5, "not plastic: {ep:?}");
            assert!((ep[0] + ep[1] + ep[2]).abs() <= 1e-12 * norm, "tr = {}", ep[0] + ep[1] + ep[2]);
            assert!(state[1].abs() <= 1e-12 * state[0] && state[0] > 0.0, "{state:?}");
            count += 1;
        }
        assert_eq!(count, 3);
    }

    /// Test 4: rigid spin of a stress on the yield surface leaves its invariants unchanged (the
    /// in-plane axes rotate, the stress stays on the surface).
    #[test]
    fn rigid_rotation_keeps_invariants_on_the_yield_surface() {
        for &(phi, psi, c) in &[(30.0, 0.0, 10e3), (35.0, 35.0, 0.0)] {
            let m = mc(phi, psi, c, 0.0);
            let k = kk(phi);
            let b = 2.0 * c * k.sqrt();
            // Principal (σ1, σ2, σ3) with σ1, σ3 in plane at 25° and σ2 out of plane.
            let (s1, s2) = (-60e3, -90e3);
            let s3 = k * s1 - b;
            let th = 25f64.to_radians();
            let (cc, ss) = (th.cos(), th.sin());
            let mut s = [s1 * cc * cc + s3 * ss * ss, s1 * ss * ss + s3 * cc * cc, s2, (s1 - s3) * cc * ss];
            let inv = |s: &Stress| {
                let p = (s[0] + s[1] + s[2]) / 3.0;
                let j2 = 0.5 * ((s[0] - p).powi(2) + (s[1] - p).powi(2) + (s[2] - p).powi(2)) + s[3] * s[3];
                (p, j2)
            };
            let (p0, j0) = inv(&s);
            let s_start = s;
            let mut state = [0.0, 0.0];
            let steps = 20000;
            let omega = std::f64::consts::FRAC_PI_2;
            for _ in 0..steps {
                m.update_stress(&mut s, &mut state, &kin([0.0, -omega, omega, 0.0, 0.0], 1.0 / steps as f64));
                let pr = principal_stresses(&s);
                assert!(m.yield_function(&pr) <= 1e-9 * s3.abs());
            }
            let (p1, j1) = inv(&s);
            assert!((p1 - p0).abs() <= 1e-3 * p0.abs(), "p {p0} -> {p1}");
            assert!((j1 - j0).abs() <= 1e-3 * j0, "J2 {j0} -> {j1}");
            assert!((s[2] - s2).abs() <= 1e-3 * s2.abs());
            let pr = principal_stresses(&s);
            assert!(m.yield_function(&pr).abs() <= 1e-3 * s3.abs(), "left the surface: {pr:?}");
            // A quarter turn swaps the normal components and flips the shear.
            assert!(
                (s[0] - s_start[1]).abs() < 1e-3 * s3.abs() && (s[1] - s_start[0]).abs() < 1e-3 * s3.abs(),
                "{s:?}"
            );
            assert!((s[3] + s_start[3]).abs() < 1e-3 * s3.abs());
        }
    }

    /// The fast elastic exit never changes a result: for trial stresses spread across the
    /// yield surface (both sides, near the apex, the cut-off and tiny magnitudes) the full
    /// update equals the exact return mapping alone, bit for bit, state included.
    #[test]
    fn fast_elastic_exit_equals_the_exact_path_bit_for_bit() {
        let mut rng = Lcg(7);
        let mut fast = 0;
        for m in [mc(30.0, 0.0, 10e3, 0.0), mc(25.0, 0.0, 0.0, 0.0), mc(40.0, 10.0, 5e3, 2e3), mc(0.0, 0.0, 20e3, 1e3)] {
            for i in 0..20000 {
                let mag = [1.0, 1e3, 1e5, 1e-200][i % 4];
                let tr: Stress = [0u8; 4].map(|_| mag * (2.0 * rng.next() - 1.5));
                let mut state_a = [0.1, 0.2];
                let mut state_b = state_a;
                let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
                if m.clearly_elastic(&tr) {
                    a = tr;
                    fast += 1;
                } else {
                    m.return_trial(&mut a, &mut state_a, tr, 1.0, 1.0);
                }
                m.return_trial(&mut b, &mut state_b, tr, 1.0, 1.0);
                assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "{tr:?}");
                assert_eq!(state_a.map(f64::to_bits), state_b.map(f64::to_bits));
            }
        }
        assert!(fast > 10000, "the fast exit was taken only {fast} times");
    }

    /// Test 5: steps that stay inside the surface equal the linear elastic update bit for bit.
    #[test]
    fn elastic_steps_match_linear_elastic_bit_for_bit() {
        let m = mc(30.0, 0.0, 10e3, 0.0);
        let le = LinearElastic::new(2000.0, E, NU);
        let mut rng = Lcg(99);
        let mut n = 0;
        for _ in 0..2000 {
            let s0 = [
                -100e3 + 20e3 * rng.next(),
                -100e3 + 20e3 * rng.next(),
                -100e3 + 20e3 * rng.next(),
                10e3 * (rng.next() - 0.5),
            ];
            let l = [0u8; 5].map(|_| 2e-4 * (rng.next() - 0.5));
            let k = kin(l, 0.7);
            let mut a = s0;
            let mut b = s0;
            let mut state = [0.25, -0.5, 0.0];
            m.update_stress(&mut a, &mut state, &k);
            le.update_stress(&mut b, &mut [], &k);
            assert!(m.yield_function(&principal_stresses(&a)) < 0.0);
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
            assert_eq!(state, [0.25, -0.5, 0.0]);
            n += 1;
        }
        assert_eq!(n, 2000);
    }

    /// Test 6: with ψ = φ the plastic strain increment C (σ_trial − σ) of a plane return is
    /// parallel to ∂f/∂σ = k n1⊗n1 − n3⊗n3 (n_i the principal axes of the returned stress),
    /// and edge returns lie in the cone of the two gradients.
    #[test]
    fn associated_plastic_strain_is_normal_to_the_yield_surface() {
        let m = mc(30.0, 30.0, 10e3, 0.0);
        let k = m.k;
        let mut rng = Lcg(4242);
        let mut planes = 0;
        for _ in 0..3000 {
            let s0 = [-150e3 * rng.next(), -150e3 * rng.next(), -150e3 * rng.next(), 60e3 * (rng.next() - 0.5)];
            let l = [0u8; 5].map(|_| 6e-3 * (rng.next() - 0.5));
            let kn = kin(l, 1.0);
            let trial = trial_of(&s0, &kn);
            let (_, region) = m.return_principal(&principal_stresses(&trial));
            if region != ReturnRegion::Plane {
                continue;
            }
            let mut s = s0;
            m.update_stress(&mut s, &mut [0.0, 0.0], &kn);
            let ep = compliance4(&[trial[0] - s[0], trial[1] - s[1], trial[2] - s[2], trial[3] - s[3]]);
            // Gradient from the eigenvectors of the returned stress.
            let c = 0.5 * (s[0] + s[1]);
            let r = (0.5 * (s[0] - s[1])).hypot(s[3]);
            let th = 0.5 * s[3].atan2(0.5 * (s[0] - s[1]));
            let (va, vb) = ([th.cos(), th.sin()], [-th.sin(), th.cos()]);
            let outer = |v: [f64; 2]| [v[0] * v[0], v[1] * v[1], 0.0, v[0] * v[1]];
            let mut entries = [(c + r, outer(va)), (c - r, outer(vb)), (s[2], [0.0, 0.0, 1.0, 0.0])];
            entries.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap());
            let n1 = entries[0].1;
            let n3 = entries[2].1;
            let grad = [0, 1, 2, 3].map(|i| k * n1[i] - n3[i]);
            // Tensor inner product (shear counted twice).
            let ip = |a: &[f64; 4], b: &[f64; 4]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * a[3] * b[3];
            let cos = ip(&ep, &grad) / (ip(&ep, &ep) * ip(&grad, &grad)).sqrt();
            assert!(cos > 1.0 - 1e-10, "cos = {cos}, {ep:?} vs {grad:?}");
            planes += 1;
        }
        assert!(planes > 100, "only {planes} plane returns");
        // Edges: principal-space cone test.
        let f = flows(30.0);
        for (trial, want) in [
            (
                add_flow([-50e3, -50e3, k * -50e3 - m.two_c_sqrt_k], &[(1e-3, f[0]), (3e-4, f[1])]),
                ReturnRegion::EdgeCompression,
            ),
            (
                add_flow(
                    [-50e3, k * -50e3 - m.two_c_sqrt_k, k * -50e3 - m.two_c_sqrt_k],
                    &[(2e-4, f[0]), (1e-3, f[2])],
                ),
                ReturnRegion::EdgeExtension,
            ),
        ] {
            let (ret, region) = m.return_principal(&trial);
            assert_eq!(region, want);
            assert!(flow_rule_holds(&trial, &ret, &active_flows(region, 30.0)));
            // And not along the main plane's normal alone.
            assert!(!flow_rule_holds(&trial, &ret, &[f[0]]));
        }
    }

    /// Full 2D/axisymmetric updates: σ33 in every sorting position, the returned stress is coaxial
    /// with the trial, on the surface, and cohesionless tension goes to exactly zero.
    #[test]
    fn full_update_is_coaxial_and_lands_on_the_surface() {
        let mut rng = Lcg(31337);
        for &(phi, psi, c, st) in &[(30.0, 0.0, 0.0, 0.0), (35.0, 10.0, 15e3, 5e3)] {
            let m = mc(phi, psi, c, st);
            for _ in 0..20000 {
                let s0 =
                    [0, 1, 2, 3].map(|i| if i == 3 { 80e3 * (rng.next() - 0.5) } else { -200e3 * rng.next() + 20e3 });
                let l = [0u8; 5].map(|_| 1e-2 * (rng.next() - 0.5));
                let kn = kin(l, 1.0);
                let trial = trial_of(&s0, &kn);
                let mut s = s0;
                m.update_stress(&mut s, &mut [0.0, 0.0], &kn);
                let pt = principal_stresses(&trial);
                let ps = principal_stresses(&s);
                let (want, _) = m.return_principal(&pt);
                let sc = scale(&pt, &m);
                for i in 0..3 {
                    assert!((ps[i] - want[i]).abs() <= 1e-9 * sc, "{trial:?} -> {s:?}: {ps:?} vs {want:?}");
                }
                assert!(worst(&m, &ps) <= 1e-9 * sc);
                // Coaxial: in-plane commutator of trial and returned stress vanishes.
                let comm = trial[3] * (s[0] - s[1]) - s[3] * (trial[0] - trial[1]);
                assert!(comm.abs() <= 1e-9 * sc * sc, "not coaxial: {comm}");
            }
        }
        // Cohesionless, pure tension: back to exactly zero, for all σ33 positions.
        let m = mc(30.0, 0.0, 0.0, 0.0);
        for s0 in [[10e3, 5e3, 1e3, 2e3], [1e3, 5e3, 10e3, -2e3], [-1e3, 20e3, 3e3, 0.0]] {
            let mut s = s0;
            let mut state = [0.0, 0.0];
            m.update_stress(&mut s, &mut state, &kin([0.0; 5], 1.0));
            assert_eq!(s, [0.0; 4], "{s0:?}");
            assert!(state[1] > 0.0);
        }
    }

    #[test]
    fn config_is_validated_with_key_names() {
        use crate::config::MaterialConfig;
        let mut base = MaterialConfig::elastic("mohr_coulomb", 1550.0, 1e6, 0.3);
        base.set("friction_angle", 30.0);
        let from = |c: &MaterialConfig| {
            let table = c.parameters.clone();
            MohrCoulomb::from_parameters(&Parameters::new("sand", &table))
        };
        let m = from(&base).unwrap();
        assert_eq!(m.model(), "mohr_coulomb");
        let plain = ["plastic_shear_strain", "plastic_volumetric_strain", "plastic_work"];
        assert_eq!(m.state_names(), &plain[..]);
        assert_eq!(m.state_names()[m.plastic_work_slot()], "plastic_work");
        assert_eq!(super::super::build("sand", &base).unwrap().state_names(), &plain[..]);
        assert_eq!((m.dilation_angle, m.cohesion, m.tension_cutoff), (0.0, 0.0, 0.0));
        assert!((m.wave_speed() - p_wave_speed(1e6, 0.3, 1550.0)).abs() < 1e-12);
        assert!(super::super::build("sand", &base).is_ok());
        let err = |key: &str, value: serde_json::Value| {
            let mut c = base.clone();
            c.set(key, value);
            from(&c).err().unwrap()
        };
        assert_eq!(
            err("friction_angle", serde_json::Value::Null),
            "materials.sand.friction_angle: is required for mohr_coulomb"
        );
        for (key, value) in [
            ("friction_angle", 90.0),
            ("friction_angle", -1.0),
            ("dilation_angle", 31.0),
            ("dilation_angle", -1.0),
            ("cohesion", -1.0),
            ("tension_cutoff", -1.0),
            ("poisson_ratio", 0.5),
            ("youngs_modulus", 0.0),
            ("density", 0.0),
        ] {
            let e = err(key, value.into());
            assert!(e.starts_with(&format!("materials.sand.{key}: must be")), "{e}");
        }
        // φ = 0 is Tresca: needs c > 0, forces ψ = 0, and has no tension cut-off by default.
        assert_eq!(
            err("friction_angle", 0.0.into()),
            "materials.sand.friction_angle: = 0 (Tresca) needs cohesion > 0 for mohr_coulomb (got cohesion = 0)"
        );
        let mut tresca = base.clone();
        tresca.set("friction_angle", 0.0);
        tresca.set("cohesion", 10e3);
        let t = from(&tresca).unwrap();
        assert!(t.tension_cutoff == f64::INFINITY && !t.cutoff && !t.has_apex);
        let mut with_cut = tresca.clone();
        with_cut.set("tension_cutoff", 2e3);
        let t = from(&with_cut).unwrap();
        assert!(t.cutoff && t.sigma_t == 2e3);
        let mut dilating = tresca.clone();
        dilating.set("dilation_angle", 1.0);
        assert!(from(&dilating).err().unwrap().starts_with("materials.sand.dilation_angle: must be"));
    }

    // ------------------------------------------------------------------ histories

    fn bulk_modulus() -> f64 {
        E / (3.0 * (1.0 - 2.0 * NU))
    }

    /// (φ, ψ, c, σ_t): cohesionless with ψ = 0 and ψ > 0, cohesive with and without a cut-off.
    const MATERIALS: [(f64, f64, f64, f64); 4] =
        [(30.0, 0.0, 0.0, 0.0), (35.0, 10.0, 0.0, 0.0), (25.0, 0.0, 10e3, 2e3), (40.0, 20.0, 5e3, 0.0)];

    /// Random stretch / compress / shear histories (cohesionless and cohesive, with and
    /// without a cut-off), hashed bit for bit (stress and the first two states) after every step.
    fn trajectory_hash(build: &dyn Fn(f64, f64, f64, f64) -> MohrCoulomb) -> (u64, usize) {
        let mut h: u64 = 0xcbf29ce484222325;
        let mut mix = |x: u64| {
            h ^= x;
            h = h.wrapping_mul(0x100000001b3);
        };
        let mut rng = Lcg(2024);
        let mut yielded = 0;
        for &(phi, psi, c, st) in &MATERIALS {
            let m = build(phi, psi, c, st);
            for _ in 0..40 {
                let mut s = [-50e3 * rng.next(), -50e3 * rng.next(), -50e3 * rng.next(), 10e3 * (rng.next() - 0.5)];
                let mut state = vec![0.0; m.state_names().len()];
                for _ in 0..150 {
                    // Volumetric bias drifts between stretching and compression.
                    let bias = 2e-3 * (rng.next() - 0.45);
                    let l = [0u8; 5].map(|_| bias + 4e-3 * (rng.next() - 0.5));
                    m.update_stress(&mut s, &mut state, &kin(l, 1.0));
                    for x in s.iter().chain(state[..2].iter()) {
                        mix(x.to_bits());
                    }
                }
                yielded += (state[0] > 0.0) as usize;
            }
        }
        (h, yielded)
    }

    /// A default-off `critical_packing_fraction` (`with_disconnection(None)`) is plain
    /// Mohr–Coulomb bit for bit; switched on (J_c = 1 on these F = I histories, so every
    /// step whose J would exceed 1 disconnects) it changes the histories.
    #[test]
    fn disconnection_off_is_plain_mohr_coulomb_bit_for_bit() {
        let (plain, yielded) = trajectory_hash(&|a, b, c, d| mc(a, b, c, d));
        assert!(yielded > 100, "only {yielded} of 160 histories yielded");
        let (off, _) = trajectory_hash(&|a, b, c, d| mc(a, b, c, d).with_disconnection(None));
        assert_eq!(off, plain);
        // `kin` reports J = 1: with J_c just below 1 every step is disconnected.
        let (on, _) = trajectory_hash(&|a, b, c, d| mc(a, b, c, d).with_disconnection(Some(0.999)));
        assert_ne!(on, plain);
    }

    // ------------------------------------------------------------------ disconnection

    use crate::material::testing::MaterialPoint;

    fn disconnecting(phi: f64, c: f64, critical_jacobian: f64) -> MohrCoulomb {
        mc(phi, 0.0, c, 0.0).with_disconnection(Some(critical_jacobian))
    }

    fn jacobian_of(p: &MaterialPoint) -> f64 {
        let f = p.deformation_gradient;
        (f[0] * f[3] - f[1] * f[2]) * f[4]
    }

    /// Above J_c the stress is 0 whatever the step does: compressing (while J is still above
    /// J_c) and shearing builds no stress, for cohesionless and cohesive material; the plain
    /// model builds stress on the same history.
    #[test]
    fn disconnected_point_carries_no_stress() {
        let jc = 1.05;
        let r = 2e-4; // isotropic rate × dt per step
        let stretch = [r, 0.0, 0.0, r, r];
        let squeeze_and_shear = [-0.2 * r, 3.0 * r, 0.0, -0.2 * r, -0.2 * r];
        for c in [0.0, 20e3] {
            let m = disconnecting(30.0, c, jc);
            let plain = mc(30.0, 0.0, c, 0.0);
            let start = [-3e3, -5e3, -3e3, 500.0];
            let mut p = MaterialPoint::new(&m, start);
            let mut q = MaterialPoint::new(&plain, start);
            let mut steps = 0;
            while jacobian_of(&p) <= 1.1 {
                p.step(&m, stretch, 1.0);
                q.step(&plain, stretch, 1.0);
                steps += 1;
                assert!(steps < 10_000);
            }
            assert_eq!(p.stress, [0.0; 4], "c = {c}");
            for _ in 0..50 {
                p.step(&m, squeeze_and_shear, 1.0);
                q.step(&plain, squeeze_and_shear, 1.0);
                assert!(jacobian_of(&p) > jc);
                assert_eq!(p.stress, [0.0; 4], "c = {c}: disconnected but stressed at J = {}", jacobian_of(&p));
            }
            let loaded = principal_stresses(&q.stress);
            assert!(loaded[2] < -1.0, "c = {c}: the plain model should be loaded, {:?}", q.stress);
            assert!(p.state[0] > 0.0 && p.state[1] > 0.05, "plastic strains {:?}", p.state);
        }
    }

    /// Stretched from a confined state past J_c and compressed back: the stress stays 0 down
    /// to J_c (no rebound of the volume lost while disconnected) and only the compression
    /// beyond J_c is elastic, p = K ln(J_c/J); the plain model, compressed along the same
    /// history, holds ~K ln(J_max/J) instead. Stretching again from there, the point is
    /// stress-free again at J_c.
    #[test]
    fn recompaction_to_the_critical_packing_has_no_rebound() {
        let jc = 1.06;
        let r = 1e-4;
        let k = bulk_modulus();
        for (dev, c) in [(0.0, 0.0), (0.5, 0.0), (0.0, 5e3)] {
            let m = disconnecting(30.0, c, jc);
            let plain = mc(30.0, 0.0, c, 0.0);
            let stretch = [r, dev * r, 0.0, r, r];
            let compress = [-r, 0.0, dev * r, -r, -r];
            let start = [-2e3, -2e3, -2e3, 0.0];
            let mut p = MaterialPoint::new(&m, start);
            let mut q = MaterialPoint::new(&plain, start);
            while jacobian_of(&p) < 1.25 {
                p.step(&m, stretch, 1.0);
                q.step(&plain, stretch, 1.0);
            }
            let mut steps = 0;
            while jacobian_of(&p) > jc {
                p.step(&m, compress, 1.0);
                q.step(&plain, compress, 1.0);
                // The step that re-connects closes only the excess over J_c stress-free.
                let pressure = -(p.stress[0] + p.stress[1] + p.stress[2]) / 3.0;
                let beyond = (jc / jacobian_of(&p)).ln().max(0.0);
                assert!(pressure <= k * beyond * 1.01 + 1e-9, "dev {dev} c {c}: p = {pressure} at J = {}", jacobian_of(&p));
                steps += 1;
                assert!(steps < 10_000);
            }
            let target = jc * (-0.01f64).exp();
            while jacobian_of(&p) > target {
                p.step(&m, compress, 1.0);
                q.step(&plain, compress, 1.0);
            }
            let j = jacobian_of(&p);
            let pressure = -(p.stress[0] + p.stress[1] + p.stress[2]) / 3.0;
            let expected = k * (jc / j).ln();
            assert!((pressure - expected).abs() < 0.02 * expected, "dev {dev} c {c}: p = {pressure}, K ln(J_c/J) = {expected}");
            let plain_pressure = -(q.stress[0] + q.stress[1] + q.stress[2]) / 3.0;
            assert!(plain_pressure > 5.0 * expected, "plain model: p = {plain_pressure} vs {expected}");
            // Volume bookkeeping: ln J = plastic + elastic volumetric strain (−p/K), the
            // stress-free compaction booked as negative plastic volume change (up to the
            // difference between Σ tr dε and ln det F, ~1e-5 here).
            let elastic_volume = -pressure / k;
            assert!((p.state[1] + elastic_volume - j.ln()).abs() < 1e-4, "dev {dev} c {c}: {:?}, ln J = {}", p.state, j.ln());
            // Unloading: back to zero stress by J_c (the elastic part returns, nothing more).
            while jacobian_of(&p) <= jc {
                p.step(&m, stretch, 1.0);
            }
            assert_eq!(p.stress, [0.0; 4], "dev {dev} c {c}");
        }
    }

    /// The elastic energy of a stressed point that is found disconnected (here without any
    /// deformation in the step, so σ_B = σ_n) is booked in full, J W(σ_n) per unit reference
    /// volume, in `disconnection_work` and in `plastic_work`; its elastic strain becomes
    /// plastic (total strain unchanged). A point compressed while disconnected (stress-free,
    /// so no work is done on it) books nothing.
    #[test]
    fn disconnection_books_the_discarded_elastic_energy() {
        let jc = 1.1;
        let m = disconnecting(30.0, 0.0, jc);
        assert_eq!(m.state_names(), &STATE_NAMES_DISCONNECTION[..]);
        assert_eq!(m.plastic_work_slot(), 3);
        let sigma = [-2e3, -1e3, -1.5e3, 300.0];
        for j in [0.9, 1.3] {
            let mut s = sigma;
            let mut state = [0.0; 4];
            let k = Kinematics { velocity_gradient: [0.0; 5], deformation_gradient: [1.0, 0.0, 0.0, 1.0, j], jacobian: j, cell_field: [0.0; 2], dt: 1.0 };
            m.update_stress(&mut s, &mut state, &k);
            if j < jc {
                assert_eq!((s, state), (sigma, [0.0; 4]), "connected and elastic");
                continue;
            }
            assert_eq!(s, [0.0; 4]);
            let w = j * super::super::complementary_energy(&sigma, E, NU);
            assert!(w > 0.0);
            assert!((state[DISCONNECTION_WORK] - w).abs() <= 1e-12 * w, "{state:?} vs {w}");
            assert_eq!(state[DISCONNECTION_WORK], state[3]);
            let ep = compliance4(&sigma);
            assert!((state[1] - (ep[0] + ep[1] + ep[2])).abs() < 1e-15, "{state:?}");
        }
        // Over a stretch–compress cycle through J_c from a confined start, the booked energy is
        // at most the initial elastic energy (the rest is returned by elastic unloading).
        let mut p = MaterialPoint::new(&m, [-2e3, -2e3, -2e3, 0.0]);
        let w0 = super::super::complementary_energy(&p.stress, E, NU);
        let r = 1e-4;
        while jacobian_of(&p) < 1.2 {
            p.step(&m, [r, 0.0, 0.0, r, r], 1.0);
        }
        while jacobian_of(&p) > 1.0 {
            p.step(&m, [-r, 0.0, 0.0, -r, -r], 1.0);
        }
        assert!(p.state[DISCONNECTION_WORK] >= 0.0 && p.state[DISCONNECTION_WORK] <= w0, "{:?} vs {w0}", p.state);
        assert!(p.state[3] >= p.state[DISCONNECTION_WORK]);
    }

    #[test]
    fn disconnection_config_names_the_field_and_its_range() {
        use crate::config::MaterialConfig;
        let mut base = MaterialConfig::elastic("mohr_coulomb", 1550.0, 1e6, 0.3);
        base.set("friction_angle", 25.0);
        let from = |c: &MaterialConfig| {
            let table = c.parameters.clone();
            MohrCoulomb::from_parameters(&Parameters::new("sand", &table))
        };
        assert_eq!(from(&base).unwrap().critical_jacobian, None);
        let mut c = base.clone();
        c.set("critical_packing_fraction", 0.58);
        assert_eq!(from(&c).err().unwrap(), "materials.sand.grain_density: is required with critical_packing_fraction");
        c.set("grain_density", 2500.0);
        let m = from(&c).unwrap();
        let jc = m.critical_jacobian.unwrap();
        assert!((jc - 1550.0 / 2500.0 / 0.58).abs() < 1e-15, "{jc}");
        assert_eq!(m.state_names(), &STATE_NAMES_DISCONNECTION[..]);
        c.set("experimental", true);
        assert_eq!(super::super::build("sand", &c).unwrap().state_names(), &STATE_NAMES_DISCONNECTION[..]);
        for phi_c in [0.0, 0.63, -0.1] {
            c.set("critical_packing_fraction", phi_c);
            assert_eq!(
                from(&c).err().unwrap(),
                format!("materials.sand.critical_packing_fraction: must be in (0, density/grain_density] = (0, 0.62] (got {phi_c})")
            );
        }
        c.set("critical_packing_fraction", 0.58).set("grain_density", 1500.0);
        assert!(from(&c).err().unwrap().starts_with("materials.sand.grain_density: must be > density = 1550"));
    }

    // ------------------------------------------------------------------ Tresca (φ = 0)

    pub(super) fn tresca(c: f64, st: f64) -> MohrCoulomb {
        mc(0.0, 0.0, c, st)
    }

    /// One step of `m` with the velocity gradient `l(x)`, the free rate x solved (secant) so that
    /// stress component `comp` ends at `target`.
    fn controlled_step(
        m: &MohrCoulomb,
        s: &mut Stress,
        st: &mut [f64],
        l: &dyn Fn(f64) -> [f64; 5],
        comp: usize,
        target: f64,
        guess: f64,
    ) {
        let run = |x: f64| {
            let (mut s2, mut st2) = (*s, [st[0], st[1]]);
            m.update_stress(&mut s2, &mut st2, &kin(l(x), 1.0));
            (s2, st2)
        };
        let (mut x0, mut x1) = (0.0, guess);
        let mut g0 = run(x0).0[comp] - target;
        let scale = target.abs() + m.cohesion;
        for _ in 0..60 {
            let g1 = run(x1).0[comp] - target;
            if g1.abs() < 1e-12 * scale || g1 == g0 {
                break;
            }
            let x2 = x1 - g1 * (x1 - x0) / (g1 - g0);
            (x0, g0, x1) = (x1, g1, x2);
        }
        let (s2, st2) = run(x1);
        *s = s2;
        st[..2].copy_from_slice(&st2);
        assert!((s[comp] - target).abs() < 1e-9 * scale, "control of component {comp}: {s:?}");
    }

    /// Closed-form Tresca strengths, whatever the mean stress p0 the test starts from (isotropic
    /// −p0, constant lateral stress): uniaxial compression and tension (axisymmetric kinematics,
    /// σ_rr = σ_θθ = −p0) fail at |σ_zz − σ_rr| = 2c; plane-strain compression (ε_zz = 0,
    /// σ_xx = −p0) at σ_xx − σ_yy = 2c, with σ_zz staying between (the flow (1, 0, −1) has no
    /// out-of-plane part: σ_zz = −p0 − 2cν at failure); simple shear (plane strain) at in-plane
    /// radius √(((σ_xx − σ_yy)/2)² + σ_xy²) = c. Elastic up to exactly that load.
    #[test]
    fn tresca_strengths_are_closed_form() {
        let c = 15e3;
        let m = tresca(c, f64::INFINITY);
        let de = 2e-5; // axial strain per step: E de = 1 kPa, so 2c is reached after 30 steps
        for &p0 in &[0.0, 50e3, 400e3] {
            for &(axisymmetric, sign) in &[(true, -1.0), (true, 1.0), (false, -1.0), (false, 1.0)] {
                let mut s = [-p0, -p0, -p0, 0.0];
                let mut st = [0.0, 0.0];
                let mut peak: f64 = 0.0;
                let ez = sign * de;
                let l = |x: f64| if axisymmetric { [x, 0.0, 0.0, ez, x] } else { [x, 0.0, 0.0, ez, 0.0] };
                let mut first_plastic = None;
                for step in 0..200 {
                    controlled_step(&m, &mut s, &mut st, &l, 0, -p0, -NU * ez);
                    let q = sign * (s[1] - s[0]);
                    peak = peak.max(q);
                    assert!(q <= 2.0 * c * (1.0 + 1e-9), "q = {q} > 2c");
                    if first_plastic.is_none() && st[0] > 0.0 {
                        first_plastic = Some(step);
                    }
                }
                let label = format!("axisymmetric {axisymmetric}, sign {sign}, p0 {p0}");
                let y = first_plastic.expect("never yielded") as f64;
                // Uniaxial: q grows by E de per step; plane strain: by E de/(1 − ν²).
                let rate = if axisymmetric { E * de } else { E * de / (1.0 - NU * NU) };
                assert!((y - 2.0 * c / rate).abs() <= 1.0, "{label}: yielded at step {y}");
                let q = sign * (s[1] - s[0]);
                assert!((q - 2.0 * c).abs() <= 1e-9 * (p0 + c), "{label}: q = {q}");
                assert!((peak - 2.0 * c).abs() <= 1e-9 * (p0 + c), "{label}: peak {peak}");
                assert!(st[1].abs() <= 1e-12 * st[0], "{label}: plastic volume change {st:?}");
                if axisymmetric {
                    assert!((s[2] - s[0]).abs() <= 1e-9 * (p0 + c), "{label}: hoop {s:?}");
                } else {
                    let zz = -p0 + sign * 2.0 * c * NU;
                    assert!((s[2] - zz).abs() <= 1e-6 * (p0 + c), "{label}: σ_zz = {} vs {zz}", s[2]);
                }
            }
            // Simple shear, plane strain: L12 = γ̇.
            let mut s = [-p0, -p0, -p0, 0.0];
            let mut st = [0.0, 0.0];
            let g = E / (2.0 * (1.0 + NU));
            let gamma = 2e-5;
            let mut first_plastic = None;
            for step in 0..200 {
                m.update_stress(&mut s, &mut st, &kin([0.0, gamma, 0.0, 0.0, 0.0], 1.0));
                let radius = (0.25 * (s[0] - s[1]).powi(2) + s[3] * s[3]).sqrt();
                assert!(radius <= c * (1.0 + 1e-9));
                if first_plastic.is_none() && st[0] > 0.0 {
                    first_plastic = Some(step);
                }
            }
            let y = first_plastic.expect("never yielded") as f64;
            assert!((y - c / (g * gamma)).abs() <= 1.5, "simple shear yielded at step {y}");
            let radius = (0.25 * (s[0] - s[1]).powi(2) + s[3] * s[3]).sqrt();
            assert!((radius - c).abs() <= 1e-9 * (p0 + c), "simple shear radius {radius}");
            assert!((s[0] + s[1] + s[2] + 3.0 * p0).abs() <= 1e-9 * (p0 + c), "mean stress changed {s:?}");
        }
    }

    // ---------------------------------------------------------------- dilute material, time step

    fn at_jacobian(l: [f64; 5], dt: f64, jacobian: f64) -> Kinematics {
        Kinematics { velocity_gradient: l, deformation_gradient: [1.0, 0.0, 0.0, 1.0, 1.0], jacobian, cell_field: [0.0; 2], dt }
    }

    /// P-wave speed a stress increment implies: c² = (Δσ_11/Δε_11) J/ρ0 for a uniaxial strain
    /// increment (ρ = ρ0/J, the current density).
    fn implied_wave_speed(m: &MohrCoulomb, jacobian: f64) -> f64 {
        let dt = 1e-5;
        let de = -1e-6; // compression along 1 only (uniaxial strain): M = λ + 2μ
        let mut s = [-10.0, -10.0, -10.0, 0.0]; // a little pressure: on the elastic side
        let mut state = [0.0; 3];
        m.update_stress(&mut s, &mut state, &at_jacobian([de / dt, 0.0, 0.0, 0.0, 0.0], dt, jacobian));
        let modulus = (s[0] + 10.0) / de;
        (modulus * jacobian / m.density).sqrt()
    }

    /// A particle dilated stress-free to J ≫ 1 and re-loaded with the moduli of the material as
    /// placed has the P-wave speed c0 √J (ρ = ρ0/J), beyond what the time step keeps stable.
    /// With the limit, the re-loading stiffness of such a particle keeps its wave speed at the
    /// limit; up to the limit nothing changes.
    #[test]
    fn dilute_material_reloads_no_faster_than_the_time_step_allows() {
        let plain = mc(25.0, 0.0, 0.0, 0.0);
        let c0 = plain.wave_speed();
        let mut limited = plain.clone();
        limited.limit_wave_speed(2.0 * c0); // stable up to J = 4
        assert!((limited.stable_jacobian - 4.0).abs() < 1e-12, "{}", limited.stable_jacobian);
        // The mechanism: without the limit the wave speed grows as √J.
        let fast = implied_wave_speed(&plain, 1000.0);
        assert!((fast / c0 - 1000f64.sqrt()).abs() < 1e-6 * 1000f64.sqrt(), "{fast} vs {c0}");
        for jacobian in [5.0, 40.0, 1000.0] {
            let c = implied_wave_speed(&limited, jacobian);
            assert!((c - 2.0 * c0).abs() < 1e-6 * c0, "J = {jacobian}: c = {c}, limit {}", 2.0 * c0);
        }
        // Up to the limit: bit for bit the plain model (compressed, sheared, returned).
        let mut rng = Lcg(7);
        for jacobian in [0.8, 1.0, 3.9, 4.0] {
            for _ in 0..50 {
                let l = [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), 0.0];
                let k = at_jacobian(l, 1e-4, jacobian);
                let (mut a, mut b) = ([-1e3, -2e3, -1.5e3, 300.0], [-1e3, -2e3, -1.5e3, 300.0]);
                let (mut sa, mut sb) = ([0.0; 3], [0.0; 3]);
                plain.update_stress(&mut a, &mut sa, &k);
                limited.update_stress(&mut b, &mut sb, &k);
                assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
                assert_eq!(sa.map(f64::to_bits), sb.map(f64::to_bits));
            }
        }
        // The limit never stiffens or softens the material as placed (J_s ≥ 1).
        let mut slow = plain.clone();
        slow.limit_wave_speed(0.5 * c0);
        assert_eq!(slow.stable_jacobian, 1.0);
    }

    /// Softer moduli s C⁻¹ mean a larger plastic strain for the same stress return:
    /// Δε^p = C (σ_B − σ_C)/s. A stress-free dilute particle sheared at the apex books all of
    /// the shear as plastic, with or without the limit.
    #[test]
    fn dilute_material_books_its_whole_shear_as_plastic() {
        let mut m = mc(25.0, 0.0, 0.0, 0.0);
        m.limit_wave_speed(2.0 * m.wave_speed()); // J_s = 4
        for jacobian in [2.0, 40.0] {
            let dt = 1e-4;
            let gamma = 1e-3; // engineering shear strain of the step
            let mut s = [0.0; 4];
            let mut state = [0.0; 3];
            m.update_stress(&mut s, &mut state, &at_jacobian([0.0, gamma / dt, 0.0, 0.0, 0.0], dt, jacobian));
            assert_eq!(s, [0.0; 4], "J = {jacobian}: stress-free at the apex");
            // Principal plastic strains ±γ/2: deviatoric norm √(2/3 · 2 (γ/2)²) = γ/√3.
            let want = gamma / 3f64.sqrt();
            assert!((state[0] - want).abs() < 1e-9 * want, "J = {jacobian}: plastic shear {} vs {want}", state[0]);
        }
    }

    /// At J = J_c exactly the material is still connected (disconnected only above J_c).
    #[test]
    fn at_the_critical_jacobian_the_material_is_still_connected() {
        let jc = 1.2;
        let m = disconnecting(25.0, 0.0, jc);
        let dt = 1e-4;
        let kinematics = Kinematics {
            velocity_gradient: [-1e-3 / dt, 0.0, 0.0, -1e-3 / dt, 0.0],
            deformation_gradient: [1.0, 0.0, 0.0, 1.0, 1.0],
            jacobian: jc,
            cell_field: [0.0; 2],
            dt,
        };
        let mut s = [-100.0, -100.0, -100.0, 0.0];
        let mut state = [0.0; 4];
        m.update_stress(&mut s, &mut state, &kinematics);
        assert!(s[0] < -100.0 && s[1] < -100.0, "connected at J_c: compressed, got {s:?}");
    }

    /// Above J_s the whole elastic increment (every component, not only the normal ones) is the
    /// one of the material as placed times s = J_s/J; the spin-free step has no rotation term.
    #[test]
    fn dilute_material_stress_increment_is_the_plain_one_times_js_over_j() {
        let plain = mc(25.0, 0.0, 0.0, 0.0);
        let mut limited = plain.clone();
        limited.limit_wave_speed(3.0 * plain.wave_speed()); // J_s = 9
        assert!((limited.stable_jacobian - 9.0).abs() < 1e-12, "{}", limited.stable_jacobian);
        let dt = 1e-5;
        // Symmetric gradient (no spin), all four strain components non-zero, small enough to
        // stay elastic from the confined start below.
        let l = [-2e-7 / dt, 1.5e-7 / dt, 1.5e-7 / dt, -1e-7 / dt, 0.5e-7 / dt];
        let start = [-1e3, -1.2e3, -0.9e3, 50.0];
        for jacobian in [12.0, 40.0, 1000.0] {
            let k = at_jacobian(l, dt, jacobian);
            let (mut a, mut b) = (start, start);
            let (mut sa, mut sb) = ([0.0; 3], [0.0; 3]);
            plain.update_stress(&mut a, &mut sa, &k);
            limited.update_stress(&mut b, &mut sb, &k);
            let s = 9.0 / jacobian;
            for c in 0..4 {
                let (da, db) = (a[c] - start[c], b[c] - start[c]);
                assert!(da.abs() > 1e-3, "component {c}: a non-trivial increment {da}");
                assert!((db - s * da).abs() <= 1e-9 * da.abs(), "J = {jacobian}, component {c}: {db} vs {s} × {da}");
            }
            assert_eq!(sb, [0.0; 3], "elastic: nothing plastic");
        }
    }

    /// A disconnected particle books its trial as plastic strain with the compliance of the
    /// moduli in use, (s C⁻¹)⁻¹: from σ = 0 that is the step's strain increment itself, with or
    /// without the limit (module doc, "Dilute material and the time step").
    #[test]
    fn a_disconnected_dilute_particle_books_its_strain_increment_as_plastic() {
        let plain = disconnecting(25.0, 0.0, 1.2);
        let mut limited = plain.clone();
        limited.limit_wave_speed(3.0 * plain.wave_speed()); // J_s = 9 < J below
        let dt = 1e-4;
        let l = [-2e-3 / dt, 1e-3 / dt, 0.5e-3 / dt, 0.5e-3 / dt, -1e-3 / dt];
        let (d, _) = rate_of_deformation(&l);
        let de = d.map(|x| x * dt);
        let vol = de[0] + de[1] + de[2];
        let dev = [de[0] - vol / 3.0, de[1] - vol / 3.0, de[2] - vol / 3.0];
        let shear = (2.0 / 3.0 * (dev[0] * dev[0] + dev[1] * dev[1] + dev[2] * dev[2] + 2.0 * de[3] * de[3])).sqrt();
        for m in [&plain, &limited] {
            let mut s = [0.0; 4];
            let mut state = [0.0; 4];
            m.update_stress(&mut s, &mut state, &at_jacobian(l, dt, 40.0));
            assert_eq!(s, [0.0; 4], "disconnected: stress-free");
            assert!((state[1] - vol).abs() <= 1e-9 * vol.abs(), "plastic volume {} vs {vol}", state[1]);
            assert!((state[0] - shear).abs() <= 1e-9 * shear, "plastic shear {} vs {shear}", state[0]);
            assert_eq!(state[DISCONNECTION_WORK], 0.0, "from σ = 0 nothing is discarded");
        }
    }

    /// A dilute particle (J > J_s) torn open from σ = 0 returns to the apex (c = 0): its whole
    /// strain increment is plastic, Δε^p = C (σ_B − 0)/s with σ_B = s C⁻¹ Δε, i.e. Δε^p = Δε in
    /// every principal direction (three distinct non-zero values here), with or without the limit.
    #[test]
    fn a_dilute_particle_torn_open_books_its_whole_strain_increment_as_plastic() {
        let plain = mc(25.0, 0.0, 0.0, 0.0);
        let mut limited = plain.clone();
        limited.limit_wave_speed(2.0 * plain.wave_speed()); // J_s = 4
        let dt = 1e-4;
        // Stretching in all three directions (in-plane principal 2.6e-3 and 0.9e-3, out-of-plane
        // 0.5e-3): the trial is tensile, beyond the apex.
        let l = [2e-3 / dt, 0.8e-3 / dt, 0.8e-3 / dt, 1.5e-3 / dt, 0.5e-3 / dt];
        let (d, _) = rate_of_deformation(&l);
        let de = d.map(|x| x * dt);
        let vol = de[0] + de[1] + de[2];
        let dev = [de[0] - vol / 3.0, de[1] - vol / 3.0, de[2] - vol / 3.0];
        let shear = (2.0 / 3.0 * (dev[0] * dev[0] + dev[1] * dev[1] + dev[2] * dev[2] + 2.0 * de[3] * de[3])).sqrt();
        for (m, jacobian) in [(&plain, 40.0), (&limited, 40.0), (&limited, 5.0)] {
            let mut s = [0.0; 4];
            let mut state = [0.0; 3];
            m.update_stress(&mut s, &mut state, &at_jacobian(l, dt, jacobian));
            assert!(s.iter().all(|x| x.abs() < 1e-9), "J = {jacobian}: at the apex, {s:?}");
            assert!((state[1] - vol).abs() <= 1e-9 * vol, "J = {jacobian}: plastic volume {} vs {vol}", state[1]);
            assert!((state[0] - shear).abs() <= 1e-9 * shear, "J = {jacobian}: plastic shear {} vs {shear}", state[0]);
        }
    }

    /// The batched update (vectorised trial and elastic test for the plain model) equals the
    /// particle-by-particle `update_stress`, bit for bit in stress and state, for runs that mix
    /// elastic, plastic and dilute (J above the stable Jacobian) particles; also for the
    /// variants and run lengths that take the particle-by-particle path, and compiled for AVX2.
    #[test]
    fn batched_update_equals_particle_by_particle() {
        let variants = [
            mc(30.0, 5.0, 0.0, 0.0).with_stable_jacobian(3.0),
            mc(25.0, 0.0, 2e3, 1e3).with_stable_jacobian(3.0),
            mc(30.0, 0.0, 0.0, 0.0).with_disconnection(Some(1.2)),
        ];
        let mut rng = Lcg(7);
        for (v, m) in variants.iter().enumerate() {
            let length = m.state_names().len();
            for n in [1, 17, 32, 40] {
                let stress: Vec<Stress> = (0..n)
                    .map(|_| {
                        let p = rng.uniform(-2e4, -1e3);
                        [p + rng.uniform(-8e3, 8e3), p + rng.uniform(-8e3, 8e3), p + rng.uniform(-3e3, 3e3), rng.uniform(-6e3, 6e3)]
                    })
                    .collect();
                let kin: Vec<Kinematics> = (0..n)
                    .map(|_| {
                        let l = [0; 5].map(|_| rng.uniform(-2.0, 2.0));
                        let mut k = kin(l, 1e-4);
                        k.jacobian = if rng.next() < 0.2 { rng.uniform(3.0, 30.0) } else { rng.uniform(0.9, 1.3) };
                        k
                    })
                    .collect();
                let state: Vec<f64> = (0..n * length).map(|_| rng.uniform(0.0, 1e-3)).collect();
                let (mut s_one, mut st_one) = (stress.clone(), state.clone());
                for i in 0..n {
                    m.update_stress(&mut s_one[i], &mut st_one[i * length..(i + 1) * length], &kin[i]);
                }
                let plastic = (0..n).filter(|&i| {
                    let (mut s, mut st) = (stress[i], state[i * length..(i + 1) * length].to_vec());
                    m.update_stress(&mut s, &mut st, &kin[i]);
                    let (d, spin) = rate_of_deformation(&kin[i].velocity_gradient);
                    let de = d.map(|x| x * kin[i].dt);
                    s != m.trial_stress(&stress[i], &de, &jaumann_rotation(&stress[i], spin, kin[i].dt), kin[i].jacobian).0
                });
                let plastic = plastic.count();
                // (The count is only meaningful for the plain variants, whose trial is that one.)
                if n >= 17 && v < 2 {
                    assert!(plastic > 0 && plastic < n, "variant {v}, n = {n}: {plastic} plastic particles, want a mix");
                }
                let (mut s, mut st) = (stress.clone(), state.clone());
                m.update_stress_batch(&mut s, &mut st, length, length, &kin);
                let mut batched = vec![(s, st)];
                #[cfg(target_arch = "x86_64")]
                if is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma") && is_x86_feature_detected!("bmi2") {
                    let (mut s, mut st) = (stress.clone(), state.clone());
                    // SAFETY: the CPU has AVX2, FMA and BMI2 (checked above).
                    unsafe { m.update_stress_batch_avx2(&mut s, &mut st, length, length, &kin) };
                    batched.push((s, st));
                }
                for (s, st) in &batched {
                    for i in 0..n {
                        assert_eq!(s[i].map(f64::to_bits), s_one[i].map(f64::to_bits), "variant {v}, n = {n}, particle {i}");
                    }
                    assert_eq!(st.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), st_one.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
                }
            }
        }
    }
}
