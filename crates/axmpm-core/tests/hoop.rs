//! The axisymmetric hoop terms under test: a free-standing elastic cylinder on a frictionless
//! base, loaded by its own weight. Linear elasticity gives uniaxial stress,
//! σ_zz = −ρ g (H − z), σ_rr = σ_θθ = σ_rz = 0, and the lateral (Poisson) bulge
//! u_r = ν ρ g (H − z) r / E (Timoshenko & Goodier, bar under its own weight). Radial
//! motion exercises the hoop rate v_r/R_p and the hoop force σ_θθ S_ip/R_p: dropping either
//! makes σ_θθ, σ_rr or u_r wrong by O(1).

mod common;
use axmpm_core::config::*;
use axmpm_core::Simulation;
use common::*;

fn cylinder(shape: ShapeFunctionKind) -> Config {
    let (radius, height, h) = (0.2, 1.0, 0.05);
    let mut cfg = block(FormulationKind::Axisymmetric, shape, [0.0, -10.0], [0.0, 0.0]);
    // ρ g H / E = 1e-3: small strain.
    cfg.materials.get_mut("m").unwrap().set("poisson_ratio", 0.3).set("youngs_modulus", 1e7);
    cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [radius + 4.0 * h, height + 2.0 * h], cell_size: h, follow: None, experimental: false };
    cfg.bodies[0].set_rectangle([0.0, 0.0], [radius, height]);
    cfg.boundaries.bottom = BoundaryCondition::ROLLER;
    cfg.simulation.gravity_ramp_time = 0.3;
    cfg.simulation.damping = 0.3;
    cfg
}

#[test]
fn standing_cylinder_bulges_by_poisson_and_carries_no_lateral_stress() {
    for shape in [ShapeFunctionKind::Linear, ShapeFunctionKind::Cpgimp, ShapeFunctionKind::Cpdi2] {
        let cfg = cylinder(shape);
        let (rho, g, e, nu, height) = (1000.0, 10.0, 1e7, 0.3, 1.0);
        let mut sim = Simulation::new(cfg, 1).unwrap();
        sim.advance(2.0, u64::MAX).unwrap();
        let p = sim.particles();
        let base = rho * g * height;
        let (mut num, mut den) = (0.0, 0.0);
        let mut lateral_max: f64 = 0.0;
        for i in 0..p.len() {
            let [r0, z0] = p.initial_position[i];
            let s = p.stress[i];
            lateral_max = lateral_max.max(s[0].abs()).max(s[2].abs());
            if z0 > 0.25 * height {
                // Away from the base, where the roller forces a flat base that the free bar
                // would not have.
                let ur_exact = nu * rho * g * (height - z0) * r0 / e;
                let ur = p.position[i][0] - r0;
                num += (ur - ur_exact).powi(2);
                den += ur_exact.powi(2);
            }
        }
        let ur_error = (num / den).sqrt();
        assert!(ur_error < 0.05, "{shape:?}: radial displacement error {ur_error:.4}");
        assert!(lateral_max < 0.05 * base, "{shape:?}: max |σ_rr|, |σ_θθ| = {lateral_max:.1} Pa vs ρgH = {base}");
    }
}

#[test]
fn laterally_confined_cylinder_carries_k0_hoop_stress() {
    // Roller on the outer face r = R: uniaxial strain, σ_rr = σ_θθ = ν/(1−ν) σ_zz,
    // σ_zz = −ρ g (H − z), u_r = 0. Radial equilibrium ∂σ_rr/∂r + (σ_rr − σ_θθ)/r = 0 holds
    // only with the hoop force −V σ_θθ S_ip/R_p: without it the interior nodes are pushed
    // towards the axis by a constant σ_rr.
    for shape in [ShapeFunctionKind::Linear, ShapeFunctionKind::Cpgimp, ShapeFunctionKind::Cpdi2] {
        let mut cfg = cylinder(shape);
        let (rho, g, nu, height) = (1000.0, 10.0, 0.3, 1.0);
        cfg.grid.extent[0] = 0.2;
        cfg.boundaries.right = BoundaryCondition::ROLLER;
        let mut sim = Simulation::new(cfg, 1).unwrap();
        sim.advance(2.0, u64::MAX).unwrap();
        let p = sim.particles();
        let k0 = nu / (1.0 - nu);
        let (mut num, mut den) = (0.0, 0.0);
        let mut max_ur: f64 = 0.0;
        for i in 0..p.len() {
            let [r0, z0] = p.initial_position[i];
            let szz = -rho * g * (height - z0);
            if z0 > 0.1 && z0 < 0.9 {
                for lateral in [p.stress[i][0], p.stress[i][2]] {
                    num += (lateral - k0 * szz).powi(2);
                    den += (k0 * szz).powi(2);
                }
            }
            max_ur = max_ur.max((p.position[i][0] - r0).abs());
        }
        let lateral_error = (num / den).sqrt();
        let uz_scale = rho * g * height * height / 1e7;
        assert!(lateral_error < 0.05, "{shape:?}: σ_rr, σ_θθ vs K0 σ_zz: relative error {lateral_error:.4}");
        assert!(max_ur < 0.02 * uz_scale, "{shape:?}: max |u_r| = {max_ur:.3e} m (vertical scale {uz_scale:.1e})");
    }
}
