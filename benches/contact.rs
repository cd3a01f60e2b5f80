//! Contact bench: the cost of one step's collision pass on a 65x65 cloth draped over the bunny,
//! with vertex contact only (`collision.mode = "vertex"`) and with face contact (the bunny scene's),
//! plus the surface measure (`max_surface_penetration`) that every metrics row takes.
//!
//! Set-up: the embedded bunny scene at 65x65 (8,192 faces), implicit Euler at a fixed 2 ms, run
//! for 0.3 s under the scene's face contact so the cloth rests on the bunny. Each iteration starts from that
//! state moved by one free step (`x + (v + g dt) dt`) and runs the pass on a copy.

use adaptcloth::collision::{ContactParams, FaceScratch, Obstacles};
use adaptcloth::math::{Real, Vec3};
use adaptcloth::scene;
use adaptcloth::sim::Simulation;
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::time::Duration;

const DT: Real = 0.002;

/// The settled 65x65 bunny drape: (positions at the step's start, positions after a free step,
/// velocities, inverse masses, faces as vertex slots, cloth friction, vertex-only obstacles,
/// face-contact obstacles).
struct Drape {
    x_start: Vec<Vec3>,
    x_free: Vec<Vec3>,
    v: Vec<Vec3>,
    inv_mass: Vec<Real>,
    faces: Vec<[usize; 3]>,
    mu: Real,
    vertex_only: Obstacles,
    with_faces: Obstacles,
}

fn drape() -> Drape {
    let overrides: Vec<String> = [
        "cloth.resolution=65",
        "integrator.name=\"implicit_euler\"",
        "time.mode=\"fixed\"",
        "time.dt=0.002",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let loaded = scene::load_embedded("bunny", &overrides)
        .expect("the bunny scene loads")
        .expect("the bunny scene is embedded");
    let mut sim = Simulation::new(&loaded).expect("the bunny scene builds");
    while sim.t < 0.3 {
        sim.step().expect("the drape runs");
    }
    let g = Vec3::from(loaded.scene.forces.g);
    let inv_mass = sim.cloth.model.inv_mass().to_vec();
    let x_start = sim.cloth.x.clone();
    let v = sim.cloth.v.clone();
    let x_free = x_start
        .iter()
        .zip(&v)
        .zip(&inv_mass)
        .map(|((x, v), &w)| if w > 0.0 { x + (v + g * DT) * DT } else { *x })
        .collect();
    let contact = |faces| {
        let params = ContactParams {
            faces,
            ..ContactParams::from(&loaded.scene.collision)
        };
        Obstacles::build(&loaded.obstacles(), &params).expect("the bunny builds")
    };
    Drape {
        x_start,
        x_free,
        v,
        inv_mass,
        faces: sim.cloth.mesh.face_vertex_slots().collect(),
        mu: loaded.scene.material.mu,
        vertex_only: contact(false),
        with_faces: contact(true),
    }
}

fn contact(c: &mut Criterion) {
    let d = drape();
    let mut group = c.benchmark_group("contact_bunny_65");
    group.measurement_time(Duration::from_secs(5));
    let mut scratch = FaceScratch::default();
    for (name, obstacles) in [("vertex", &d.vertex_only), ("face", &d.with_faces)] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let (mut x, mut v) = (d.x_free.clone(), d.v.clone());
                let mut n = obstacles
                    .respond(&d.x_start, &mut x, &mut v, &d.inv_mass, d.mu, DT)
                    .contacts;
                n += obstacles
                    .respond_faces(
                        &d.faces,
                        Some(&d.x_start),
                        &mut x,
                        &mut v,
                        &d.inv_mass,
                        d.mu,
                        &mut scratch,
                    )
                    .contacts;
                black_box((n, x, v))
            })
        });
    }
    group.bench_function("surface_measure", |b| {
        b.iter(|| {
            black_box(
                d.with_faces
                    .surface_penetration(&d.x_start, d.faces.iter().copied()),
            )
        })
    });
    group.finish();
}

criterion_group!(benches, contact);
criterion_main!(benches);
