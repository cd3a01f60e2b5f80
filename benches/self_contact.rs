//! Self-collision bench: the cost of one step's self-contact pass (`collision.self = true`) on
//! the bunny drape at 17x17, 33x33 and 65x65, against the cost of a whole step there.
//!
//! Set-up per resolution: the embedded bunny scene (self-collision on), implicit Euler at a fixed
//! 2 ms, run for 0.3 s so the cloth lies folded over the bunny. From that state moved by one free
//! step (`x + (v + g dt) dt`), the self-contact pass on a copy: `listed_N` with its pair list
//! kept from the previous iteration (as between small steps, when no vertex leaves the box it was
//! listed with), `new_N` from a new pass (tree built, pairs listed: as after a mesh change; a
//! step that only outgrows its list refits the tree instead). `step_N`: whole steps of the same
//! simulation from there on (it keeps draping, so the figure is of the next few hundred steps;
//! the duration is raised so it never ends).

use adaptcloth::collision::SelfContact;
use adaptcloth::math::{Real, Vec3};
use adaptcloth::scene;
use adaptcloth::sim::Simulation;
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::time::Duration;

const DT: Real = 0.002;

/// The bunny drape at `resolution`, 0.3 s in.
fn drape(resolution: usize) -> Simulation {
    let overrides: Vec<String> = [
        format!("cloth.resolution={resolution}"),
        "integrator.name=\"implicit_euler\"".into(),
        "time.mode=\"fixed\"".into(),
        format!("time.dt={DT}"),
        "time.duration=100".into(),
    ]
    .to_vec();
    let loaded = scene::load_embedded("bunny", &overrides)
        .expect("the bunny scene loads")
        .expect("the bunny scene is embedded");
    assert!(loaded.scene.collision.self_collision);
    let mut sim = Simulation::new(&loaded).expect("the bunny scene builds");
    while sim.t < 0.3 {
        sim.step().expect("the drape runs");
    }
    sim
}

fn self_contact(c: &mut Criterion) {
    let mut group = c.benchmark_group("self_contact_bunny");
    group.measurement_time(Duration::from_secs(5));
    group.sample_size(20);
    for n in [17, 33, 65] {
        let mut sim = drape(n);
        let cloth = &sim.cloth;
        let g = Vec3::from(sim.scene.forces.g);
        let inv_mass = cloth.model.inv_mass().to_vec();
        let x_start = cloth.x.clone();
        let x_free: Vec<Vec3> = x_start
            .iter()
            .zip(&cloth.v)
            .zip(&inv_mass)
            .map(|((x, v), &w)| if w > 0.0 { x + (v + g * DT) * DT } else { *x })
            .collect();
        let faces: Vec<[usize; 3]> = cloth.mesh.face_vertex_slots().collect();
        let rest = cloth.mesh.rest_slots().to_vec();
        let (mu, thickness) = (sim.scene.material.mu, sim.scene.collision.thickness);
        let mut kept = SelfContact::new(thickness);
        let pass = |contact: &mut SelfContact| {
            let (mut x, mut v) = (x_free.clone(), sim.cloth.v.clone());
            let stats = contact.respond(
                0,
                faces.iter().copied(),
                &rest,
                &x_start,
                &mut x,
                Some(&mut v),
                &inv_mass,
                mu,
                DT,
            );
            black_box((stats, x, v))
        };
        group.bench_function(format!("listed_{n}"), |b| b.iter(|| pass(&mut kept)));
        group.bench_function(format!("new_{n}"), |b| {
            b.iter(|| pass(&mut SelfContact::new(thickness)))
        });
        group.bench_function(format!("step_{n}"), |b| {
            b.iter(|| black_box(sim.step().expect("the drape runs")))
        });
    }
    group.finish();
}

criterion_group!(benches, self_contact);
criterion_main!(benches);
