//! The lane kernels give bit for bit the scalar formulas, on the CPU's fastest path and on the
//! portable one, for every force switch, partial last blocks and degenerate elements included;
//! the chunked sweep gives the same forces on any number of threads.

use super::*;
use crate::math::{Real, Vec3};
use crate::mesh::union_jack;
use crate::physics::chunks::Chunks;
use crate::physics::elements::{Bends, Springs};
use crate::physics::forces::bend_modes;
use crate::physics::{ForceModel, Forces, Material, SpringMode};
use crate::testing::{built, in_pool, random_state};
use proptest::prelude::*;
use std::panic::AssertUnwindSafe;

/// The scalar springs, one element after the other (the formula of [`spring_forces`]).
fn scalar_springs(
    sp: &Springs,
    both: bool,
    switches: (bool, bool),
    x: &[Vec3],
    v: &[Vec3],
) -> Vec<Vec3> {
    let mut f = vec![Vec3::zeros(); x.len()];
    for j in 0..sp.len() {
        let (ia, ib) = (sp.a[j] as usize, sp.b[j] as usize);
        let d = x[ib] - x[ia];
        let len2 = d.norm_squared();
        if len2 <= 0.0 {
            continue;
        }
        let mut c = 0.0;
        if switches.0 {
            let len = len2.sqrt();
            let s = len - sp.rest_length[j];
            c += sp.k[j] * if both { s } else { s.max(0.0) } / len;
        }
        if switches.1 {
            c += sp.kd[j] * (v[ib] - v[ia]).dot(&d) / len2;
        }
        f[ia] += d * c;
        f[ib] -= d * c;
    }
    f
}

/// The scalar bending, one element after the other, from [`bend_modes`].
fn scalar_bends(
    b: &Bends,
    k: (Real, Real),
    switches: (bool, bool),
    x: &[Vec3],
    v: &[Vec3],
) -> Vec<Vec3> {
    let mut f = vec![Vec3::zeros(); x.len()];
    for ids in &b.v {
        let ids = ids.map(|i| i as usize);
        let Some(u) = bend_modes(x[ids[0]], x[ids[1]], x[ids[2]], x[ids[3]]) else {
            continue;
        };
        let mut c = 0.0;
        if switches.0 {
            c += k.0 * u.elastic_scale * u.sin_half;
        }
        if switches.1 {
            let uv = u.u[0].dot(&v[ids[0]])
                + u.u[1].dot(&v[ids[1]])
                + u.u[2].dot(&v[ids[2]])
                + u.u[3].dot(&v[ids[3]]);
            c -= k.1 * u.damping_scale * uv;
        }
        for m in 0..4 {
            f[ids[m]] += u.u[m] * c;
        }
    }
    f
}

