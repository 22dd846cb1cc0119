//! Conservation and exactness properties of the explicit step.

mod common;
use axmpm_core::config::*;
use axmpm_core::Simulation;
use common::*;

fn total_momentum(sim: &Simulation) -> [f64; 2] {
    let p = sim.particles();
    let mut m = [0.0; 2];
    for i in 0..p.len() {
        m[0] += p.mass[i] * p.velocity[i][0];
        m[1] += p.mass[i] * p.velocity[i][1];
    }
    m
}

#[test]
fn mass_is_conserved_on_particles_and_grid() {
    for f in ALL_FORMULATIONS {
        for s in ALL_SHAPES {
            let mut sim = Simulation::new(block(f, s, [0.0, -9.81], [0.3, 0.1]), 1).unwrap();
            let m0: f64 = sim.particles().mass.iter().sum();
            sim.advance(0.05, u64::MAX).unwrap();
            let m1: f64 = sim.particles().mass.iter().sum();
            assert_eq!(m0, m1);
            // The grid receives the whole mass (partition of unity, body away from the edges).
            let mg: f64 = sim.grid_fields().mass.iter().sum();
            assert!((mg - m0).abs() < 1e-10 * m0, "{f:?} {s:?}: grid mass {mg} vs {m0}");
        }
    }
}

#[test]
fn linear_momentum_is_conserved_in_free_flight() {
    // Plane strain, no gravity, no boundaries, a block moving and spinning: total momentum is
    // constant (internal forces sum to zero by Σ∇S = 0). Axisymmetric momentum in r is not
    // conserved (hoop forces), so only its z component is checked there. Nodes lighter than
    // 1e-12 of a particle mass carry no velocity, which may lose momentum of that order.
    for f in ALL_FORMULATIONS {
        for s in ALL_SHAPES {
            let mut sim = Simulation::new(block(f, s, [0.0, 0.0], [0.5, -0.3]), 1).unwrap();
            // Add a shear velocity field so that stresses develop.
            let p0 = total_momentum(&sim);
            sim.advance(0.2, u64::MAX).unwrap();
            let p1 = total_momentum(&sim);
            let scale = p0[0].abs() + p0[1].abs();
            assert!((p1[1] - p0[1]).abs() < 1e-10 * scale, "{f:?} {s:?}: p_y {} -> {}", p0[1], p1[1]);
            if f == FormulationKind::PlaneStrain {
                assert!((p1[0] - p0[0]).abs() < 1e-10 * scale, "{s:?}: p_x {} -> {}", p0[0], p1[0]);
            }
        }
    }
}

#[test]
fn free_fall_is_exact_under_constant_gravity() {
    // No boundaries: every particle falls with x(t) = x0 + v0 t + g t²/2, with no stress,
    // whatever the FLIP/PIC blend: the FLIP part adds Σ S (v⁺ − v) = g Δt, the PIC part takes
    // Σ S v⁺ = v + g Δt (the new grid velocity; the old one would lose g Δt per step). Exact up
    // to the rounding of the stress (≲ 1e-4 Pa) and what it accelerates.
    for flip in [0.0, 0.5, 1.0] {
        for f in ALL_FORMULATIONS {
            for s in ALL_SHAPES {
                // Sideways gravity too in plane strain (a uniform radial motion would strain a
                // body of revolution).
                let g = if f == FormulationKind::PlaneStrain { [2.0, -9.81] } else { [0.0, -9.81] };
                let mut cfg = block(f, s, g, [0.0, 1.0]);
                cfg.simulation.time_step = 1e-3;
                cfg.simulation.flip_fraction = flip;
                let mut sim = Simulation::new(cfg, 1).unwrap();
                let t = 0.25;
                sim.advance(t, u64::MAX).unwrap();
                assert_eq!(sim.time(), t);
                let p = sim.particles();
                for i in 0..p.len() {
                    let v = 1.0 + g[1] * t;
                    assert!((p.velocity[i][1] - v).abs() < 1e-8, "FLIP {flip} {f:?} {s:?}: v = {:?}", p.velocity[i]);
                    assert!((p.velocity[i][0] - g[0] * t).abs() < 1e-8, "FLIP {flip} {f:?} {s:?}: v = {:?}", p.velocity[i]);
                    // Symplectic Euler: x_n = x0 + v0 t + g t (t + dt)/2, exact for this integrator.
                    let y = p.initial_position[i][1] + 1.0 * t + 0.5 * g[1] * t * (t + 1e-3);
                    assert!((p.position[i][1] - y).abs() < 1e-8, "FLIP {flip} {f:?} {s:?}: y {} vs {}", p.position[i][1], y);
                    let x = p.initial_position[i][0] + 0.5 * g[0] * t * (t + 1e-3);
                    assert!((p.position[i][0] - x).abs() < 1e-8, "FLIP {flip} {f:?} {s:?}: x {} vs {x}", p.position[i][0]);
                    // Rounding of the gradient sums only (ρ g H ≈ 6 kPa).
                    assert!(p.stress[i].iter().all(|s| s.abs() < 1e-4), "{:?}", p.stress[i]);
                }
            }
        }
    }
}

