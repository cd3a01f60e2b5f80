//! Tests of [`Mesh::replace`]: valid splits, merges and re-meshes; refused edits leave the mesh
//! identical; a property test drives random split/merge sequences.
use super::*;
use crate::mesh::union_jack;
use proptest::prelude::*;
use VertexRef::{New, Old};

/// Splits edge `a-b` at its rest midpoint (2 faces -> 4 inside, 1 -> 2 on the border).
fn split_edit(m: &Mesh, a: VertexId, b: VertexId) -> Edit {
    let ef = *m.edge(a, b).expect("edge exists");
    let mut edit = Edit {
        new_vertices: vec![NewVertex {
            rest: (m.rest(a) + m.rest(b)) / 2.0,
            origin: Origin::Midpoint(a, b),
        }],
        ..Edit::default()
    };
    for f in ef.iter() {
        let vs = m.face(f);
        let k = (0..3)
            .find(|&k| {
                let (x, y) = (vs[k], vs[(k + 1) % 3]);
                (x == a && y == b) || (x == b && y == a)
            })
            .expect("face has the edge");
        let (x, y, z) = (vs[k], vs[(k + 1) % 3], vs[(k + 2) % 3]);
        edit.remove.push(f);
        edit.add.push([Old(x), New(0), Old(z)]);
        edit.add.push([New(0), Old(y), Old(z)]);
    }
    edit
}

/// The wedges around `v` chained into its fan: neighbours in counter-clockwise order.
fn link(m: &Mesh, v: VertexId) -> Vec<VertexId> {
    let wedges: Vec<(VertexId, VertexId)> = m
        .vertex_faces(v)
        .iter()
        .map(|&f| {
            let vs = m.face(f);
            let k = (0..3).find(|&k| vs[k] == v).unwrap();
            (vs[(k + 1) % 3], vs[(k + 2) % 3])
        })
        .collect();
    let start = wedges
        .iter()
        .find(|w| !wedges.iter().any(|u| u.1 == w.0))
        .unwrap_or(&wedges[0]);
    let mut out = vec![start.0, start.1];
    while out.len() <= wedges.len() {
        let last = *out.last().unwrap();
        match wedges.iter().find(|w| w.0 == last) {
            Some(w) if w.1 != out[0] => out.push(w.1),
            _ => break,
        }
    }
    out
}

fn between(m: &Mesh, p: VertexId, v: VertexId, q: VertexId) -> bool {
    let (a, b, x) = (m.rest(p), m.rest(q), m.rest(v));
    let d = b - a;
    let t = (x - a).dot(&d) / d.norm_squared();
    (d.perp(&(x - a))).abs() <= 1e-9 * d.norm_squared() && t > 0.0 && t < 1.0
}

/// Removes `v` when it is the midpoint of a valence-4 interior star or a 2-face border star.
fn merge_edit(m: &Mesh, v: VertexId) -> Option<Edit> {
    let faces = m.vertex_faces(v).to_vec();
    let l = link(m, v);
    let add = match (faces.len(), l.len()) {
        (4, 4) if between(m, l[0], v, l[2]) => vec![[l[0], l[1], l[2]], [l[2], l[3], l[0]]],
        (4, 4) if between(m, l[1], v, l[3]) => vec![[l[1], l[2], l[3]], [l[3], l[0], l[1]]],
        (2, 3) if between(m, l[0], v, l[2]) => vec![[l[0], l[1], l[2]]],
        _ => return None,
    };
    Some(Edit {
        remove: faces,
        new_vertices: vec![],
        add: add.into_iter().map(|f| f.map(Old)).collect(),
    })
}

fn total_area(m: &Mesh) -> Real {
    m.faces().map(|f| m.face_rest_area(f)).sum()
}

fn vid(i: u32) -> VertexId {
    VertexId(i)
}

#[test]
fn interior_edge_split() {
    let mut m = union_jack(3, 3, 1.0, 1.0);
    let (a, b) = (vid(0), vid(4)); // diagonal of cell (0, 0)
    assert!(!m.edge(a, b).unwrap().is_border());
    let rec = m.replace(&split_edit(&m, a, b)).unwrap();
    assert_eq!(rec.removed_faces.len(), 2);
    assert_eq!(rec.added_faces.len(), 4);
    assert_eq!(rec.added_vertices, vec![(vid(9), Origin::Midpoint(a, b))]);
    assert!(rec.removed_vertices.is_empty());
    assert_eq!(m.face_count(), 10);
    assert_eq!(m.rest(vid(9)), Vec2::new(0.25, 0.25));
    assert!(m.edge(a, b).is_none());
    m.check().unwrap();
}

