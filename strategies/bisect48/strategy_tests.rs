//! Tests of the criteria mapping of the `bisect48` strategy: a fold is refined, a flattened
//! cloth is merged back only after the hysteresis time, and the strategy is built by name.
use super::*;
use crate::adapt::{AdaptContext, AdaptParams, Adaptivity};
use crate::cloth::Cloth;
use crate::math::{Real, Vec3};
use crate::testing::{self, flat_cloth};

/// Folds the cloth by 90 degrees along the rest line u = 0.5 (every slot, live or not).
fn fold(cloth: &mut Cloth) {
    for v in cloth.mesh.vertices().collect::<Vec<_>>() {
        let p = cloth.mesh.rest(v);
        cloth.x[v.0 as usize] = if p.x > 0.5 {
            Vec3::new(0.5, p.y, p.x - 0.5)
        } else {
            Vec3::new(p.x, p.y, 0.0)
        };
    }
}

fn flatten(cloth: &mut Cloth) {
    for v in cloth.mesh.vertices().collect::<Vec<_>>() {
        let p = cloth.mesh.rest(v);
        cloth.x[v.0 as usize] = Vec3::new(p.x, p.y, 0.0);
    }
}

#[test]
fn fold_is_refined_and_flat_cloth_merges_back_after_t_simplify() {
    let obstacles = testing::obstacles(&[]);
    let spec = AdaptParams::default();
    let mut cloth = flat_cloth(5, Vec3::zeros());
    let mut s = Bisect48::new();
    let ctx = |time: Real| AdaptContext {
        obstacles: &obstacles,
        time,
        params: &spec,
        interrupt: None,
    };
    // A flat cloth at rest: nothing to do.
    let r = s.adapt(&mut cloth, &ctx(0.0)).unwrap();
    assert_eq!(r.events, 0);
    // Folded: refined along the fold, over several calls (one level per call where an edge is
    // a leg of its faces).
    fold(&mut cloth);
    let mut added = 0;
    for k in 1..=6 {
        let r = s.adapt(&mut cloth, &ctx(0.001 * k as Real)).unwrap();
        cloth.refresh();
        cloth.mesh.check().unwrap();
        s.labels().unwrap().check(&cloth.mesh).unwrap();
        added += r.vertices_added;
        fold(&mut cloth); // keep new vertices on the fold's surface
    }
    assert!(added > 0 && cloth.mesh.vertex_count() == 25 + added);
    // Every inserted vertex lies near the fold line.
    for v in cloth.mesh.vertices().filter(|v| v.0 >= 25) {
        let u = cloth.mesh.rest(v).x;
        assert!((u - 0.5).abs() <= 0.25 + 1e-12, "vertex at u = {u}");
    }
    // Flattened: nothing is merged before t_simplify has passed since the last refinement...
    flatten(&mut cloth);
    let t_refined = 0.006;
    let r = s
        .adapt(&mut cloth, &ctx(t_refined + 0.5 * spec.t_simplify))
        .unwrap();
    assert_eq!(r.vertices_removed, 0);
    // ...then merged back level by level to the initial grid.
    let mut t = t_refined + spec.t_simplify;
    for _ in 0..20 {
        let r = s.adapt(&mut cloth, &ctx(t)).unwrap();
        cloth.refresh();
        cloth.mesh.check().unwrap();
        if r.events == 0 {
            break;
        }
        assert_eq!(r.vertices_added, 0);
        t += 0.001;
    }
    assert_eq!(cloth.mesh.vertex_count(), 25);
    assert_eq!(cloth.mesh.face_count(), 32);
}

#[test]
fn strategy_is_built_by_name() {
    let s = crate::strategies::make_strategy("bisect48").unwrap();
    assert_eq!(s.name(), "bisect48");
}

/// Edges the energy law refused wait before they are tried again: a fold selected for
/// refinement is not bisected within the wait, and is bisected after it.
#[test]
fn edges_refused_by_the_energy_law_are_not_bisected_again_within_their_wait() {
    let obstacles = testing::obstacles(&[]);
    let spec = AdaptParams::default();
    let mut cloth = flat_cloth(5, Vec3::zeros());
    fold(&mut cloth);
    let mut s = Bisect48::new();
    s.refusals = testing::every_edge_refused(&cloth.mesh, spec.t_simplify);
    let ctx = |time: Real| AdaptContext {
        obstacles: &obstacles,
        time,
        params: &spec,
        interrupt: None,
    };
    let r = s.adapt(&mut cloth, &ctx(0.5 * spec.t_simplify)).unwrap();
    assert_eq!(r.events, 0, "bisected within the wait");
    let r = s.adapt(&mut cloth, &ctx(1.01 * spec.t_simplify)).unwrap();
    assert!(r.events > 0, "the fold is bisected once the wait is over");
}