/// Reported totals are the per-radian sums × 2π in axisymmetry (the body of revolution) and
/// the per-metre sums in plane strain: checked against hand sums over the particles.
#[test]
fn energies_are_whole_body_totals() {
    for f in ALL_FORMULATIONS {
        let g = [0.0, -9.81];
        let mut sim = Simulation::new(block(f, ShapeFunctionKind::Linear, g, [0.3, -0.4]), 1).unwrap();
        sim.advance(0.05, u64::MAX).unwrap();
        let p = sim.particles();
        let (mut kinetic, mut work) = (0.0, 0.0);
        for i in 0..p.len() {
            let v = p.velocity[i];
            kinetic += 0.5 * p.mass[i] * (v[0] * v[0] + v[1] * v[1]);
            work += p.mass[i] * g[1] * (p.position[i][1] - p.initial_position[i][1]);
        }
        let factor = match f {
            FormulationKind::PlaneStrain => 1.0,
            FormulationKind::Axisymmetric => 2.0 * std::f64::consts::PI,
        };
        assert_eq!(sim.total_factor(), factor);
        let e = sim.energies();
        assert!(kinetic > 0.0 && work > 0.0);
        assert!((e.kinetic_energy - factor * kinetic).abs() < 1e-12 * factor * kinetic, "{f:?}: {e:?} vs {kinetic}");
        assert!((e.gravity_work - factor * work).abs() < 1e-12 * factor * work, "{f:?}: {e:?} vs {work}");
        // The block's mass as the particles carry it: ρ A per metre, ρ ∫ r dA per radian.
        let mass: f64 = p.mass.iter().sum();
        let expect = match f {
            FormulationKind::PlaneStrain => 1000.0 * 0.4 * 0.6,
            FormulationKind::Axisymmetric => 1000.0 * 0.5 * (1.0 - 0.36) * 0.6,
        };
        assert!((mass - expect).abs() < 1e-9 * expect, "{f:?}: mass {mass} vs {expect}");
    }
}

#[test]
fn results_do_not_depend_on_thread_count_and_checkpoints_resume_bit_for_bit() {
    for s in ALL_SHAPES {
        let mut cfg = block(FormulationKind::Axisymmetric, s, [0.0, -9.81], [0.2, 0.0]);
        cfg.boundaries.bottom = BoundaryCondition::friction(0.3);
        cfg.bodies[0].set_rectangle([0.0, 0.0], [1.0, 1.2]);
        // Runs stop at output times (here 0.05 and 0.1); checkpoints are written there.
        let run = |threads: usize| {
            let mut sim = Simulation::new(cfg.clone(), threads).unwrap();
            sim.advance(0.05, u64::MAX).unwrap();
            sim.advance(0.1, u64::MAX).unwrap();
            sim
        };
        let a = run(1);
        let b = run(2);
        assert_eq!(a.particles().position, b.particles().position, "{s:?}");
        assert_eq!(a.particles().stress, b.particles().stress, "{s:?}");

        let mut half = Simulation::new(cfg.clone(), 2).unwrap();
        half.advance(0.05, u64::MAX).unwrap();
        let bytes = half.to_bytes().unwrap();
        let mut resumed = Simulation::from_bytes(&bytes, 1).unwrap();
        resumed.advance(0.1, u64::MAX).unwrap();
        assert_eq!(resumed.steps(), a.steps());
        assert_eq!(resumed.particles().position, a.particles().position, "{s:?}");
        assert_eq!(resumed.particles().velocity, a.particles().velocity, "{s:?}");
        assert_eq!(resumed.particles().stress, a.particles().stress, "{s:?}");
    }
}

#[test]
fn a_particle_leaving_the_grid_stops_the_run_with_a_message() {
    let mut cfg = block(FormulationKind::PlaneStrain, ShapeFunctionKind::Linear, [0.0, 0.0], [20.0, 0.0]);
    cfg.simulation.time_step = 1e-3;
    let mut sim = Simulation::new(cfg, 1).unwrap();
    let err = sim.advance(1.0, u64::MAX).unwrap_err();
    assert!(err.message.contains("left the grid"), "{err}");
    // Further calls report the same failure instead of stepping a broken state.
    assert_eq!(sim.advance(2.0, 10).unwrap_err(), err);
}