#[test]
fn border_edge_split_and_merge_back() {
    let original = union_jack(3, 3, 1.0, 1.0);
    let mut m = original.clone();
    let rec = m.replace(&split_edit(&m, vid(0), vid(1))).unwrap();
    assert_eq!((rec.removed_faces.len(), rec.added_faces.len()), (1, 2));
    let mid = rec.added_vertices[0].0;
    assert!(m.is_border_vertex(mid));
    m.check().unwrap();
    let rec = m.replace(&merge_edit(&m, mid).unwrap()).unwrap();
    assert_eq!(rec.removed_vertices, vec![mid]);
    m.check().unwrap();
    assert!(!m.is_vertex(mid));
    assert_eq!(m.face_count(), original.face_count());
    assert!(m.edge(vid(0), vid(1)).unwrap().is_border());
}

#[test]
fn interior_split_merge_round_trip() {
    let mut m = union_jack(4, 4, 1.0, 1.0);
    let before: Vec<_> = m.edges().map(|(k, e)| (k, e.iter().count())).collect();
    let rec = m.replace(&split_edit(&m, vid(5), vid(6))).unwrap();
    let mid = rec.added_vertices[0].0;
    m.replace(&merge_edit(&m, mid).unwrap()).unwrap();
    let after: Vec<_> = m.edges().map(|(k, e)| (k, e.iter().count())).collect();
    assert_eq!(before, after);
    m.check().unwrap();
}

#[test]
fn region_remesh_with_interior_vertex() {
    // Remove the 8-face star of vertex 12 (grid point (2, 2)) and fan a new, moved vertex.
    let mut m = union_jack(5, 5, 1.0, 1.0);
    let centre = vid(12);
    let star = m.vertex_faces(centre).to_vec();
    assert_eq!(star.len(), 8);
    let ring = link(&m, centre);
    assert_eq!(ring.len(), 8);
    let edit = Edit {
        remove: star,
        new_vertices: vec![NewVertex {
            rest: Vec2::new(0.52, 0.47),
            origin: Origin::InTriangle {
                corners: [vid(12), vid(13), vid(18)],
                weights: [0.9, 0.05, 0.05],
            },
        }],
        add: (0..8)
            .map(|i| [New(0), Old(ring[i]), Old(ring[(i + 1) % 8])])
            .collect(),
    };
    let rec = m.replace(&edit).unwrap();
    assert_eq!(rec.removed_vertices, vec![centre]);
    assert_eq!(rec.added_vertices.len(), 1);
    assert_eq!(rec.added_faces.len(), 8);
    assert_ne!(
        rec.added_vertices[0].0, centre,
        "no slot reuse within one edit"
    );
    m.check().unwrap();
}

/// Applies an edit that must fail, and checks the mesh is untouched.
fn refused(m: &mut Mesh, edit: &Edit) -> EditError {
    let before = m.clone();
    let err = m.replace(edit).expect_err("edit must be refused");
    assert_eq!(*m, before, "mesh changed by a refused edit ({err})");
    err
}

#[test]
fn gap_is_refused() {
    let mut m = union_jack(3, 3, 1.0, 1.0);
    let mut edit = split_edit(&m, vid(0), vid(4));
    edit.add.pop();
    assert!(matches!(refused(&mut m, &edit), EditError::NotATiling(_)));
    // A border split whose new vertex is pulled inside leaves a notch.
    let mut edit = split_edit(&m, vid(0), vid(1));
    edit.new_vertices[0].rest.y += 0.01;
    assert!(matches!(refused(&mut m, &edit), EditError::NotATiling(_)));
}

