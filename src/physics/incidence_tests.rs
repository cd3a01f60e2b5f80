//! Tests of the per-slot lists and of the parallel sweeps they serve.

use super::*;
use crate::math::Real;
use crate::mesh::union_jack;
use crate::physics::{Forces, Material, SpringMode};
use crate::testing::{built, random_state};

/// Every element is listed at each of its slots exactly once, in increasing index.
#[test]
fn each_slot_lists_its_elements_once_in_increasing_order() {
    let mesh = union_jack(7, 5, 1.0, 1.0);
    let model = built(&mesh, &Material::default(), &Forces::default());
    let (springs, bends) = (model.springs(), model.bends());
    let slots = mesh.vertex_slots();
    let mut incidence = Incidence::default();
    incidence.rebuild(slots, springs, bends);
    let mut seen_springs = vec![0; springs.len()];
    let mut seen_bends = vec![0; bends.len()];
    for i in 0..slots {
        let at: Vec<SpringEnd> = incidence.springs_at(i).collect();
        assert!(at.windows(2).all(|w| w[0].j < w[1].j), "slot {i}");
        for end in at {
            let slot = if end.second {
                springs.b[end.j]
            } else {
                springs.a[end.j]
            };
            assert_eq!(slot as usize, i);
            seen_springs[end.j] += 1;
        }
        let at: Vec<BendCorner> = incidence.bends_at(i).collect();
        assert!(at.windows(2).all(|w| w[0].e < w[1].e), "slot {i}");
        for c in at {
            assert_eq!(bends.v[c.e][c.k] as usize, i);
            seen_bends[c.e] += 1;
        }
    }
    assert!(seen_springs.iter().all(|&n| n == 2));
    assert!(seen_bends.iter().all(|&n| n == 4));
}

/// A model above the threshold evaluates its forces (every force on, springs both ways) with
/// the parallel gather: the same bits as the serial sweep, in a pool of one thread or of four.
#[test]
fn parallel_forces_equal_the_serial_sweep_bit_for_bit_at_any_thread_count() {
    let mesh = union_jack(50, 50, 1.0, 1.0);
    assert!(mesh.vertex_slots() >= PARALLEL_MIN_SLOTS);
    let material = Material {
        springs: SpringMode::Both,
        ..Material::default()
    };
    let model = built(&mesh, &material, &Forces::default());
    let (x, v) = random_state(&mesh, 7, 0.01);
    let mut serial = vec![Vec3::zeros(); x.len()];
    model.serial().forces(&x, &v, &mut serial);
    let largest: Real = serial.iter().map(|f| f.norm()).fold(0.0, Real::max);
    assert!(largest > 0.0);
    for threads in [1, 4] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a pool");
        let mut parallel = vec![Vec3::zeros(); x.len()];
        pool.install(|| model.forces(&x, &v, &mut parallel));
        assert!(parallel == serial, "{threads} thread(s)");
    }
}

/// The items of a parallel sweep are the serial sweep's, whatever the chunking.
#[test]
fn for_each_indexed_visits_every_index_once() {
    for n in [0, 1, CHUNK - 1, CHUNK, 3 * CHUNK + 5] {
        let mut out = vec![usize::MAX; n];
        for_each_indexed(&mut out, true, |i, o| *o = i * i);
        assert!(out.iter().enumerate().all(|(i, &o)| o == i * i), "{n}");
    }
}
