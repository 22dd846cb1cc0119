//! Return-map test helpers shared by the elasto-plastic models' tests (Mohr–Coulomb now, J2
//! next): reproducible random stress states, principal stresses, isotropic elastic stiffness
//! and compliance in principal space, a flow-rule check, surface checks and a material-point
//! driver that integrates F as the solver does.

use super::{Kinematics, Material};
use crate::particles::{DeformationGradient, Stress, IDENTITY_F};

/// A small linear congruential generator: reproducible random numbers without a dependency.
pub struct Lcg(pub u64);

impl Lcg {
    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// Random sorted principal stresses σ1 ≥ σ2 ≥ σ3 in [lo, hi), with about one in ten having
/// σ1 = σ2 and one in ten σ2 = σ3 (the edges of a principal-space return).
pub fn random_sorted(rng: &mut Lcg, lo: f64, hi: f64) -> [f64; 3] {
    let mut v = [rng.uniform(lo, hi), rng.uniform(lo, hi), rng.uniform(lo, hi)];
    v.sort_by(|a, b| b.partial_cmp(a).unwrap());
    if rng.next() < 0.1 {
        v[1] = v[0];
    } else if rng.next() < 0.1 {
        v[2] = v[1];
    }
    v
}

/// A random stress `[σ11, σ22, σ33, σ12]`: normal components in [lo, hi), shear in
/// [−shear/2, shear/2).
pub fn random_stress(rng: &mut Lcg, lo: f64, hi: f64, shear: f64) -> Stress {
    [rng.uniform(lo, hi), rng.uniform(lo, hi), rng.uniform(lo, hi), shear * (rng.next() - 0.5)]
}

/// Principal stresses of `[σ11, σ22, σ33, σ12]` (σ33 is principal), sorted σ1 ≥ σ2 ≥ σ3.
pub fn principal_stresses(s: &Stress) -> [f64; 3] {
    let c = 0.5 * (s[0] + s[1]);
    let r = (0.5 * (s[0] - s[1])).hypot(s[3]);
    let mut v = [c + r, c - r, s[2]];
    v.sort_by(|a, b| b.partial_cmp(a).unwrap());
    v
}

/// Kinematics of one step with velocity gradient `l` and F = I (for models that do not read F).
pub fn kinematics(l: [f64; 5], dt: f64) -> Kinematics {
    Kinematics { velocity_gradient: l, deformation_gradient: IDENTITY_F, jacobian: 1.0, cell_field: [0.0; 2], dt }
}

/// Isotropic elastic stiffness in principal space, D v = λ tr(v) 1 + 2μ v.
pub fn elastic_stiffness(youngs_modulus: f64, poisson_ratio: f64, v: [f64; 3]) -> [f64; 3] {
    let (l, m) = super::lame(youngs_modulus, poisson_ratio);
    let t = l * (v[0] + v[1] + v[2]);
    [t + 2.0 * m * v[0], t + 2.0 * m * v[1], t + 2.0 * m * v[2]]
}

/// Isotropic elastic compliance in principal space, C v = ((1 + ν) v − ν tr(v) 1) / E.
pub fn elastic_compliance(youngs_modulus: f64, poisson_ratio: f64, v: [f64; 3]) -> [f64; 3] {
    let (e, nu) = (youngs_modulus, poisson_ratio);
    let s = nu * (v[0] + v[1] + v[2]);
    [((1.0 + nu) * v[0] - s) / e, ((1.0 + nu) * v[1] - s) / e, ((1.0 + nu) * v[2] - s) / e]
}

pub fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Small dense solve (Gaussian elimination with partial pivoting); `None` when singular.
pub fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().partial_cmp(&a[j][c].abs()).unwrap())?;
        if a[p][c].abs() < 1e-300 {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in 0..n {
            if r != c {
                let f = a[r][c] / a[c][c];
                let pivot = a[c].clone();
                for (x, y) in a[r].iter_mut().zip(&pivot) {
                    *x -= f * y;
                }
                b[r] -= f * b[c];
            }
        }
    }
    Some((0..n).map(|i| b[i] / a[i][i]).collect())
}

