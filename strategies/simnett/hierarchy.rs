//! The edge/triangle hierarchy of Simnett et al. 2009 (MODEL.md §8.3) and the triangle states.
//!
//! Every hierarchy edge and triangle is keyed by its vertices (rest-space segments and triangles
//! are unique, so the vertex pair or triple names them); nodes live in sorted maps, so iteration
//! never depends on hashing. An edge is *split* when it has a midpoint vertex and two child edges
//! (`a-m`, `m-b`); a *leaf* edge is unsplit. A triangle's state (0-7) is the split status of its
//! three edges (see [`state_of`]); in states 0-6 the triangle owns the mesh faces that tile it
//! (state 0: itself; 1-6: its temporary state -1 children); in state 7 it has four regular
//! children (hierarchy triangles one level deeper) and owns no face.
//!
//! The hierarchy never changes the mesh itself: the operations (module `ops`) build one
//! [`crate::mesh::Edit`] per split or merge and commit the hierarchy change only once the edit was
//! applied.

use crate::math::Real;
use crate::mesh::{EdgeKey, FaceId, Mesh, VertexId};
use std::collections::{BTreeMap, BTreeSet};

/// A hierarchy triangle's key: its three vertices in increasing id order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TriKey(pub [VertexId; 3]);

impl TriKey {
    /// The key of the triangle with these corners (any order).
    pub fn new(mut corners: [VertexId; 3]) -> TriKey {
        corners.sort_unstable();
        TriKey(corners)
    }
}

/// The state number of a triangle (the source's Figure 3.6) from the split bits of its edges
/// (bit `k` = edge `k`, from corner `k` to corner `k + 1`): 0 none; 1, 2, 3 only edge 0, 1, 2;
/// 4 edges 0 and 1; 5 edges 1 and 2; 6 edges 2 and 0; 7 all three.
pub fn state_of(bits: u8) -> u8 {
    match bits & 0b111 {
        0b000 => 0,
        0b001 => 1,
        0b010 => 2,
        0b100 => 3,
        0b011 => 4,
        0b110 => 5,
        0b101 => 6,
        _ => 7,
    }
}

/// The split bits of a state number (inverse of [`state_of`]).
pub fn bits_of(state: u8) -> u8 {
    [0b000, 0b001, 0b010, 0b100, 0b011, 0b110, 0b101, 0b111][state as usize & 7]
}

/// The state of the temporary children that tile a triangle in states 1-6 (the source's -1).
pub const TEMPORARY_STATE: i8 = -1;

/// An edge of the hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct EdgeNode {
    /// Subdivision depth: 0 for edges of the initial mesh; children and the interior edges of a
    /// state-7 triangle of depth `d` have depth `d + 1`.
    pub depth: u32,
    /// The edge this one is half of (`None` for initial edges and interior edges).
    pub parent: Option<EdgeKey>,
    /// The midpoint vertex when split.
    pub mid: Option<VertexId>,
    /// The hierarchy triangles having this edge as one of their three edges (one or two, in key
    /// order). A child edge whose parent's neighbour is in states 1-6 has no triangle on that side:
    /// the faces there are temporary (state -1).
    pub tris: Vec<TriKey>,
    /// Simulated time (s) when the edge was created (`None` for edges of the initial mesh).
    pub born: Option<Real>,
    /// Simulated time (s) of the last split.
    pub split_at: Real,
}

impl EdgeNode {
    /// The two child edges of a split edge `e`.
    pub fn children(&self, e: EdgeKey) -> Option<[EdgeKey; 2]> {
        self.mid
            .map(|m| [EdgeKey::new(e.0, m), EdgeKey::new(m, e.1)])
    }
}

/// A triangle of the hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct TriNode {
    /// Corners, counter-clockwise in rest space.
    pub corners: [VertexId; 3],
    /// Depth: 0 for the initial faces, parent + 1 for regular children.
    pub depth: u32,
    /// The state-7 triangle this is a regular child of.
    pub parent: Option<TriKey>,
    /// The stored state 0-7; [`Hierarchy::check`] verifies it against the split status of the
    /// edges.
    pub state: u8,
    /// The mesh faces tiling this triangle in states 0-6 (one face in state 0, two or three
    /// temporary children in states 1-6); empty in state 7.
    pub faces: Vec<FaceId>,
    /// The four regular children in state 7: corner children 0, 1, 2 then the middle one.
    pub children: Option<[TriKey; 4]>,
    /// Simulated time (s) of the last state change.
    pub changed: Real,
}

