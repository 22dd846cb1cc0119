//! Reactions of the grid faces (`Simulation::reactions`): the force the material exerts on a
//! constraint, from the momentum its corrections of v⁺ remove, Σ m_i (v⁺_before − v⁺_after),
//! over the elapsed time, × 2π in axisymmetry.

mod common;
use axmpm_core::config::*;
use axmpm_core::geometry::{Rectangle, Region};
use axmpm_core::Simulation;
use common::*;

const RHO: f64 = 1000.0;
const G: f64 = 9.81;


/// A 0.3 m × 0.3 m elastic block standing on the bottom face of a grid of 0.05 m cells,
/// on the axis (axisymmetric) or in the middle of the grid (plane strain).
fn block_on_base(formulation: FormulationKind, shape: ShapeFunctionKind, base: BoundaryCondition) -> (Config, Rectangle) {
    let mut cfg = block(formulation, shape, [0.0, -G], [0.0, 0.0]);
    cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [1.0, 0.6], cell_size: 0.05, follow: None, experimental: false };
    let region = match formulation {
        FormulationKind::Axisymmetric => Rectangle { min: [0.0, 0.0], max: [0.3, 0.3] },
        FormulationKind::PlaneStrain => Rectangle { min: [0.35, 0.0], max: [0.65, 0.3] },
    };
    cfg.bodies[0].set_rectangle(region.min, region.max);
    cfg.boundaries.bottom = base;
    (cfg, region)
}

/// Weight of the block: ρ g A per metre (plane strain), 2π ρ g ∫ r dA (axisymmetric).
fn weight(formulation: FormulationKind, region: &Rectangle) -> f64 {
    match formulation {
        FormulationKind::PlaneStrain => RHO * G * region.area(),
        FormulationKind::Axisymmetric => 2.0 * std::f64::consts::PI * RHO * G * region.radial_moment(),
    }
}

fn force<'a>(reactions: &'a [(String, [f64; 2])], name: &str) -> [f64; 2] {
    reactions.iter().find(|(n, _)| n == name).unwrap_or_else(|| panic!("no reaction {name} in {reactions:?}")).1
}

/// Loaded slowly (gravity ramped over 0.3 s, several periods of the block's vertical mode) and
/// then left at rest, the block presses on its base with its weight: the mean base reaction
/// over 1 s is −W within 0.2 % (what is left is the momentum of the small residual
/// oscillation, ≲ 2 M v / T), and there is no net horizontal force. FLIP 0.99 (the scenario
/// default): with pure FLIP the start-of-step correction, which particle velocities never see,
/// keeps a velocity pattern alive at the base that biases the v⁺ reaction by up to ~1 %.
#[test]
fn a_block_at_rest_presses_on_its_base_with_its_weight() {
    for formulation in ALL_FORMULATIONS {
        for (shape, base) in [
            (ShapeFunctionKind::Linear, BoundaryCondition::FIXED),
            (ShapeFunctionKind::Linear, BoundaryCondition::ROLLER),
            (ShapeFunctionKind::Cpgimp, BoundaryCondition::FIXED),
        ] {
            let (mut cfg, region) = block_on_base(formulation, shape, base);
            cfg.simulation.gravity_ramp_time = 0.3;
            cfg.simulation.flip_fraction = 0.99;
            let mut sim = Simulation::new(cfg, 1).unwrap();
            assert_eq!(sim.reaction_names(), ["bottom"]);
            sim.advance(0.5, u64::MAX).unwrap();
            let _ = sim.reactions(); // the loading phase
            sim.advance(1.5, u64::MAX).unwrap();
            let reactions = sim.reactions();
            let w = weight(formulation, &region);
            let f = force(&reactions, "bottom");
            eprintln!("{formulation:?} {shape:?} {:?}: base force {f:?}, weight {w}", base.condition);
            assert!((f[1] + w).abs() < 2e-3 * w, "{formulation:?} {shape:?}: base force {} vs weight {w}", f[1]);
            // In axisymmetry force_x sums the radial forces over the circumference (the outward
            // push of the base's friction on a bulging body; zero as a vector), so only plane
            // strain has a net horizontal force to check.
            if formulation == FormulationKind::PlaneStrain {
                assert!(f[0].abs() < 2e-3 * w, "{shape:?}: horizontal base force {}", f[0]);
            }
            // Taken: nothing more until the next step.
            assert_eq!(force(&sim.reactions(), "bottom"), [0.0, 0.0]);
        }
    }
}