/// Whether the principal plastic strain increment C (σ_B − σ_C) of a return from `trial` to
/// `ret` is a non-negative combination Σ λ_i g_i of some subset of at most three of the flow
/// directions `g` (fit to 1e-9 relative); `compliance` is C.
pub fn flow_rule_holds(
    compliance: impl Fn([f64; 3]) -> [f64; 3],
    trial: &[f64; 3],
    ret: &[f64; 3],
    g: &[[f64; 3]],
) -> bool {
    let v = compliance([trial[0] - ret[0], trial[1] - ret[1], trial[2] - ret[2]]);
    let vn = dot(&v, &v).sqrt();
    let n = g.len();
    for mask in 1u32..(1 << n) {
        let idx: Vec<usize> = (0..n).filter(|i| mask & (1 << i) != 0).collect();
        if idx.len() > 3 {
            continue;
        }
        let a: Vec<Vec<f64>> = idx.iter().map(|&i| idx.iter().map(|&j| dot(&g[i], &g[j])).collect()).collect();
        let b: Vec<f64> = idx.iter().map(|&i| dot(&g[i], &v)).collect();
        if let Some(l) = solve(a, b) {
            let mut r = v;
            for (q, &i) in idx.iter().enumerate() {
                for c in 0..3 {
                    r[c] -= l[q] * g[i][c];
                }
            }
            if dot(&r, &r).sqrt() <= 1e-9 * vn && l.iter().all(|&x| x >= -1e-9 * vn) {
                return true;
            }
        }
    }
    false
}

/// One material point driven through velocity gradients, its F integrated as the solver does
/// (F ← (I + Δt L) F in-plane, F33 ← (1 + Δt L33) F33).
#[derive(Clone, Debug)]
pub struct MaterialPoint {
    pub stress: Stress,
    pub state: Vec<f64>,
    pub deformation_gradient: DeformationGradient,
}

impl MaterialPoint {
    /// A point of `material` at `stress`, with zero state and F = I.
    pub fn new(material: &dyn Material, stress: Stress) -> Self {
        Self { stress, state: vec![0.0; material.state_names().len()], deformation_gradient: IDENTITY_F }
    }

    /// One step of velocity gradient `l` over `dt`.
    pub fn step(&mut self, material: &dyn Material, l: [f64; 5], dt: f64) {
        let f = self.deformation_gradient;
        let a = [1.0 + dt * l[0], dt * l[1], dt * l[2], 1.0 + dt * l[3]];
        let f = [
            a[0] * f[0] + a[1] * f[2],
            a[0] * f[1] + a[1] * f[3],
            a[2] * f[0] + a[3] * f[2],
            a[2] * f[1] + a[3] * f[3],
            (1.0 + dt * l[4]) * f[4],
        ];
        self.deformation_gradient = f;
        let jacobian = (f[0] * f[3] - f[1] * f[2]) * f[4];
        let k = Kinematics { velocity_gradient: l, deformation_gradient: f, jacobian, cell_field: [0.0; 2], dt };
        material.update_stress(&mut self.stress, &mut self.state, &k);
    }

    /// `steps` steps of the same velocity gradient.
    pub fn drive(&mut self, material: &dyn Material, l: [f64; 5], dt: f64, steps: usize) {
        for _ in 0..steps {
            self.step(material, l, dt);
        }
    }
}

/// `steps` steps of velocity gradient `l` (dt = 1, F = I) on a stress and state held by the caller.
pub fn drive(material: &dyn Material, stress: &mut Stress, state: &mut [f64], l: [f64; 5], steps: usize) {
    for _ in 0..steps {
        material.update_stress(stress, state, &kinematics(l, 1.0));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::LinearElastic;

    #[test]
    fn helpers_by_hand() {
        let (e, nu) = (10e6, 0.25);
        let v = [1e-4, -2e-4, 3e-4];
        let back = elastic_compliance(e, nu, elastic_stiffness(e, nu, v));
        for i in 0..3 {
            assert!((back[i] - v[i]).abs() < 1e-18);
        }
        assert_eq!(principal_stresses(&[-1.0, -3.0, -2.0, 0.0]), [-1.0, -2.0, -3.0]);
        assert_eq!(solve(vec![vec![2.0, 0.0], vec![0.0, 4.0]], vec![2.0, 2.0]), Some(vec![1.0, 0.5]));
        // Uniaxial strain of a linear elastic point: σ11 = (λ + 2μ) ε, with λ = μ = 4 MPa.
        let m = LinearElastic::new(2000.0, e, nu);
        let mut point = MaterialPoint::new(&m, [0.0; 4]);
        point.drive(&m, [1e-3, 0.0, 0.0, 0.0, 0.0], 0.1, 10);
        assert!((point.stress[0] - 12e6 * 1e-3).abs() < 1e-6, "{:?}", point.stress);
        assert!((point.deformation_gradient[0] - 1.0001f64.powi(10)).abs() < 1e-15);
    }
}
