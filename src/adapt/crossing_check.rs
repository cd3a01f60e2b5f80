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
    let key = |r: VertexRef| match r {
        VertexRef::Old(v) => v.0 as usize,
        VertexRef::New(k) => usize::MAX - k,
    };
    let at = |k: Key| {
        if k > usize::MAX / 2 {
            new_positions[usize::MAX - k]
        } else {
            cloth.x[k]
        }
    };
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
    let crosses = |edge: [Key; 2], face: [Key; 3]| {
        !face.contains(&edge[0])
            && !face.contains(&edge[1])
            && segment_crosses_triangle(at(edge[0]), at(edge[1]), face.map(at))
    };
    if new_faces
        .iter()
        .any(|&f| new_edges.iter().any(|&e| crosses(e, f)))
    {
        return true;
    }
    let mut removed = edit.remove.clone();
    removed.sort_unstable();
    let mesh = &cloth.mesh;
    mesh.faces()
        .filter(|f| removed.binary_search(f).is_err())
        .map(|f| mesh.face(f).map(|v| v.0 as usize))
        .filter(|f| {
            let points = f.map(|k| cloth.x[k]);
            (0..3).all(|a| {
                points.iter().any(|p| p[a] <= hi[a]) && points.iter().any(|p| p[a] >= lo[a])
            })
        })
        .any(|f| {
            new_edges.iter().any(|&e| crosses(e, f))
                || (0..3).any(|i| {
                    let edge = sorted(f[i], f[(i + 1) % 3]);
                    new_faces.iter().any(|&g| crosses(edge, g))
                })
        })
}

fn sorted(a: Key, b: Key) -> [Key; 2] {
    [a.min(b), a.max(b)]
}
