//! Force-driven rigid bodies (`constraint/rigid_body.rs`, "Force-driven bodies"): exact free
//! flight, momentum conserved between the body and the material, thread-count and checkpoint
//! independence, the failure of a body that leaves the grid (the bodies' energy: tests/energy.rs).
mod common;

use axmpm_core::config::*;
use axmpm_core::Simulation;
use common::*;
use serde_json::json;

use common::{material_momentum as momentum, rigid_body_table as table};

/// A force-driven body's displacement X and integration velocity V (the body's momentum is M V).
fn body_state(sim: &Simulation, name: &str) -> ([f64; 2], [f64; 2]) {
    let d = sim.rigid_body_displacements().into_iter().find(|(n, _)| n == name).unwrap().1;
    let state = sim.rigid_body_states().into_iter().find(|(n, _)| n == name).unwrap().1;
    assert_eq!(state.displacement, d);
    (d, state.velocity)
}

/// A plate of mass M = 50 kg thrown at v0 under gravity g and a constant force F, far from
/// the block of material (no contact): after every output its displacement is
/// v0 t + ½ (F/M + g) t² and its velocity v0 + (F/M + g) t to round-off (10⁻¹² of the
/// distance travelled), whatever the steps (`advance` shortens the last ones to land on each
/// output time). Plane strain in x and y; axisymmetric in y only.
#[test]
fn free_flight_is_exact() {
    for formulation in ALL_FORMULATIONS {
        let axisymmetric = formulation == FormulationKind::Axisymmetric;
        let mut cfg = block(formulation, ShapeFunctionKind::Cpgimp, [0.0, -9.81], [0.0, 0.0]);
        cfg.bodies[0].set_rectangle([0.0, 0.0], [0.4, 0.2]);
        cfg.boundaries.bottom = BoundaryCondition::FIXED;
        let (v0, force) = if axisymmetric { ([0.0, 3.0], [0.0, 200.0]) } else { ([1.5, 3.0], [-60.0, 200.0]) };
        let mass = 50.0;
        cfg.rigid_bodies = vec![table(json!({"name": "plate", "shape": "rectangle", "min": [0.5, 1.0], "max": [0.7, 1.1],
                                               "mass": mass, "initial_velocity": v0,
                                               "force": [[0.0, force[0], force[1]]]}))];
        let mut sim = Simulation::new(cfg, 1).unwrap();
        let a = [force[0] / mass, force[1] / mass - 9.81];
        let mut steps = 0;
        for t in [0.0137, 0.05, 0.1, 0.2] {
            steps += sim.advance(t, u64::MAX).unwrap();
            let (d, v) = body_state(&sim, "plate");
            for c in 0..2 {
                let exact = v0[c] * t + 0.5 * a[c] * t * t;
                assert!((d[c] - exact).abs() <= 1e-12 * 0.5, "{formulation:?} t = {t}: d[{c}] {} vs {exact}", d[c]);
                let exact_v = v0[c] + a[c] * t;
                assert!((v[c] - exact_v).abs() <= 1e-12 * 5.0, "{formulation:?} t = {t}: v[{c}] {} vs {exact_v}", v[c]);
                // The reported velocity is the one over the last step: v at its middle.
                let last = sim.rigid_body_velocities()[0].1[c];
                assert!((last - exact_v).abs() <= 0.5 * a[c].abs() * sim.dt() * (1.0 + 1e-9) + 1e-12, "{last} vs {exact_v}");
                assert!(a[c] == 0.0 || (last - exact_v).abs() > 0.1 * a[c].abs() * sim.dt(), "{last} vs {exact_v}");
            }
        }
        assert!(steps > 50, "{steps}");
        // No contact: the reaction is zero.
        assert!(sim.reactions().iter().all(|(n, f)| n != "plate" || *f == [0.0, 0.0]));
    }
}