fn bits(f: &[Vec3]) -> Vec<[u64; 3]> {
    f.iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

/// Runs a kernel on a zeroed force buffer.
fn run(n: usize, kernel: impl FnOnce(&mut [Vec3])) -> Vec<Vec3> {
    let mut f = vec![Vec3::zeros(); n];
    kernel(&mut f);
    f
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn lane_kernels_match_the_scalar_formulas_bit_for_bit(
        nx in 3usize..9,
        ny in 3usize..8,
        seed in 0u64..1000,
        amp in prop_oneof![Just(1e-3), Just(0.05), Just(0.4)],
        collapse in 0usize..64,
        elastic in any::<bool>(),
        damp in any::<bool>(),
        both in any::<bool>(),
    ) {
        // Every switch combination that evaluates something (damping alone when elastic is off).
        let damp = damp || !elastic;
        let mesh = union_jack(nx, ny, 1.0, 0.8);
        let material = Material {
            springs: if both { SpringMode::Both } else { SpringMode::Tension },
            ..Material::default()
        };
        let (mut x, v) = random_state(&mesh, seed, amp);
        // Coincident ends and collapsed triangles: the elements with no force.
        let (i, j) = (collapse % x.len(), (collapse + 1) % x.len());
        x[j] = x[i];
        let mut springs = Springs::default();
        springs.rebuild(&mesh, &material);
        let mut bends = Bends::default();
        bends.rebuild(&mesh);
        let k = (material.k_b, material.k_bd);
        let n = x.len();
        let kb = BendConstants { elastic: k.0, damping: k.1 };

        let want = scalar_springs(&springs, both, (elastic, damp), &x, &v);
        let (fast, portable) = match (elastic, damp, both) {
            (true, true, false) => (
                run(n, |f| spring_forces::<true, true, false>(&springs, 0..springs.len(), &x, &v, Window::whole(f))),
                run(n, |f| spring_blocks::<true, true, false>(&springs, 0..springs.len(), &x, &v, Window::whole(f))),
            ),
            (true, true, true) => (
                run(n, |f| spring_forces::<true, true, true>(&springs, 0..springs.len(), &x, &v, Window::whole(f))),
                run(n, |f| spring_blocks::<true, true, true>(&springs, 0..springs.len(), &x, &v, Window::whole(f))),
            ),
            (true, false, false) => (
                run(n, |f| spring_forces::<true, false, false>(&springs, 0..springs.len(), &x, &v, Window::whole(f))),
                run(n, |f| spring_blocks::<true, false, false>(&springs, 0..springs.len(), &x, &v, Window::whole(f))),
            ),
            (true, false, true) => (
                run(n, |f| spring_forces::<true, false, true>(&springs, 0..springs.len(), &x, &v, Window::whole(f))),
                run(n, |f| spring_blocks::<true, false, true>(&springs, 0..springs.len(), &x, &v, Window::whole(f))),
            ),
            (false, _, _) => (
                run(n, |f| spring_forces::<false, true, false>(&springs, 0..springs.len(), &x, &v, Window::whole(f))),
                run(n, |f| spring_blocks::<false, true, false>(&springs, 0..springs.len(), &x, &v, Window::whole(f))),
            ),
        };
        prop_assert_eq!(bits(&fast), bits(&want));
        prop_assert_eq!(bits(&portable), bits(&want));

        let want = scalar_bends(&bends, k, (elastic, damp), &x, &v);
        let (fast, portable) = match (elastic, damp) {
            (true, true) => (
                run(n, |f| bend_forces::<true, true>(&bends, 0..bends.len(), kb, &x, &v, Window::whole(f))),
                run(n, |f| bend_blocks::<true, true>(&bends, 0..bends.len(), kb, &x, &v, Window::whole(f))),
            ),
            (true, false) => (
                run(n, |f| bend_forces::<true, false>(&bends, 0..bends.len(), kb, &x, &v, Window::whole(f))),
                run(n, |f| bend_blocks::<true, false>(&bends, 0..bends.len(), kb, &x, &v, Window::whole(f))),
            ),
            (false, _) => (
                run(n, |f| bend_forces::<false, true>(&bends, 0..bends.len(), kb, &x, &v, Window::whole(f))),
                run(n, |f| bend_blocks::<false, true>(&bends, 0..bends.len(), kb, &x, &v, Window::whole(f))),
            ),
        };
        prop_assert!(want.iter().any(|p| p.norm() > 0.0), "no bending force to compare");
        prop_assert_eq!(bits(&fast), bits(&want));
        prop_assert_eq!(bits(&portable), bits(&want));
    }
}

/// The forces of `model` computed in a pool of `threads` threads.
fn forces_on(threads: usize, model: &ForceModel, x: &[Vec3], v: &[Vec3]) -> Vec<Vec3> {
    let mut f = vec![Vec3::zeros(); x.len()];
    in_pool(threads, || model.internal_forces(x, v, &mut f));
    f
}

#[test]
fn chunked_sweeps_give_the_same_forces_on_any_number_of_threads() {
    let mesh = union_jack(65, 49, 1.0, 0.8);
    let material = Material::default();
    let model = built(&mesh, &material, &Forces::default());
    let chunks = Chunks::build(model.springs(), model.bends(), mesh.vertex_slots());
    assert!(!chunks.is_empty(), "a 65x49 grid is swept in chunks");
    let (x, v) = random_state(&mesh, 3, 0.02);
    let one = forces_on(1, &model, &x, &v);
    for threads in [2, 4] {
        assert_eq!(
            bits(&forces_on(threads, &model, &x, &v)),
            bits(&one),
            "{threads} threads"
        );
    }
    // The chunks only change the order of each vertex's sum: round-off from the one-piece sweep.
    let springs = scalar_springs(model.springs(), false, (true, true), &x, &v);
    let bends = scalar_bends(
        model.bends(),
        (material.k_b, material.k_bd),
        (true, true),
        &x,
        &v,
    );
    let scale: Real = one.iter().map(|f| f.norm()).fold(0.0, Real::max);
    let mut reordered = 0;
    for ((f, s), b) in one.iter().zip(&springs).zip(&bends) {
        let err = (f - (s + b)).norm();
        assert!(err <= 1e-13 * scale, "{f} against {}", s + b);
        reordered += usize::from(err > 0.0);
    }
    assert!(
        reordered > 0,
        "the chunked order rounds differently somewhere"
    );
}

#[test]
fn chunks_cover_every_element_once_and_their_even_and_odd_windows_never_meet() {
    for (nx, ny) in [(65, 65), (129, 17), (40, 200)] {
        let mesh = union_jack(nx, ny, 1.0, 1.0);
        let model = built(&mesh, &Material::default(), &Forces::default());
        let chunks = Chunks::build(model.springs(), model.bends(), mesh.vertex_slots());
        let parts = chunks.parts();
        assert!(parts.len() >= 4, "{nx}x{ny}: {} chunks", parts.len());
        assert_eq!(parts[0].springs.start, 0);
        assert_eq!(parts[0].bends.start, 0);
        for pair in parts.windows(2) {
            assert_eq!(pair[0].springs.end, pair[1].springs.start);
            assert_eq!(pair[0].bends.end, pair[1].bends.start);
        }
        let last = parts.last().unwrap();
        assert_eq!(
            (last.springs.end, last.bends.end),
            (model.springs().len(), model.bends().len())
        );
        for t in 2..parts.len() {
            assert!(
                parts[t - 2].window.end <= parts[t].window.start,
                "{nx}x{ny}: chunk {t}"
            );
        }
        for c in parts {
            let sp = model.springs();
            let touched = c.springs.clone().flat_map(|j| [sp.a[j], sp.b[j]]);
            let touched = touched.chain(c.bends.clone().flat_map(|j| model.bends().v[j]));
            assert!(touched
                .into_iter()
                .all(|i| c.window.contains(&(i as usize))));
        }
    }
    // A model over a few elements of a large mesh, as remesh's energy trial makes, is swept in
    // one piece.
    let mesh = union_jack(65, 65, 1.0, 1.0);
    let model = built(&mesh, &Material::default(), &Forces::default());
    let local = model.around(&[100, 101, 102]);
    assert!(!local.springs().is_empty());
    assert!(Chunks::build(local.springs(), local.bends(), mesh.vertex_slots()).is_empty());
    // A small mesh is swept in one piece.
    let mesh = union_jack(33, 33, 1.0, 1.0);
    let model = built(&mesh, &Material::default(), &Forces::default());
    assert!(Chunks::build(model.springs(), model.bends(), mesh.vertex_slots()).is_empty());
}

/// The sweeps read and write without bounds checks once each block's slots are checked: a slot
/// outside the window, or a state shorter than the elements need, must panic, never touch memory
/// out of bounds.
#[test]
fn slots_outside_the_window_or_the_state_panic() {
    let mesh = union_jack(4, 4, 1.0, 1.0);
    let (x, v) = random_state(&mesh, 3, 0.05);
    let mut springs = Springs::default();
    springs.rebuild(&mesh, &Material::default());
    let mut bends = Bends::default();
    bends.rebuild(&mesh);
    let kb = BendConstants {
        elastic: 1e-3,
        damping: 1e-5,
    };
    let n = x.len();
    // True when the sweep stops on the block check (not on some other panic).
    let panics = |sweep: &dyn Fn()| match std::panic::catch_unwind(AssertUnwindSafe(sweep)) {
        Ok(()) => false,
        Err(payload) => payload
            .downcast_ref::<String>()
            .is_some_and(|m| m.contains("outside the state or the window")),
    };
    // A window that leaves out the last slot, and one that starts after slot 0.
    for (from, to) in [(0, n - 1), (1, n)] {
        assert!(panics(&|| {
            let mut f = vec![Vec3::zeros(); n];
            let w = Window {
                values: &mut f[from..to],
                first: from,
            };
            spring_forces::<true, true, false>(&springs, 0..springs.len(), &x, &v, w)
        }));
        assert!(panics(&|| {
            let mut f = vec![Vec3::zeros(); n];
            let w = Window {
                values: &mut f[from..to],
                first: from,
            };
            bend_forces::<true, true>(&bends, 0..bends.len(), kb, &x, &v, w)
        }));
    }
    // A state shorter than the mesh: positions, then velocities, through both kernels.
    let zeros = || vec![Vec3::zeros(); n];
    for (xs, vs) in [(&x[..n - 1], &v[..]), (&x[..], &v[..n - 1])] {
        assert!(panics(&|| {
            spring_forces::<true, true, false>(
                &springs,
                0..springs.len(),
                xs,
                vs,
                Window::whole(&mut zeros()),
            )
        }));
        assert!(panics(&|| {
            bend_forces::<true, true>(
                &bends,
                0..bends.len(),
                kb,
                xs,
                vs,
                Window::whole(&mut zeros()),
            )
        }));
    }
    // The same sweeps with everything in bounds do not panic.
    assert!(!panics(&|| {
        let mut f = vec![Vec3::zeros(); n];
        spring_forces::<true, true, false>(
            &springs,
            0..springs.len(),
            &x,
            &v,
            Window::whole(&mut f),
        );
        bend_forces::<true, true>(&bends, 0..bends.len(), kb, &x, &v, Window::whole(&mut f));
    }));
}