/// Impulse balance of a block falling onto the base and bouncing: with PIC velocities
/// (flip_fraction 0) the particle momentum after each step is Σ_i m_i v⁺_i of the constrained
/// v⁺, so its change is exactly the gravity impulse minus the impulse the base took,
/// p(T) − p(0) = M g T − J (each × 2π in axisymmetry). (With FLIP, particle velocities keep
/// what the start-of-step constraint removed from the grid, so the balance holds only as the
/// block comes to rest.)
#[test]
fn momentum_lost_by_a_falling_block_is_the_impulse_on_the_base() {
    for formulation in ALL_FORMULATIONS {
        for (shape, base) in [
            (ShapeFunctionKind::Linear, BoundaryCondition::FIXED),
            (ShapeFunctionKind::Cpdi2, BoundaryCondition::friction(0.3)),
        ] {
            let (mut cfg, region) = block_on_base(formulation, shape, base);
            let lifted = Rectangle { min: [region.min[0], 0.1], max: [region.max[0], 0.4] };
            cfg.bodies[0].set_rectangle(lifted.min, lifted.max);
            cfg.bodies[0].velocity = [0.5, -1.0];
            cfg.simulation.flip_fraction = 0.0;
            cfg.boundaries.left = BoundaryCondition::FREE;
            let mut sim = Simulation::new(cfg, 1).unwrap();
            let total = sim.total_factor();
            let momentum = |sim: &Simulation| {
                let p = sim.particles();
                let mut m = [0.0; 2];
                for i in 0..p.len() {
                    m[0] += total * p.mass[i] * p.velocity[i][0];
                    m[1] += total * p.mass[i] * p.velocity[i][1];
                }
                m
            };
            let mass: f64 = total * sim.particles().mass.iter().sum::<f64>();
            let p0 = momentum(&sim);
            let t = 0.3;
            sim.advance(t, u64::MAX).unwrap();
            let p1 = momentum(&sim);
            let f = force(&sim.reactions(), "bottom");
            let impulse = [f[0] * t, f[1] * t];
            let scale = mass * G * t;
            eprintln!("{formulation:?} {shape:?}: impulse on the base {impulse:?}, M g T = {scale}");
            assert!(impulse[1] < -0.5 * scale, "{formulation:?}: the block did not land ({impulse:?})");
            assert!((p1[1] - p0[1] - (-mass * G * t - impulse[1])).abs() < 1e-9 * scale, "{formulation:?} {shape:?} y");
            // Radial momentum is not conserved in axisymmetry (hoop forces).
            if formulation == FormulationKind::PlaneStrain {
                assert!((p1[0] - p0[0] + impulse[0]).abs() < 1e-9 * scale, "{shape:?} x");
            }
        }
    }
}

/// Walls report under their index in the scenario; the axis is never reported.
#[test]
fn walls_are_named_by_their_index_and_the_axis_is_not_reported() {
    let (mut cfg, _) = block_on_base(FormulationKind::Axisymmetric, ShapeFunctionKind::Linear, BoundaryCondition::FIXED);
    let wall = |position: f64| WallConfig {
        axis: Axis::X,
        position,
        material_side: Side::Negative,
        condition: Condition::Roller,
        coefficient: 0.0,
        removal_time: None,
    };
    cfg.walls = vec![wall(0.3), wall(0.9)];
    cfg.boundaries.top = BoundaryCondition::ROLLER;
    let mut sim = Simulation::new(cfg, 1).unwrap();
    assert_eq!(sim.reaction_names(), ["bottom", "top", "wall_0", "wall_1"]);
    sim.advance(0.2, u64::MAX).unwrap();
    let reactions = sim.reactions();
    let names: Vec<&str> = reactions.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["bottom", "top", "wall_0", "wall_1"]);
    // The block bulges against the wall at its side: pushed outwards (+r).
    assert!(force(&reactions, "wall_0")[0] > 0.0, "{reactions:?}");
    assert_eq!(force(&reactions, "wall_1"), [0.0, 0.0]);
}
