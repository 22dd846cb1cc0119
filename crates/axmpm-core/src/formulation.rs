//! Plane strain and axisymmetric kinematics (Sulsky & Schreyer 1996; docs/physics.md §2).
//!
//! The two formulations differ only in three places, all at the particle:
//! the volume measure (V_p = A_p or A_p R_p), the hoop term of the internal force
//! (σ_θθ S_ip / R_p) and the hoop rate of deformation (L_θθ = Σ v_r,i S_ip / R_p).
//! Following NairnMPM, they live here and the solver loops call them through a type
//! parameter, so each combination is compiled into its own monomorphised loop.

pub trait Formulation: Send + Sync + 'static {
    const NAME: &'static str;
    const AXISYMMETRIC: bool;

    /// Factor turning an in-plane area into the volume measure used in the sums:
    /// 1 in plane strain, R_p per radian in axisymmetry.
    fn volume_factor(position: [f64; 2]) -> f64;

    /// Factor multiplying S_ip in the hoop terms: 0 in plane strain, 1/R_p in axisymmetry.
    /// Used for the hoop internal force −V_p σ_θθ S_ip / R_p and the hoop velocity gradient
    /// L_θθ = Σ_i v_r,i S_ip / R_p.
    fn hoop_factor(position: [f64; 2]) -> f64;

    /// Multiplier turning per-radian or per-metre quantities into the reported totals
    /// (2π for a body of revolution, 1 per metre thickness in plane strain).
    const TOTAL_FACTOR: f64;
}

/// Plane strain: (x, y), ε_zz = 0.
pub struct PlaneStrain;

impl Formulation for PlaneStrain {
    const NAME: &'static str = "plane_strain";
    const AXISYMMETRIC: bool = false;
    const TOTAL_FACTOR: f64 = 1.0;

    #[inline(always)]
    fn volume_factor(_: [f64; 2]) -> f64 {
        1.0
    }

    #[inline(always)]
    fn hoop_factor(_: [f64; 2]) -> f64 {
        0.0
    }
}

/// Axisymmetric: (r, z) with r ≥ 0, quantities per radian.
pub struct Axisymmetric;

impl Formulation for Axisymmetric {
    const NAME: &'static str = "axisymmetric";
    const AXISYMMETRIC: bool = true;
    const TOTAL_FACTOR: f64 = 2.0 * std::f64::consts::PI;

    #[inline(always)]
    fn volume_factor(position: [f64; 2]) -> f64 {
        position[0]
    }

    #[inline(always)]
    fn hoop_factor(position: [f64; 2]) -> f64 {
        1.0 / position[0]
    }
}
