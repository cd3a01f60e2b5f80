//! Whether a mesh edit would make the cloth cross itself: the check behind
//! [`super::TransferOptions::refuse_crossings`], so that with self-collision on no adaptation
//! creates a crossing the step's swept test could never undo (it assumes a start free of them).

use crate::cloth::Cloth;
use crate::collision::segment_crosses_triangle;
use crate::math::Vec3;
use crate::mesh::{Edit, VertexRef};

/// A vertex of the edited mesh: an old vertex slot, or a new vertex (`usize::MAX - k` for new
/// vertex `k`), so the two never collide.
type Key = usize;

/// Whether applying `edit` to `cloth`, with new vertex `k` at `new_positions[k]` (m), would give
/// an edge crossing a face it shares no vertex with ([`segment_crosses_triangle`]): the new
/// edges against the faces that stay and the new faces, and the edges of the faces that stay
/// against the new faces. Faces that stay are tested only when their box meets the new faces'
/// box, so the check costs one pass over the faces' boxes plus the few pairs near the edit.
pub fn edit_crosses(cloth: &Cloth, edit: &Edit, new_positions: &[Vec3]) -> bool {
    let at = |k: Key| position(cloth, new_positions, k);
    let new_faces: Vec<[Key; 3]> = edit.add.iter().map(|f| f.map(key)).collect();
    if new_faces.is_empty() {
        return false;
    }
    let mut new_edges: Vec<[Key; 2]> = new_faces
        .iter()
        .flat_map(|f| (0..3).map(move |i| sorted(f[i], f[(i + 1) % 3])))
        .collect();
    new_edges.sort_unstable();
    new_edges.dedup();
    let (mut lo, mut hi) = (at(new_faces[0][0]), at(new_faces[0][0]));
    for &k in new_faces.iter().flatten() {
        lo = lo.inf(&at(k));
        hi = hi.sup(&at(k));
    }
    let edge_boxes: Vec<Bounds> = new_edges.iter().map(|e| bounds(e.map(at))).collect();
    let face_boxes: Vec<Bounds> = new_faces.iter().map(|f| bounds(f.map(at))).collect();
    // An edge can cross a face only where their boxes meet (the test is strict).
    let crosses = |edge: [Key; 2], edge_box: &Bounds, face: [Key; 3], face_box: &Bounds| {
        overlap(edge_box, face_box)
            && !face.contains(&edge[0])
            && !face.contains(&edge[1])
            && segment_crosses_triangle(at(edge[0]), at(edge[1]), face.map(at))
    };
    let new_edges_cross = |face: [Key; 3], face_box: &Bounds| {
        new_edges
            .iter()
            .zip(&edge_boxes)
            .any(|(&e, e_box)| crosses(e, e_box, face, face_box))
    };
    if new_faces
        .iter()
        .zip(&face_boxes)
        .any(|(&f, f_box)| new_edges_cross(f, f_box))
    {
        return true;
    }
    let mut removed = edit.remove.clone();
    removed.sort_unstable();
    let mesh = &cloth.mesh;
    // The box first: most faces are far from the edit.
    mesh.faces()
        .filter_map(|id| {
            let f = mesh.face(id).map(|v| v.0 as usize);
            let face_box = bounds(f.map(|k| cloth.x[k]));
            (overlap(&face_box, &(lo, hi)) && removed.binary_search(&id).is_err())
                .then_some((f, face_box))
        })
        .any(|(f, face_box)| {
            new_edges_cross(f, &face_box)
                || (0..3).any(|i| {
                    let edge = sorted(f[i], f[(i + 1) % 3]);
                    let edge_box = bounds(edge.map(at));
                    new_faces
                        .iter()
                        .zip(&face_boxes)
                        .any(|(&g, g_box)| crosses(edge, &edge_box, g, g_box))
                })
        })
}

/// A box: its lowest and highest corners (m).
type Bounds = (Vec3, Vec3);

/// The smallest box holding `points` (m).
fn bounds<const N: usize>(points: [Vec3; N]) -> Bounds {
    let mut b = (points[0], points[0]);
    for p in &points[1..] {
        b = (b.0.inf(p), b.1.sup(p));
    }
    b
}

/// Whether two boxes meet (touching included).
fn overlap(a: &Bounds, b: &Bounds) -> bool {
    (0..3).all(|k| a.0[k] <= b.1[k] && b.0[k] <= a.1[k])
}

/// The key of a vertex of the edited mesh.
fn key(r: VertexRef) -> Key {
    match r {
        VertexRef::Old(v) => v.0 as usize,
        VertexRef::New(k) => usize::MAX - k,
    }
}

