//! Tests of the simnett hierarchy, its operations and the strategy. The property tests
//! (`proptests`) drive random split/merge sequences on random grids through the cloth (mass and
//! momentum) and the bare mesh in lockstep.

use super::*;
use crate::adapt::{AdaptContext, AdaptParams, Adaptivity};
use crate::cloth::Cloth;
use crate::collision::Obstacles;
use crate::collision::{Obstacle, ObstacleShape};
use crate::math::{Real, Vec2, Vec3};
use crate::mesh::{union_jack, EdgeKey, Mesh, VertexId};
use crate::testing;
use std::collections::BTreeSet;

mod proptests;

/// One counter-clockwise right triangle (0,0), (1,0), (0,1).
fn one_triangle() -> Mesh {
    Mesh::from_faces(
        vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.0, 1.0),
        ],
        &[[0, 1, 2]],
    )
    .unwrap()
}

fn v(i: u32) -> VertexId {
    VertexId(i)
}

/// The sorted set of canonical face triples.
fn triples(mesh: &Mesh) -> BTreeSet<[VertexId; 3]> {
    mesh.faces().map(|f| canonical(mesh.face(f))).collect()
}

fn only_triangle() -> TriKey {
    TriKey::new([v(0), v(1), v(2)])
}

#[test]
fn state_numbers_and_split_bits_are_inverse() {
    for s in 0..8 {
        assert_eq!(state_of(bits_of(s)), s);
    }
    assert_eq!(state_of(0b001), 1);
    assert_eq!(state_of(0b100), 3);
    assert_eq!(state_of(0b101), 6);
}

#[test]
fn each_state_of_one_triangle_has_the_prescribed_faces() {
    // Every subset of split edges, reached by splitting in edge order.
    for bits in 0u8..8 {
        let mut mesh = one_triangle();
        let mut h = Hierarchy::new(&mesh);
        let t = only_triangle();
        for k in 0..3 {
            if bits & (1 << k) != 0 {
                let e = h.triangle(t).unwrap().edge(k);
                h.split_edge(&mut mesh, e, 3, 0.0).unwrap();
            }
        }
        mesh.check().unwrap();
        h.check(&mesh, 3).unwrap();
        let tri = h.triangle(t).unwrap();
        assert_eq!(tri.state, state_of(bits));
        let expected_faces = [1, 2, 2, 2, 3, 3, 3, 4][tri.state as usize];
        assert_eq!(mesh.face_count(), expected_faces, "state {}", tri.state);
        if tri.state == 7 {
            assert!(tri.children.is_some());
            for c in tri.children.unwrap() {
                assert_eq!(h.triangle(c).unwrap().state, 0);
            }
            for f in mesh.faces() {
                assert_eq!(h.face_state(f), Some(0));
            }
        } else if tri.state > 0 {
            for f in mesh.faces() {
                assert_eq!(h.face_state(f), Some(TEMPORARY_STATE));
            }
        }
    }
}

#[test]
fn two_split_edges_use_the_shorter_diagonal_of_the_quad() {
    // Edges 0 (0-1) and 1 (1-2) split: quad 0, m01, m12, 2; diagonals 0-m12 (0.707) and
    // m01-2 (1.118): the first is used.
    let mut mesh = one_triangle();
    let mut h = Hierarchy::new(&mesh);
    h.split_edge(&mut mesh, EdgeKey::new(v(0), v(1)), 3, 0.0)
        .unwrap();
    h.split_edge(&mut mesh, EdgeKey::new(v(1), v(2)), 3, 0.0)
        .unwrap();
    let m12 = mesh
        .vertices()
        .find(|&w| (mesh.rest(w) - Vec2::new(0.5, 0.5)).norm() < 1e-12)
        .unwrap();
    assert!(mesh.edge(v(0), m12).is_some());
    let m01 = mesh
        .vertices()
        .find(|&w| (mesh.rest(w) - Vec2::new(0.5, 0.0)).norm() < 1e-12)
        .unwrap();
    assert!(mesh.edge(m01, v(2)).is_none());
}

