//! Micro-benchmarks of the engine's kernels (Criterion): `cargo bench -p axmpm-core`.
//!
//! - `stencil/*`: one particle's weights and gradients, per interpolation scheme;
//! - `material/*`: one stress update, per constitutive model;
//! - `step/*`: one full explicit step of a 20,000-particle block, per scheme (axisymmetric).

use std::collections::BTreeMap;
use std::hint::black_box;

use axmpm_core::config::*;
use axmpm_core::grid::GridGeometry;
use axmpm_core::material::{Kinematics, LinearElastic, Material, MohrCoulomb, NeoHookean};
use axmpm_core::particles::Particles;
use axmpm_core::interpolation::*;
use axmpm_core::Simulation;
use criterion::{criterion_group, criterion_main, Criterion};

fn particles_in_block(n: usize, h: f64) -> Particles {
    let mut p = Particles::default();
    let spacing = 0.5 * h;
    for j in 0..n {
        for i in 0..n {
            let x = [h + (i as f64 + 0.5) * spacing, h + (j as f64 + 0.5) * spacing];
            p.push(x, [0.0; 2], 1.0, spacing * spacing, [0.5 * spacing; 2], [0.0; 4], 0);
            p.corners.push(Particles::rectangle_corners(x, [0.5 * spacing; 2]));
        }
    }
    p
}

fn bench_stencil<S: ShapeFunction>(c: &mut Criterion, grid: &GridGeometry, particles: &Particles) {
    let mut st = Stencil::default();
    let n = particles.len();
    let mut p = 0;
    c.bench_function(&format!("stencil/{}", S::NAME), |b| {
        b.iter(|| {
            p = (p + 1) % n;
            S::stencil(grid, particles, black_box(p), true, &mut st);
            black_box(st.weight[0])
        })
    });
}

fn stencils(c: &mut Criterion) {
    let h = 0.001;
    let grid = GridGeometry::new([0.0, 0.0], [0.2, 0.2], h);
    let particles = particles_in_block(200, h);
    bench_stencil::<Linear>(c, &grid, &particles);
    bench_stencil::<UGimp>(c, &grid, &particles);
    bench_stencil::<CpGimp>(c, &grid, &particles);
    bench_stencil::<Cpdi2>(c, &grid, &particles);
}

fn bench_material(c: &mut Criterion, name: &str, m: &dyn Material, stress0: [f64; 4]) {
    let k = Kinematics {
        velocity_gradient: [-1e-3, 2e-4, 1e-4, 5e-4, -2e-4],
        deformation_gradient: [0.99, 0.01, 0.0, 1.005, 0.998],
        jacobian: 0.99 * 1.005 * 0.998,
        cell_field: [0.0; 2],
        dt: 1.0,
    };
    let mut state = [0.0; 2];
    c.bench_function(&format!("material/{name}"), |b| {
        b.iter(|| {
            let mut s = stress0;
            m.update_stress(&mut s, &mut state[..m.state_names().len()], black_box(&k));
            black_box(s)
        })
    });
}

fn materials(c: &mut Criterion) {
    bench_material(c, "linear_elastic", &LinearElastic::new(1550.0, 1e6, 0.3), [-1e3, -2e3, -1e3, 100.0]);
    bench_material(c, "neo_hookean", &NeoHookean::new(1550.0, 1e6, 0.3), [0.0; 4]);
    let mc = MohrCoulomb::new(1550.0, 1e6, 0.3, 25.0, 0.0, 0.0, 0.0);
    // A stress near the yield surface, so that the step returns plastically.
    bench_material(c, "mohr_coulomb", &mc, [-1e3, -2.4e3, -1e3, 0.0]);
}

fn block(shape: ShapeFunctionKind) -> Config {
    let mut materials = BTreeMap::new();
    materials.insert(
        "sand".to_string(),
        MaterialConfig::new(
            "mohr_coulomb",
            &[
                ("density", 1550.0.into()),
                ("youngs_modulus", 1e6.into()),
                ("poisson_ratio", 0.3.into()),
                ("friction_angle", 25.0.into()),
                ("dilation_angle", 0.0.into()),
                ("cohesion", 0.0.into()),
                ("tension_cutoff", 0.0.into()),
            ],
        ),
    );
    Config {
        simulation: SimulationConfig {
            formulation: FormulationKind::Axisymmetric,
            shape_function: shape,
            end_time: 1.0,
            output_interval: 1.0,
            gravity: [0.0, -9.81],
            gravity_ramp_time: 0.0,
            time_step: 0.0,
            cfl: 0.4,
            update_scheme: UpdateScheme::Musl,
            flip_fraction: 0.99,
            xpic_order: 1,
            experimental: false,
            damping: 0.0,
            volumetric_averaging: VolumetricAveraging::None,
            extra: Default::default(),
        },
        grid: GridConfig { origin: [0.0, 0.0], extent: [0.2, 0.1], cell_size: 0.001, follow: None, experimental: false },
        materials,
        bodies: vec![BodyConfig {
            initial_stress: InitialStress::Geostatic,
            k0: Some(0.58),
            ..BodyConfig::rectangle("sand", [0.0, 0.0], [0.05, 0.1])
        }],
        boundaries: BoundariesConfig {
            left: BoundaryCondition::ROLLER,
            right: BoundaryCondition::FREE,
            bottom: BoundaryCondition::friction(0.47),
            top: BoundaryCondition::FREE,
        },
        walls: vec![],
        rigid_bodies: vec![],
        drainage: Default::default(),
        surcharges: Vec::new(),
        extra: Default::default(),
    }
}

fn steps(c: &mut Criterion) {
    let mut group = c.benchmark_group("step");
    group.sample_size(20);
    for shape in [ShapeFunctionKind::Linear, ShapeFunctionKind::Ugimp, ShapeFunctionKind::Cpgimp, ShapeFunctionKind::Cpdi2] {
        let mut sim = Simulation::new(block(shape), 1).unwrap();
        group.throughput(criterion::Throughput::Elements(sim.particles().len() as u64));
        group.bench_function(format!("{shape:?}").to_lowercase(), |b| b.iter(|| sim.advance(1e9, 1).unwrap()));
    }
    group.finish();
}

criterion_group!(benches, stencils, materials, steps);
criterion_main!(benches);