#[test]
fn overlap_is_refused() {
    let mut m = union_jack(3, 3, 1.0, 1.0);
    // The two faces of diagonal 0-4 replaced by the same quad cut twice.
    let f = *m.edge(vid(0), vid(4)).unwrap();
    let edit = Edit {
        remove: f.iter().collect(),
        new_vertices: vec![],
        add: vec![
            [Old(vid(0)), Old(vid(1)), Old(vid(4))],
            [Old(vid(0)), Old(vid(4)), Old(vid(3))],
            [Old(vid(0)), Old(vid(1)), Old(vid(3))],
        ],
    };
    assert!(matches!(refused(&mut m, &edit), EditError::NotATiling(_)));
    // A new face stacked on a kept face.
    let g = *m.edge(vid(1), vid(4)).unwrap();
    let kept = g.iter().find(|h| !f.iter().any(|x| x == *h)).unwrap();
    let mut add: Vec<_> = f.iter().map(|x| m.face(x).map(Old)).collect();
    add.push(m.face(kept).map(Old));
    let edit = Edit {
        remove: f.iter().collect(),
        new_vertices: vec![],
        add,
    };
    let err = refused(&mut m, &edit);
    assert!(
        matches!(err, EditError::NotATiling(_) | EditError::Conformity(_)),
        "{err}"
    );
}

#[test]
fn clockwise_face_is_refused() {
    let mut m = union_jack(3, 3, 1.0, 1.0);
    let mut edit = split_edit(&m, vid(0), vid(4));
    edit.add[1].swap(0, 1);
    assert!(matches!(
        refused(&mut m, &edit),
        EditError::BadFace { face: 1, area } if area < 0.0
    ));
}

#[test]
fn stale_face_is_refused() {
    let mut m = union_jack(3, 3, 1.0, 1.0);
    let mut edit = split_edit(&m, vid(0), vid(4));
    edit.remove.push(edit.remove[0]);
    assert!(matches!(refused(&mut m, &edit), EditError::StaleFace(_)));
    let edit = Edit {
        remove: vec![FaceId(99)],
        ..Edit::default()
    };
    assert_eq!(refused(&mut m, &edit), EditError::StaleFace(FaceId(99)));
    let edit = split_edit(&m, vid(0), vid(4));
    let mut bad = edit.clone();
    bad.add[0][1] = New(3);
    assert!(matches!(
        refused(&mut m, &bad),
        EditError::BadVertex { face: 0, .. }
    ));
}

#[test]
fn removing_pinned_vertex_is_refused() {
    let mut m = union_jack(3, 3, 1.0, 1.0);
    let rec = m.replace(&split_edit(&m, vid(2), vid(5))).unwrap();
    let mid = rec.added_vertices[0].0;
    m.set_pinned(mid, true);
    let edit = merge_edit(&m, mid).unwrap();
    assert_eq!(refused(&mut m, &edit), EditError::RemovesPinned(mid));
    m.set_pinned(mid, false);
    m.replace(&edit).unwrap();
    // The reused slot comes back unpinned.
    let rec = m.replace(&split_edit(&m, vid(2), vid(5))).unwrap();
    assert_eq!(rec.added_vertices[0].0, mid);
    assert!(!m.is_pinned(mid));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]
    #[test]
    fn random_splits_and_merges_stay_conforming(
        nx in 2usize..8,
        ny in 2usize..8,
        ops in proptest::collection::vec((0u8..3, any::<u32>()), 50),
    ) {
        let mut m = union_jack(nx, ny, 1.0, 0.8);
        let area0 = total_area(&m);
        let mut mids = Vec::new();
        for (kind, pick) in ops {
            if kind > 0 || mids.is_empty() {
                let (key, _) = m.edges().nth(pick as usize % m.edge_count()).unwrap();
                let rec = m.replace(&split_edit(&m, key.0, key.1));
                prop_assert!(rec.is_ok(), "split {key:?} refused: {rec:?}");
                mids.push(m.key(rec.unwrap().added_vertices[0].0));
            } else {
                let key = mids.swap_remove(pick as usize % mids.len());
                let Some(v) = m.resolve(key) else { continue };
                if let Some(edit) = merge_edit(&m, v) {
                    let rec = m.replace(&edit);
                    prop_assert!(rec.is_ok(), "merge of {v:?} refused: {rec:?}");
                    prop_assert_eq!(rec.unwrap().removed_vertices, vec![v]);
                } else {
                    mids.push(key);
                }
            }
            prop_assert_eq!(m.check(), Ok(()));
            prop_assert!((total_area(&m) - area0).abs() <= 1e-12 * area0);
        }
    }
}