#[test]
fn faithful_rule_blocks_children_until_the_parent_reaches_state_7() {
    let mut mesh = union_jack(3, 3, 1.0, 1.0);
    let mut h = Hierarchy::new(&mesh);
    // The interior diagonal 0-4 (cell (0,0) is cut through its corner (0,0)).
    let e = EdgeKey::new(v(0), v(4));
    let r = h.split_edge(&mut mesh, e, 3, 0.0).unwrap();
    assert_eq!(r.triangles.len(), 2);
    let child = EdgeKey::new(v(0), r.mid);
    let before = (mesh.clone(), h.clone());
    let err = h.split_edge(&mut mesh, child, 3, 0.0).unwrap_err();
    assert!(
        matches!(err, OpError::NextToTemporary { edge, .. } if edge == child),
        "{err}"
    );
    assert_eq!((mesh.clone(), h.clone()), before, "untouched on error");
    // An edge between temporary children is not a hierarchy edge.
    let temp = EdgeKey::new(r.mid, v(1));
    let err = h.split_edge(&mut mesh, temp, 3, 0.0).unwrap_err();
    assert!(matches!(err, OpError::Temporary { .. }), "{err}");
    // Forced: both parent triangles are completed first (2 + 2 more splits), then the child.
    let records = h.split_edge_forced(&mut mesh, child, 3, 0.0).unwrap();
    assert_eq!(records.len(), 5);
    assert_eq!(records.last().unwrap().edge, child);
    mesh.check().unwrap();
    h.check(&mesh, 3).unwrap();
    for t in h.edge(e).unwrap().tris.iter() {
        assert_eq!(h.triangle(*t).unwrap().state, 7);
    }
}

#[test]
fn preconditions_are_named_and_leave_everything_untouched() {
    let mut mesh = union_jack(3, 3, 1.0, 1.0);
    let mut h = Hierarchy::new(&mesh);
    let e = EdgeKey::new(v(0), v(1));
    let before = (mesh.clone(), h.clone());
    let checks: Vec<(OpError, &str)> = vec![
        (
            h.merge_edge(&mut mesh, e, 0.0).unwrap_err(),
            "merge of a leaf",
        ),
        (
            h.split_edge(&mut mesh, EdgeKey::new(v(0), v(8)), 3, 0.0)
                .unwrap_err(),
            "not an edge",
        ),
        (
            h.split_edge(&mut mesh, e, 0, 0.0).unwrap_err(),
            "max depth 0",
        ),
    ];
    assert!(
        matches!(checks[0].0, OpError::NotSplit(_)),
        "{}",
        checks[0].0
    );
    assert!(
        matches!(checks[1].0, OpError::NotAnEdge(_)),
        "{}",
        checks[1].0
    );
    assert!(
        matches!(
            checks[2].0,
            OpError::MaxDepth {
                depth: 0,
                max_depth: 0,
                ..
            }
        ),
        "{}",
        checks[2].0
    );
    assert_eq!((mesh.clone(), h.clone()), before);
    // Split twice: already split.
    h.split_edge(&mut mesh, e, 3, 0.0).unwrap();
    let err = h.split_edge(&mut mesh, e, 3, 0.0).unwrap_err();
    assert_eq!(err, OpError::AlreadySplit(e));
    // Complete the border triangle 0-1-4 and split a child edge: the parent cannot merge.
    let t = *h.edge(e).unwrap().tris.first().unwrap();
    let mut records = h.split_edge_forced(&mut mesh, EdgeKey::new(v(0), v(4)), 3, 0.0);
    assert!(records.is_ok());
    for k in 0..3 {
        let f = h.triangle(t).unwrap().edge(k);
        if h.edge(f).unwrap().mid.is_none() {
            records = h.split_edge_forced(&mut mesh, f, 3, 0.0);
            assert!(records.is_ok());
        }
    }
    assert_eq!(h.triangle(t).unwrap().state, 7);
    let mid = h.edge(e).unwrap().mid.unwrap();
    let child = EdgeKey::new(v(0), mid);
    h.split_edge(&mut mesh, child, 3, 0.0).unwrap();
    let before = (mesh.clone(), h.clone());
    let err = h.merge_edge(&mut mesh, e, 0.0).unwrap_err();
    assert!(matches!(err, OpError::ChildSplit { .. }), "{err}");
    // Another edge of t: its own children are leaves, but t's corner child is refined.
    let other = (0..3)
        .map(|k| h.triangle(t).unwrap().edge(k))
        .find(|&f| f != e)
        .unwrap();
    let err = h.merge_edge(&mut mesh, other, 0.0).unwrap_err();
    assert!(matches!(err, OpError::RefinedChildren { .. }), "{err}");
    assert_eq!((mesh.clone(), h.clone()), before);
    mesh.check().unwrap();
    h.check(&mesh, 3).unwrap();
}

