//! Head-to-head bench: every registered strategy on every source scene over a short fixed window of
//! simulated time in which adaptivity is active (the cloth is in contact and folding), starting
//! from a stored mid-drape state: the static 5x5 run of the scene taken to mid-drape once, in the
//! bench's setup (all strategies start from the same union-jack 5x5 mesh, so the state applies to
//! each). `BenchmarkId::new(strategy, scene)`. Criterion runs without its plotting feature.
//!
//! `cargo bench --bench strategies`

use adaptcloth::math::Vec3;
use adaptcloth::scene::{load_embedded, LoadedScene, SOURCE_SCENES};
use adaptcloth::sim::Simulation;
use adaptcloth::strategies::strategy_names;
use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use std::hint::black_box;
use std::time::Duration;

/// The simulated time (s) of a source scene's mid-drape state: after the first contact,
/// while the cloth is still folding over the obstacle.
fn mid_drape_time(scene: &str) -> f64 {
    match scene {
        "round_table" => 0.4,
        "bunny" => 0.25,
        _ => 0.3,
    }
}

/// The benchmarked window of simulated time (s).
const WINDOW: f64 = 0.005;

fn scene(name: &str, overrides: &[String]) -> LoadedScene {
    load_embedded(name, overrides)
        .expect("embedded scene")
        .expect("valid scene")
}

/// Positions and velocities (per vertex slot) of the static 5x5 run at `t_mid`.
fn mid_drape(name: &str, t_mid: f64) -> (Vec<Vec3>, Vec<Vec3>) {
    let loaded = scene(
        name,
        &[
            "cloth.resolution=5".into(),
            format!("time.duration={t_mid}"),
        ],
    );
    let mut sim = Simulation::new(&loaded).expect("scene builds");
    while !sim.finished() {
        sim.step().expect("the static run reaches mid-drape");
    }
    (sim.cloth.x.clone(), sim.cloth.v.clone())
}

/// A simulation of `strategy` on the 5x5 scene, set to the stored state at `t_mid`, that ends
/// `WINDOW` later. The dynamic step applies at once (no `dt_initial`: the cloth is in contact).
fn start(name: &str, strategy: &str, t_mid: f64, state: &(Vec<Vec3>, Vec<Vec3>)) -> Simulation {
    let loaded = scene(
        name,
        &[
            "cloth.resolution=5".into(),
            format!("adaptivity.strategy=\"{strategy}\""),
            format!("time.duration={}", t_mid + WINDOW),
            "time.dt_initial=0".into(),
        ],
    );
    let mut sim = Simulation::new(&loaded).expect("scene builds");
    sim.cloth.x.clone_from(&state.0);
    sim.cloth.v.clone_from(&state.1);
    sim.t = t_mid;
    sim
}

fn strategies(c: &mut Criterion) {
    let mut group = c.benchmark_group("strategies");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for name in SOURCE_SCENES {
        let t_mid = mid_drape_time(name);
        let state = mid_drape(name, t_mid);
        for &strategy in strategy_names() {
            group.bench_with_input(BenchmarkId::new(strategy, name), &state, |b, state| {
                b.iter_batched(
                    || start(name, strategy, t_mid, state),
                    |mut sim| {
                        while !sim.finished() {
                            sim.step().expect("step");
                        }
                        black_box(sim.cloth.mesh.vertex_count())
                    },
                    BatchSize::LargeInput,
                )
            });
        }
    }
    group.finish();
}

criterion_group!(benches, strategies);
criterion_main!(benches);