impl TriNode {
    /// The key of edge `k` (corner `k` to corner `k + 1`).
    pub fn edge(&self, k: usize) -> EdgeKey {
        EdgeKey::new(self.corners[k], self.corners[(k + 1) % 3])
    }

    /// Which edge (0-2) `e` is, if it is one.
    pub fn edge_index(&self, e: EdgeKey) -> Option<usize> {
        (0..3).find(|&k| self.edge(k) == e)
    }
}

/// The hierarchy over a mesh: every edge and triangle ever created and still live, and the owner
/// of every mesh face.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Hierarchy {
    pub(crate) edges: BTreeMap<EdgeKey, EdgeNode>,
    pub(crate) tris: BTreeMap<TriKey, TriNode>,
    pub(crate) owner: BTreeMap<FaceId, TriKey>,
}

/// What a mesh edge is in the hierarchy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeRole {
    /// A hierarchy edge (a leaf when it is a mesh edge).
    Hierarchy(EdgeKey),
    /// An edge inside a triangle in states 1-6, between its temporary children.
    Temporary(TriKey),
}

impl Hierarchy {
    /// The hierarchy of an initial mesh: every face a depth-0 triangle in state 0, every edge a
    /// depth-0 leaf.
    pub fn new(mesh: &Mesh) -> Hierarchy {
        let mut h = Hierarchy::default();
        for f in mesh.faces() {
            let corners = mesh.face(f);
            let key = TriKey::new(corners);
            h.tris.insert(
                key,
                TriNode {
                    corners,
                    depth: 0,
                    parent: None,
                    state: 0,
                    faces: vec![f],
                    children: None,
                    changed: 0.0,
                },
            );
            h.owner.insert(f, key);
            for k in 0..3 {
                let e = EdgeKey::new(corners[k], corners[(k + 1) % 3]);
                h.edges
                    .entry(e)
                    .or_insert_with(|| EdgeNode {
                        depth: 0,
                        parent: None,
                        mid: None,
                        tris: Vec::new(),
                        born: None,
                        split_at: 0.0,
                    })
                    .tris
                    .push(key);
            }
        }
        for e in h.edges.values_mut() {
            e.tris.sort_unstable();
        }
        h
    }

    /// The hierarchy edge `e`, if it is one.
    pub fn edge(&self, e: EdgeKey) -> Option<&EdgeNode> {
        self.edges.get(&e)
    }

    /// The hierarchy triangle `t`, if it is one.
    pub fn triangle(&self, t: TriKey) -> Option<&TriNode> {
        self.tris.get(&t)
    }