#[test]
fn split_then_merge_restores_the_mesh_exactly() {
    let mut mesh = union_jack(4, 4, 1.0, 1.0);
    let mut h = Hierarchy::new(&mesh);
    let initial = (triples(&mesh), h.clone());
    let e = EdgeKey::new(v(5), v(6));
    let r = h.split_edge(&mut mesh, e, 3, 0.0).unwrap();
    assert_eq!(r.kind, OpKind::Split);
    assert_eq!(mesh.vertex_count(), 17);
    let m = h.merge_edge(&mut mesh, e, 0.0).unwrap();
    assert_eq!(m.kind, OpKind::Merge);
    assert_eq!(m.edit.removed_vertices, vec![r.mid]);
    assert_eq!(triples(&mesh), initial.0);
    assert_eq!(h.split_count(), 0);
    h.check(&mesh, 3).unwrap();
}

/// The flat 5 x 5 cloth of 1 m centred on the origin at z = 0.
fn flat_cloth() -> Cloth {
    testing::flat_cloth(5, Vec3::new(-0.5, -0.5, 0.0))
}

fn sphere(radius: Real, z: Real) -> Obstacles {
    testing::obstacles(&[Obstacle {
        restitution: 0.5,
        ..Obstacle::new(ObstacleShape::Sphere {
            center: [0.0, 0.0, z],
            radius,
        })
    }])
}

#[test]
fn collision_split_projects_the_new_vertex_onto_the_obstacle_surface() {
    // A flat 5x5 cloth at z = 0 cutting a sphere's cap (radius 0.3, centre 0.25 below): edges
    // through the cap are refined for collision and their midpoints land on the sphere (+margin).
    let mut cloth = flat_cloth();
    let obstacles = sphere(0.3, -0.25);
    let spec = AdaptParams {
        l_min: 0.05,
        ..AdaptParams::default()
    };
    let mut s = Simnett::default();
    let p0 = cloth.linear_momentum();
    let ctx = AdaptContext {
        obstacles: &obstacles,
        time: 0.0,
        params: &spec,
        interrupt: None,
    };
    let report = s.adapt(&mut cloth, &ctx).unwrap();
    assert!(report.events > 0);
    cloth.mesh.check().unwrap();
    let h = s.hierarchy().unwrap();
    h.check(&cloth.mesh, spec.max_depth).unwrap();
    let mut on_surface = 0;
    for (e, node) in h.edges() {
        let Some(m) = node.mid else { continue };
        let x = cloth.x[m.0 as usize];
        let d = (x - Vec3::new(0.0, 0.0, -0.25)).norm() - 0.3;
        let mid = (cloth.x[e.0 .0 as usize] + cloth.x[e.1 .0 as usize]) * 0.5;
        if (d - obstacles.margin()).abs() < 1e-9 && (mid - x).norm() > 1e-6 {
            on_surface += 1;
        }
    }
    assert!(on_surface > 0, "no projected midpoint");
    assert!((cloth.linear_momentum() - p0).norm() <= 1e-15);
}