/// A force-driven plate (M = 20 kg per metre or whole ring, thrown down at 2 m/s onto the free
/// block, friction 0.3, no gravity, no other constraint) and the block exchange momentum: the
/// total M V + Σ m_p v_p stays what it was to round-off in every formulation
/// (axial only in axisymmetry: the hoop force takes radial momentum), scheme and FLIP fraction,
/// while the plate loses a good part of its speed to the block.
#[test]
fn momentum_is_conserved_between_a_force_driven_body_and_the_material() {
    {
        for formulation in ALL_FORMULATIONS {
            for shape in ALL_SHAPES {
                for flip in [0.0, 1.0] {
                    let mut cfg = block(formulation, shape, [0.0, 0.0], [0.0, 0.0]);
                    cfg.simulation.flip_fraction = flip;
                    let mass = 20.0;
                    let v0 = -2.0;
                    cfg.rigid_bodies = vec![table(json!({"name": "plate", "shape": "rectangle", "min": [0.6, 1.22],
                                                           "max": [1.0, 1.42], "mass": mass, "initial_velocity": [0.0, v0],
                                                           "friction": 0.3}))];
                    let mut sim = Simulation::new(cfg, 1).unwrap();
                    let total = |sim: &Simulation| {
                        let (p, v) = (momentum(sim), body_state(sim, "plate").1);
                        [p[0] + mass * v[0], p[1] + mass * v[1]]
                    };
                    let p0 = total(&sim);
                    sim.advance(0.1, u64::MAX).unwrap();
                    let p1 = total(&sim);
                    let soil = momentum(&sim);
                    let reaction = sim.reactions().into_iter().find(|(n, _)| n == "plate").unwrap().1;
                    let label = format!("{formulation:?} {shape:?} flip {flip}");
                    let v = body_state(&sim, "plate").1;
                    assert!(v[1] > 0.8 * v0, "{label}: the plate was not slowed by the block ({v:?})");
                    let block_mass = sim.total_factor() * sim.particles().mass.iter().sum::<f64>();
                    let scale = block_mass * v0.abs();
                    // The material alone balances its momentum against the reaction to 10⁻¹⁰ of
                    // its scale (the GIMP schemes' nodes lighter than the solver's threshold get
                    // no force: measured ≤ 5·10⁻¹¹, as with a prescribed body); the body takes
                    // exactly the opposite impulse, so the total changes by that imbalance alone.
                    let imbalance = soil[1] + reaction[1] * 0.1;
                    assert!((p1[1] - p0[1]).abs() < 1e-10 * scale, "{label}: y {p0:?} → {p1:?}");
                    assert!((p1[1] - p0[1] - imbalance).abs() < 1e-13 * scale, "{label}: body side {}", p1[1] - p0[1] - imbalance);
                    if formulation == FormulationKind::PlaneStrain {
                        assert!((p1[0] - p0[0]).abs() < 1e-10 * scale, "{label}: x {p0:?} → {p1:?}");
                    } else {
                        assert_eq!(v[0], 0.0, "{label}: a ring moves axially only");
                    }
                }
            }
        }
    }
}

/// A footing of mass M on a clay layer under a constant load and gravity (ramped), run to
/// t = 0.06 s in one go on one thread, on two threads, and paused at 0.025 s and resumed from
/// a checkpoint: the particles, the footing's displacement and velocity and the energy budget's
/// body work are the same bit for bit.
type FootingResult = (Vec<[f64; 2]>, Vec<[f64; 4]>, axmpm_core::constraint::rigid_body::RigidBodyState, [f64; 2], f64);

fn driven_footing(threads: usize, resume: bool) -> FootingResult {
    let mut cfg = clay_layer();
    cfg.simulation.gravity_ramp_time = 0.02;
    cfg.rigid_bodies = vec![table(json!({"name": "footing", "shape": "rectangle", "min": [0.0, 1.2], "max": [0.5, 1.4],
                                           "mass": 500.0, "force": [[0.0, 0.0, 0.0], [0.02, 0.0, -40e3]],
                                           "friction": "rough"}))];
    let mut sim = Simulation::new(cfg, threads).unwrap();
    sim.advance(0.025, u64::MAX).unwrap();
    if resume {
        let bytes = sim.to_bytes().unwrap();
        sim = Simulation::from_bytes(&bytes, threads).unwrap();
    }
    sim.advance(0.06, u64::MAX).unwrap();
    let state = sim.rigid_body_states()[0].1;
    let p = sim.particles();
    (p.position.clone(), p.stress.clone(), state, sim.rigid_body_velocities()[0].1, sim.energies().rigid_body_work)
}

#[test]
fn a_force_driven_body_does_not_depend_on_threads_or_on_a_checkpoint() {
    let reference = driven_footing(1, false);
    assert!(reference.2.displacement[1] < -1e-4, "the footing did not settle: {:?}", reference.2);
    let two = driven_footing(2, false);
    assert!(two == reference, "threads changed the result");
    let resumed = driven_footing(1, true);
    assert!(resumed == reference, "the checkpoint changed the result");
}

/// A force-driven body thrown sideways out of the grid ends the run as failed, naming the
/// body, the time and its velocity.
#[test]
fn a_force_driven_body_that_leaves_the_grid_fails_the_run() {
    let mut cfg = block(FormulationKind::PlaneStrain, ShapeFunctionKind::Linear, [0.0, 0.0], [0.0, 0.0]);
    cfg.rigid_bodies = vec![table(json!({"name": "hammer", "shape": "rectangle", "min": [1.5, 1.5], "max": [1.7, 1.7],
                                           "mass": 1.0, "initial_velocity": [2.0, 0.0]}))];
    let mut sim = Simulation::new(cfg, 1).unwrap();
    // The box's right side reaches x = 2 at t = 0.15 s.
    let failure = sim.advance(1.0, u64::MAX).err().expect("the body left the grid");
    assert!(failure.time > 0.15 && failure.time < 0.15 + 2.0 * sim.dt(), "{failure}");
    for part in ["rigid body 'hammer' left the grid at t = ", "moving at (2.000e0, 0.000e0) m/s", "grid.extent"] {
        assert!(failure.message.contains(part), "{part:?} not in {}", failure.message);
    }
    // The run stays failed.
    assert!(sim.advance(2.0, u64::MAX).is_err());
}
