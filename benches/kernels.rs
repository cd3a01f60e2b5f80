//! Kernel benches: one force evaluation and one integrator step on union-jack grids.
//!
//! Grids of 17x17, 65x65 and 257x257 vertices over 1 m x 1 m, stretched by 1 % and slightly
//! perturbed out of plane so every spring is in tension and every bending element is bent.
//! Groups: `forces` (all forces on, per vertex), `springs` (springs and their damping only, per
//! spring), `bending` (bending and its damping only, per element), `rk4` and `symplectic_euler`
//! (one step, all forces on, per vertex).

use adaptcloth::math::{Real, Vec3};
use adaptcloth::mesh::{union_jack, Mesh};
use adaptcloth::physics::{integrator_named, ForceModel, Forces, Material};
use adaptcloth::scene::TimeSpec;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::Duration;

const SIZES: [usize; 3] = [17, 65, 257];

/// Positions (m) of a stretched, slightly perturbed grid and small random velocities (m/s).
fn state(mesh: &Mesh, seed: u64) -> (Vec<Vec3>, Vec<Vec3>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let h = 1.0 / (mesh.vertex_count() as Real).sqrt();
    let mut x = vec![Vec3::zeros(); mesh.vertex_slots()];
    let mut v = vec![Vec3::zeros(); mesh.vertex_slots()];
    for id in mesh.vertices() {
        let r = mesh.rest(id);
        let i = id.0 as usize;
        x[i] = Vec3::new(
            1.01 * r.x + 0.05 * h * rng.random_range(-1.0..1.0),
            1.01 * r.y + 0.05 * h * rng.random_range(-1.0..1.0),
            0.1 * h * rng.random_range(-1.0..1.0),
        );
        v[i] = Vec3::new(
            rng.random_range(-0.01..0.01),
            rng.random_range(-0.01..0.01),
            rng.random_range(-0.01..0.01),
        );
    }
    (x, v)
}

fn model(mesh: &Mesh, forces: &Forces) -> ForceModel {
    let mut m = ForceModel::new(&Material::default(), forces);
    m.rebuild(mesh);
    m
}

fn only(springs: bool, bending: bool) -> Forces {
    Forces {
        springs,
        spring_damping: springs,
        bending,
        bending_damping: bending,
        gravity: false,
        drag: false,
        ..Forces::default()
    }
}

fn force_kernels(c: &mut Criterion) {
    let mut group = c.benchmark_group("force_kernels");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for n in SIZES {
        let mesh = union_jack(n, n, 1.0, 1.0);
        let (x, v) = state(&mesh, 1);
        let mut f = vec![Vec3::zeros(); x.len()];
        let cases = [
            ("forces", Forces::default()),
            ("springs", only(true, false)),
            ("bending", only(false, true)),
        ];
        for (name, forces) in cases {
            let m = model(&mesh, &forces);
            let elements = match name {
                "springs" => m.springs().len(),
                "bending" => m.bends().len(),
                _ => mesh.vertex_count(),
            };
            group.throughput(Throughput::Elements(elements as u64));
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| m.forces(black_box(&x), black_box(&v), black_box(&mut f)))
            });
        }
    }
    group.finish();
}

fn integrator_steps(c: &mut Criterion) {
    let mut group = c.benchmark_group("integrator_steps");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for n in SIZES {
        let mesh = union_jack(n, n, 1.0, 1.0);
        let m = model(&mesh, &Forces::default());
        // The scene's default safety factor: the spring damping (alpha = 0.01) needs it, a larger
        // factor lets the state diverge and the bench would time NaN arithmetic.
        let dt = m.stable_step(TimeSpec::default().beta);
        for name in ["rk4", "symplectic_euler"] {
            let mut integrator = integrator_named(name).expect("registered integrator");
            let (mut x, mut v) = state(&mesh, 2);
            group.throughput(Throughput::Elements(mesh.vertex_count() as u64));
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| {
                    integrator.step(black_box(&m), 0.0, dt, black_box(&mut x), &mut v);
                })
            });
            assert!(
                x.iter().chain(&v).all(|p| p.iter().all(|c| c.is_finite())),
                "{name} diverged on the {n}x{n} grid"
            );
        }
    }
    group.finish();
}

criterion_group!(benches, force_kernels, integrator_steps);
criterion_main!(benches);