#[test]
fn fold_refines_by_curvature_up_to_max_depth_and_flat_cloth_merges_back() {
    // Fold a 5x5 cloth by 90 degrees along u = 0.5; adapt repeatedly (time advancing past the
    // hysteresis each call) until nothing changes; then flatten and adapt until all merged.
    let mut cloth = flat_cloth();
    let fold = |cloth: &mut Cloth| {
        for w in cloth.mesh.vertices().collect::<Vec<_>>() {
            let p = cloth.mesh.rest(w);
            cloth.x[w.0 as usize] = if p.x > 0.5 {
                Vec3::new(0.0, p.y - 0.5, p.x - 0.5)
            } else {
                Vec3::new(p.x - 0.5, p.y - 0.5, 0.0)
            };
        }
    };
    fold(&mut cloth);
    let obstacles = sphere(0.01, -10.0);
    let spec = AdaptParams {
        force_completion: true,
        l_min: 0.01,
        ..AdaptParams::default()
    };
    let mut s = Simnett::default();
    let mut t = 0.0;
    for _ in 0..10 {
        let ctx = AdaptContext {
            obstacles: &obstacles,
            time: t,
            params: &spec,
            interrupt: None,
        };
        let r = s.adapt(&mut cloth, &ctx).unwrap();
        cloth.refresh();
        cloth.mesh.check().unwrap();
        s.hierarchy().unwrap().check(&cloth.mesh, 3).unwrap();
        fold(&mut cloth);
        t += 1e-3;
        if r.events == 0 {
            break;
        }
    }
    let h = s.hierarchy().unwrap();
    assert!(h.split_count() > 0);
    assert!(h.max_depth() >= 2, "depth {}", h.max_depth());
    // Refinement only near the fold.
    for (e, node) in h.edges() {
        if node.mid.is_some() {
            let (a, b) = (cloth.mesh.rest(e.0), cloth.mesh.rest(e.1));
            assert!((a.x - 0.5).abs() <= 0.5 || (b.x - 0.5).abs() <= 0.5);
        }
    }
    // Flatten: everything merges back once old enough.
    let initial = triples(&union_jack(5, 5, 1.0, 1.0));
    for _ in 0..20 {
        for w in cloth.mesh.vertices().collect::<Vec<_>>() {
            let p = cloth.mesh.rest(w);
            cloth.x[w.0 as usize] = Vec3::new(p.x - 0.5, p.y - 0.5, 0.0);
        }
        t += spec.t_simplify;
        let ctx = AdaptContext {
            obstacles: &obstacles,
            time: t,
            params: &spec,
            interrupt: None,
        };
        s.adapt(&mut cloth, &ctx).unwrap();
        cloth.refresh();
        cloth.mesh.check().unwrap();
    }
    assert_eq!(s.hierarchy().unwrap().split_count(), 0);
    assert_eq!(triples(&cloth.mesh), initial);
}

/// Edges the energy law refused wait before they are tried again: a fold selected for
/// refinement is not split within the wait, and is split after it.
#[test]
fn edges_refused_by_the_energy_law_are_not_split_again_within_their_wait() {
    let mut cloth = flat_cloth();
    for w in cloth.mesh.vertices().collect::<Vec<_>>() {
        let p = cloth.mesh.rest(w);
        if p.x > 0.5 {
            cloth.x[w.0 as usize] = Vec3::new(0.0, p.y - 0.5, p.x - 0.5);
        }
    }
    let obstacles = sphere(0.01, -10.0);
    let spec = AdaptParams::default();
    let mut s = Simnett::default();
    s.refusals = testing::every_edge_refused(&cloth.mesh, spec.t_simplify);
    let ctx = |time| AdaptContext {
        obstacles: &obstacles,
        time,
        params: &spec,
        interrupt: None,
    };
    let r = s.adapt(&mut cloth, &ctx(0.5 * spec.t_simplify)).unwrap();
    assert_eq!(r.events, 0, "split within the wait {r:?}");
    let r = s.adapt(&mut cloth, &ctx(1.01 * spec.t_simplify)).unwrap();
    assert!(r.events > 0, "the fold is split once the wait is over");
}