/// The world position (m) of the vertex `k` of the edited mesh, new vertex `j` being at
/// `new_positions[j]`.
fn position(cloth: &Cloth, new_positions: &[Vec3], k: Key) -> Vec3 {
    if k > usize::MAX / 2 {
        new_positions[usize::MAX - k]
    } else {
        cloth.x[k]
    }
}

fn sorted(a: Key, b: Key) -> [Key; 2] {
    [a.min(b), a.max(b)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::FaceId;
    use crate::testing::folded_cloth;
    use proptest::prelude::*;

    /// [`edit_crosses`] without any box: every new edge against every new face and every face
    /// that stays, every edge of a face that stays against every new face.
    fn crosses_by_every_pair(cloth: &Cloth, edit: &Edit, new_positions: &[Vec3]) -> bool {
        let at = |k: Key| position(cloth, new_positions, k);
        let new_faces: Vec<[Key; 3]> = edit.add.iter().map(|f| f.map(key)).collect();
        let edges_of = |f: [Key; 3]| (0..3).map(move |i| sorted(f[i], f[(i + 1) % 3]));
        let new_edges: Vec<[Key; 2]> = new_faces.iter().flat_map(|&f| edges_of(f)).collect();
        let crosses = |e: [Key; 2], f: [Key; 3]| {
            !f.contains(&e[0])
                && !f.contains(&e[1])
                && segment_crosses_triangle(at(e[0]), at(e[1]), f.map(at))
        };
        let kept: Vec<[Key; 3]> = cloth
            .mesh
            .faces()
            .filter(|f| !edit.remove.contains(f))
            .map(|f| cloth.mesh.face(f).map(|v| v.0 as usize))
            .collect();
        let faces = || new_faces.iter().chain(&kept);
        new_edges.iter().any(|&e| faces().any(|&f| crosses(e, f)))
            || kept
                .iter()
                .any(|&f| edges_of(f).any(|e| new_faces.iter().any(|&g| crosses(e, g))))
    }

    /// Face `f` of `cloth` replaced by three faces around one new vertex (its position is the
    /// check's argument; the edit's new vertex list is not read by the check).
    fn split_at_new_vertex(cloth: &Cloth, f: FaceId) -> Edit {
        let [a, b, c] = cloth.mesh.face(f).map(VertexRef::Old);
        Edit {
            remove: vec![f],
            new_vertices: Vec::new(),
            add: vec![
                [a, b, VertexRef::New(0)],
                [b, c, VertexRef::New(0)],
                [c, a, VertexRef::New(0)],
            ],
        }
    }

    proptest! {
        /// A face of the folded cloth split at a new vertex placed anywhere around the fold: the
        /// boxes only skip pairs that cannot cross.
        #[test]
        fn the_boxes_skip_no_crossing(
            face in 0usize..32,
            p in (0.2..0.8f64, 0.0..1.0f64, -0.2..0.4f64),
        ) {
            let cloth = folded_cloth(5);
            let faces: Vec<FaceId> = cloth.mesh.faces().collect();
            let f = faces[face % faces.len()];
            let edit = split_at_new_vertex(&cloth, f);
            let at = [Vec3::new(p.0, p.1, p.2)];
            prop_assert_eq!(edit_crosses(&cloth, &edit, &at), crosses_by_every_pair(&cloth, &edit, &at));
        }
    }

    /// A new vertex pulled through the standing half of the folded cloth crosses it; one kept
    /// in the face's plane does not.
    #[test]
    fn a_vertex_pulled_through_the_other_half_crosses() {
        let cloth = folded_cloth(5);
        // A face of the flat half touching the fold (x = 0.5), and its centre.
        let f = cloth
            .mesh
            .faces()
            .find(|&f| {
                let xs = cloth.mesh.face(f).map(|v| cloth.x[v.0 as usize]);
                xs.iter().all(|p| p.z == 0.0) && xs.iter().filter(|p| p.x == 0.5).count() == 1
            })
            .unwrap();
        let centre = cloth
            .mesh
            .face(f)
            .map(|v| cloth.x[v.0 as usize])
            .iter()
            .sum::<Vec3>()
            / 3.0;
        let edit = split_at_new_vertex(&cloth, f);
        assert!(!edit_crosses(&cloth, &edit, &[centre]));
        let through = Vec3::new(0.8, centre.y, 0.05);
        assert!(edit_crosses(&cloth, &edit, &[through]));
        assert!(crosses_by_every_pair(&cloth, &edit, &[through]));
    }
}