    /// All hierarchy edges in key order.
    pub fn edges(&self) -> impl Iterator<Item = (EdgeKey, &EdgeNode)> + '_ {
        self.edges.iter().map(|(k, n)| (*k, n))
    }

    /// All hierarchy triangles in key order.
    pub fn triangles(&self) -> impl Iterator<Item = (TriKey, &TriNode)> + '_ {
        self.tris.iter().map(|(k, n)| (*k, n))
    }

    /// The hierarchy triangle owning mesh face `f` (the face itself in state 0, or one of its
    /// temporary children).
    pub fn owner(&self, f: FaceId) -> Option<TriKey> {
        self.owner.get(&f).copied()
    }

    /// The state of mesh face `f` as the source numbers it: its owner's state (0) when the face is
    /// the owner itself, [`TEMPORARY_STATE`] when it is a temporary child.
    pub fn face_state(&self, f: FaceId) -> Option<i8> {
        let t = &self.tris[&self.owner(f)?];
        Some(if t.state == 0 { 0 } else { TEMPORARY_STATE })
    }

    /// Which role the mesh edge `e` plays, looked up through the faces next to it.
    pub fn role(&self, mesh: &Mesh, e: EdgeKey) -> Option<EdgeRole> {
        if self.edges.contains_key(&e) {
            return Some(EdgeRole::Hierarchy(e));
        }
        let f = mesh.edge(e.0, e.1)?.first;
        self.owner(f).map(EdgeRole::Temporary)
    }

    /// The split bits of triangle `t`'s edges (bit k = edge k split), from the edge nodes.
    pub fn split_bits(&self, t: &TriNode) -> u8 {
        (0..3).fold(0, |bits, k| {
            let split = self.edges.get(&t.edge(k)).is_some_and(|e| e.mid.is_some());
            bits | (u8::from(split) << k)
        })
    }

    /// Deepest depth of any edge or triangle.
    pub fn max_depth(&self) -> u32 {
        let e = self.edges.values().map(|e| e.depth).max().unwrap_or(0);
        let t = self.tris.values().map(|t| t.depth).max().unwrap_or(0);
        e.max(t)
    }

    /// Number of split edges.
    pub fn split_count(&self) -> usize {
        self.edges.values().filter(|e| e.mid.is_some()).count()
    }

    /// Verifies the hierarchy against itself and the mesh: every triangle's stored state equals
    /// the state computed from its edges; triangles in states 0-6 own exactly the faces their
    /// state prescribes (same vertex triples), state-7 triangles own none and have four children
    /// in the hierarchy; the owned faces are exactly the mesh's faces; edges' triangle lists agree
    /// with the triangles; split edges have child edges one level deeper; no depth exceeds
    /// `max_depth`.
    pub fn check(&self, mesh: &Mesh, max_depth: u32) -> Result<(), String> {
        let mut owned = BTreeSet::new();
        for (&key, t) in &self.tris {
            let bits = self.split_bits(t);
            if state_of(bits) != t.state {
                return Err(format!(
                    "triangle {key:?} stored in state {} but its edges give state {}",
                    t.state,
                    state_of(bits)
                ));
            }
            if t.depth > max_depth {
                return Err(format!(
                    "triangle {key:?} at depth {} > {max_depth}",
                    t.depth
                ));
            }
            for k in 0..3 {
                let e = t.edge(k);
                let node = self
                    .edges
                    .get(&e)
                    .ok_or_else(|| format!("triangle {key:?} has no edge node {e:?}"))?;
                if !node.tris.contains(&key) {
                    return Err(format!("edge {e:?} does not list its triangle {key:?}"));
                }
            }
            if t.state == 7 {
                let children = t
                    .children
                    .ok_or_else(|| format!("state-7 triangle {key:?} has no children"))?;
                if !t.faces.is_empty() {
                    return Err(format!("state-7 triangle {key:?} owns faces"));
                }
                check_children(children, key, t.depth, "", |c| {
                    self.tris.get(c).map(|n| (n.parent, n.depth))
                })?;
                continue;
            }
            if t.children.is_some() {
                return Err(format!(
                    "triangle {key:?} in state {} has children",
                    t.state
                ));
            }
            let mut want: Vec<[VertexId; 3]> = self
                .active_faces(mesh, t, bits, None)
                .into_iter()
                .map(|f| canonical(f.map(|r| r.expect("no new vertex"))))
                .collect();
            let mut have: Vec<[VertexId; 3]> = Vec::new();
            for &f in &t.faces {
                if !mesh.is_face(f) || self.owner.get(&f) != Some(&key) {
                    return Err(format!(
                        "triangle {key:?} owns face {f:?} which is not live"
                    ));
                }
                have.push(canonical(mesh.face(f)));
                owned.insert(f);
            }
            want.sort_unstable();
            have.sort_unstable();
            if want != have {
                return Err(format!(
                    "triangle {key:?} in state {} has faces {have:?}, its state gives {want:?}",
                    t.state
                ));
            }
        }
        let live: BTreeSet<FaceId> = mesh.faces().collect();
        if live != owned || self.owner.len() != owned.len() {
            return Err(format!(
                "{} mesh faces, {} owned by hierarchy triangles in states 0-6 ({} in the owner map)",
                live.len(),
                owned.len(),
                self.owner.len()
            ));
        }
        for (&e, node) in &self.edges {
            if node.depth > max_depth {
                return Err(format!("edge {e:?} at depth {} > {max_depth}", node.depth));
            }
            for t in &node.tris {
                let tri = self
                    .tris
                    .get(t)
                    .ok_or_else(|| format!("edge {e:?} lists missing triangle {t:?}"))?;
                if tri.edge_index(e).is_none() {
                    return Err(format!("edge {e:?} lists {t:?} which does not contain it"));
                }
            }
            if let Some(children) = node.children(e) {
                check_children(children, e, node.depth, "split edge ", |c| {
                    self.edges.get(c).map(|n| (n.parent, n.depth))
                })?;
            }
            // A child edge lies in the corner children of its parent's state-7 triangles (on the
            // other sides: temporary children); any other edge has a triangle.
            let expected = match node.parent {
                Some(p) => {
                    let parent = self
                        .edges
                        .get(&p)
                        .ok_or_else(|| format!("parent {p:?} of {e:?} missing"))?;
                    parent
                        .tris
                        .iter()
                        .filter(|t| self.tris.get(t).is_some_and(|t| t.state == 7))
                        .count()
                }
                None => node.tris.len().max(1),
            };
            if node.tris.len() != expected {
                return Err(format!(
                    "edge {e:?} lists {} triangles, expected {expected}",
                    node.tris.len()
                ));
            }
        }
        Ok(())
    }

    /// The faces (corner triples, counter-clockwise) that tile triangle `t` when its split bits
    /// are `bits` (state 0-6; state 7 gives the four regular children). Midpoints come from the
    /// split edges; with `new_mid = Some(k)`, edge `k`'s midpoint is a vertex the caller is about
    /// to create (`None` in the triples; its rest point is the rest midpoint of edge `k`).
    pub fn active_faces(
        &self,
        mesh: &Mesh,
        t: &TriNode,
        bits: u8,
        new_mid: Option<usize>,
    ) -> Vec<[Option<VertexId>; 3]> {
        let c = t.corners.map(Some);
        let mid = |k: usize| -> Option<VertexId> {
            if new_mid == Some(k) {
                None
            } else {
                self.edges.get(&t.edge(k)).and_then(|e| e.mid)
            }
        };
        let rest = |v: Option<VertexId>, k: usize| match v {
            Some(v) => mesh.rest(v),
            None => (mesh.rest(t.corners[k]) + mesh.rest(t.corners[(k + 1) % 3])) * 0.5,
        };
        match state_of(bits) {
            0 => vec![c],
            s @ 1..=3 => {
                let k = (s - 1) as usize;
                let m = mid(k);
                vec![
                    [c[k], m, c[(k + 2) % 3]],
                    [m, c[(k + 1) % 3], c[(k + 2) % 3]],
                ]
            }
            s @ 4..=6 => {
                // Edges k and k + 1 split, sharing corner k + 1; the quad c_k, m_k, m_k+1, c_k+2
                // is cut by its shorter diagonal (rest space; ties take c_k - m_k+1).
                let k = (s - 4) as usize;
                let (k1, k2) = ((k + 1) % 3, (k + 2) % 3);
                let (mk, mk1) = (mid(k), mid(k1));
                let (pk, pk1) = (rest(mk, k), rest(mk1, k1));
                let d1 = (pk1 - mesh.rest(t.corners[k])).norm();
                let d2 = (mesh.rest(t.corners[k2]) - pk).norm();
                let mut out = vec![[mk, c[k1], mk1]];
                if d1 <= d2 {
                    out.push([c[k], mk, mk1]);
                    out.push([c[k], mk1, c[k2]]);
                } else {
                    out.push([c[k], mk, c[k2]]);
                    out.push([mk, mk1, c[k2]]);
                }
                out
            }
            _ => {
                let m = [mid(0), mid(1), mid(2)];
                vec![
                    [c[0], m[0], m[2]],
                    [m[0], c[1], m[1]],
                    [m[2], m[1], c[2]],
                    [m[0], m[1], m[2]],
                ]
            }
        }
    }
}

/// A face's vertex triple rotated so the smallest id comes first (orientation kept).
pub fn canonical(f: [VertexId; 3]) -> [VertexId; 3] {
    let k = (0..3).min_by_key(|&k| f[k]).unwrap_or(0);
    [f[k], f[(k + 1) % 3], f[(k + 2) % 3]]
}

/// Checks that every child exists (`get` gives its parent and depth), names `parent` as its
/// parent and lies one level below `depth`; `what` prefixes the parent in the message.
fn check_children<K: Copy + PartialEq + std::fmt::Debug>(
    children: impl IntoIterator<Item = K>,
    parent: K,
    depth: u32,
    what: &str,
    get: impl Fn(&K) -> Option<(Option<K>, u32)>,
) -> Result<(), String> {
    for c in children {
        let (p, d) = get(&c).ok_or_else(|| format!("child {c:?} of {what}{parent:?} missing"))?;
        if p != Some(parent) || d != depth + 1 {
            return Err(format!(
                "child {c:?} of {parent:?} has wrong parent or depth"
            ));
        }
    }
    Ok(())
}
