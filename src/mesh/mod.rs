//! Triangle mesh: topology and rest (pattern) geometry; no world state, no forces.
//!
//! Vertices and faces live in slots addressed by [`VertexId`] and [`FaceId`]. Slots freed by an edit
//! are reused (smallest first, so runs are deterministic) and every slot carries a generation that
//! is bumped when it is freed, so a strategy holding a [`VertexKey`] across edits can detect a stale
//! handle. Edges are derived from the faces and kept incrementally, each listed at its smaller
//! vertex in a short list sorted by the larger one: an edge is found by one index and a scan of a
//! few entries, and iteration runs in key order (by the ordered vertex pair), never depending on
//! hashing.
//!
//! Every change goes through [`Mesh::replace`] (module `edit`), which checks its preconditions,
//! leaves the mesh untouched on failure and returns an [`EditRecord`] of what changed; the state
//! transfer (module `adapt`) consumes that record. [`Mesh::check`] (module `check`) verifies every
//! conformity rule of MODEL.md §1.

mod check;
mod edit;
mod generate;
mod grid;
mod locate;
mod obj;
mod patch;
mod point_tree;

pub use check::{ConformityError, Rule};
pub use edit::{Edit, EditError, EditRecord, NewVertex, Origin, VertexRef};
pub use generate::{disk, union_jack};
pub use locate::{Barycentric, RestLocator, SNAP_REL_TOL};
pub use obj::{load_obj, ObjCloth, ObjError};
pub use patch::Patch;

use crate::math::{signed_area, Real, Vec2};
use std::collections::BTreeSet;

/// Most vertices a cloth may start with (and the most `adaptivity.max_vertices` may allow): a
/// run needs about [`BYTES_PER_VERTEX`] of memory per vertex, so this is about 4 GB, a sixth of
/// this project's 24 GB machines. Larger requests (a 100000 x 100000 grid) are refused up front
/// instead of aborting in an allocation.
pub const MAX_VERTICES: usize = 4_000_000;

/// Memory a run needs per vertex (bytes), rounded up from the peak resident size of a 500 x 500
/// grid run with `rk4` (206 MB for 250000 vertices): mesh, state, force elements, integrator
/// scratch.
pub const BYTES_PER_VERTEX: usize = 1024;

/// Index of a vertex slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct VertexId(pub u32);

/// Index of a face slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FaceId(pub u32);

/// A vertex handle that survives edits: the slot and its generation when the key was taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct VertexKey {
    /// The slot.
    pub id: VertexId,
    /// The slot's generation when the key was taken.
    pub generation: u32,
}

/// An undirected edge: its two vertices in increasing slot order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct EdgeKey(pub VertexId, pub VertexId);

impl EdgeKey {
    /// The edge between `a` and `b`, in either order.
    pub fn new(a: VertexId, b: VertexId) -> Self {
        if a <= b {
            EdgeKey(a, b)
        } else {
            EdgeKey(b, a)
        }
    }
}

/// The faces adjacent to an edge: one (cloth border) or two (interior edge).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EdgeFaces {
    /// The first adjacent face (the smallest id).
    pub first: FaceId,
    /// The second adjacent face, `None` on the cloth border.
    pub second: Option<FaceId>,
    /// Faces beyond two (only in a broken mesh; the conformity checker reports them).
    pub extra: u32,
}

impl EdgeFaces {
    /// The adjacent faces in id order.
    pub fn iter(&self) -> impl Iterator<Item = FaceId> {
        std::iter::once(self.first).chain(self.second)
    }

    /// True when the edge lies on the cloth border (exactly one adjacent face).
    pub fn is_border(&self) -> bool {
        self.second.is_none()
    }
}

/// The triangle mesh: rest coordinates, faces, derived edges and adjacency, pinned flags.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    rest: Vec<Vec2>,
    vertex_live: Vec<bool>,
    vertex_generation: Vec<u32>,
    pinned: Vec<bool>,
    free_vertices: BTreeSet<u32>,
    faces: Vec<[VertexId; 3]>,
    face_live: Vec<bool>,
    face_generation: Vec<u32>,
    free_faces: BTreeSet<u32>,
    /// Per vertex slot, the edges whose smaller vertex it is: the larger vertex and the adjacent
    /// faces, sorted by the larger vertex.
    lower_edges: Vec<Vec<(VertexId, EdgeFaces)>>,
    edge_count: usize,
    vertex_faces: Vec<Vec<FaceId>>,
    pattern_area: Real,
    version: u64,
}

/// Why a mesh could not be built from vertex and face lists.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    /// A face names a vertex index past the end of the vertex list.
    #[error("face {face} uses vertex {vertex}, but there are only {count} vertices")]
    VertexOutOfRange {
        /// Face index in the input list.
        face: usize,
        /// The offending vertex index.
        vertex: usize,
        /// Number of vertices given.
        count: usize,
    },
    /// The built mesh breaks a conformity rule.
    #[error("mesh is not conforming: {0}")]
    NotConforming(#[from] ConformityError),
}

impl Mesh {
    /// Builds a mesh from rest coordinates (m) and counter-clockwise faces, records the pattern
    /// area, and checks every conformity rule.
    pub fn from_faces(rest: Vec<Vec2>, faces: &[[usize; 3]]) -> Result<Mesh, MeshError> {
        let mut mesh = Mesh::with_capacity(rest.len(), faces.len());
        for &p in &rest {
            mesh.push_vertex(p);
        }
        for (i, f) in faces.iter().enumerate() {
            for &v in f {
                if v >= rest.len() {
                    return Err(MeshError::VertexOutOfRange {
                        face: i,
                        vertex: v,
                        count: rest.len(),
                    });
                }
            }
            mesh.push_face([
                VertexId(f[0] as u32),
                VertexId(f[1] as u32),
                VertexId(f[2] as u32),
            ]);
        }
        mesh.pattern_area = mesh.faces().map(|f| mesh.face_rest_area(f)).sum();
        mesh.check()?;
        Ok(mesh)
    }

    /// Number of live vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertex_live.len() - self.free_vertices.len()
    }

    /// Number of live faces.
    pub fn face_count(&self) -> usize {
        self.face_live.len() - self.free_faces.len()
    }

    /// Number of edges.
    pub fn edge_count(&self) -> usize {
        self.edge_count
    }

    /// Number of vertex slots (live or free): the length of per-vertex state arrays.
    pub fn vertex_slots(&self) -> usize {
        self.vertex_live.len()
    }

    /// Number of face slots (live or free).
    pub fn face_slots(&self) -> usize {
        self.face_live.len()
    }

    /// A counter bumped by every change of the topology or rest geometry: derived data built for
    /// one version must be rebuilt when it differs.
    pub fn version(&self) -> u64 {
        self.version
    }

    /// Total rest area of the pattern recorded at construction (m²): the conformity checker
    /// requires the faces to cover exactly this area.
    pub fn pattern_area(&self) -> Real {
        self.pattern_area
    }

    /// Live vertices in slot order.
    pub fn vertices(&self) -> impl Iterator<Item = VertexId> + '_ {
        (0..self.vertex_live.len() as u32)
            .filter(|&i| self.vertex_live[i as usize])
            .map(VertexId)
    }

    /// Live faces in slot order.
    pub fn faces(&self) -> impl Iterator<Item = FaceId> + '_ {
        (0..self.face_live.len() as u32)
            .filter(|&i| self.face_live[i as usize])
            .map(FaceId)
    }

    /// The live faces as the slot indices of their vertices (indices into per-slot arrays such
    /// as the cloth's positions), in [`Mesh::faces`] order.
    pub fn face_vertex_slots(&self) -> impl Iterator<Item = [usize; 3]> + '_ {
        self.faces().map(|f| self.face(f).map(|v| v.0 as usize))
    }

    /// Edges in key order, with their adjacent faces.
    pub fn edges(&self) -> impl Iterator<Item = (EdgeKey, &EdgeFaces)> + '_ {
        self.lower_edges.iter().enumerate().flat_map(|(a, list)| {
            list.iter()
                .map(move |(b, faces)| (EdgeKey(VertexId(a as u32), *b), faces))
        })
    }

    /// The faces adjacent to the edge between `a` and `b`, if that edge exists.
    pub fn edge(&self, a: VertexId, b: VertexId) -> Option<&EdgeFaces> {
        let key = EdgeKey::new(a, b);
        let list = self.lower_edges.get(key.0 .0 as usize)?;
        let k = list.binary_search_by_key(&key.1, |&(b, _)| b).ok()?;
        Some(&list[k].1)
    }

    /// True when `v` is a live vertex slot.
    pub fn is_vertex(&self, v: VertexId) -> bool {
        self.vertex_live.get(v.0 as usize).copied().unwrap_or(false)
    }

    /// True when `f` is a live face slot.
    pub fn is_face(&self, f: FaceId) -> bool {
        self.face_live.get(f.0 as usize).copied().unwrap_or(false)
    }

    /// The key (slot and generation) of a live vertex.
    pub fn key(&self, v: VertexId) -> VertexKey {
        VertexKey {
            id: v,
            generation: self.vertex_generation[v.0 as usize],
        }
    }

    /// The vertex a key names, or `None` when the slot was freed since the key was taken.
    pub fn resolve(&self, key: VertexKey) -> Option<VertexId> {
        (self.is_vertex(key.id) && self.vertex_generation[key.id.0 as usize] == key.generation)
            .then_some(key.id)
    }

    /// Rest coordinates of a vertex (m). The slot must be live.
    pub fn rest(&self, v: VertexId) -> Vec2 {
        self.rest[v.0 as usize]
    }

    /// The rest coordinates (m) of every vertex slot, free slots included (their values are
    /// meaningless).
    pub fn rest_slots(&self) -> &[Vec2] {
        &self.rest
    }

    /// True when the vertex is pinned (never moves).
    pub fn is_pinned(&self, v: VertexId) -> bool {
        self.pinned[v.0 as usize]
    }

    /// Pins or unpins a vertex.
    pub fn set_pinned(&mut self, v: VertexId, pinned: bool) {
        self.pinned[v.0 as usize] = pinned;
    }

    /// The three vertices of a face, counter-clockwise in rest space. The slot must be live.
    pub fn face(&self, f: FaceId) -> [VertexId; 3] {
        self.faces[f.0 as usize]
    }

    /// Faces incident to a vertex, in id order.
    pub fn vertex_faces(&self, v: VertexId) -> &[FaceId] {
        &self.vertex_faces[v.0 as usize]
    }

    /// Signed rest area of a face (m²); positive for a valid face.
    pub fn face_rest_area(&self, f: FaceId) -> Real {
        let [a, b, c] = self.face(f);
        signed_area(self.rest(a), self.rest(b), self.rest(c))
    }

    /// Rest length of the edge between `a` and `b` (m).
    pub fn rest_length(&self, a: VertexId, b: VertexId) -> Real {
        (self.rest(b) - self.rest(a)).norm()
    }

    /// The longest rest edge of the mesh (m); 0 for a mesh without edges.
    pub fn longest_rest_edge(&self) -> Real {
        self.edges()
            .map(|(e, _)| self.rest_length(e.0, e.1))
            .fold(0.0, Real::max)
    }

    /// Barycentric rest area of a vertex: a third of the rest areas of its faces (m²).
    pub fn vertex_rest_area(&self, v: VertexId) -> Real {
        self.vertex_faces(v)
            .iter()
            .map(|&f| self.face_rest_area(f))
            .sum::<Real>()
            / 3.0
    }

    /// Live vertices adjacent to `v` through an edge, in id order.
    pub fn neighbours(&self, v: VertexId) -> Vec<VertexId> {
        let mut out: Vec<VertexId> = self
            .vertex_faces(v)
            .iter()
            .flat_map(|&f| self.face(f))
            .filter(|&w| w != v)
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The vertex of face `f` that is not on edge `(a, b)`, if `f` contains that edge.
    pub fn opposite(&self, f: FaceId, a: VertexId, b: VertexId) -> Option<VertexId> {
        let vs = self.face(f);
        if !(vs.contains(&a) && vs.contains(&b)) {
            return None;
        }
        vs.into_iter().find(|&w| w != a && w != b)
    }

    /// True when the vertex lies on the cloth border (it has a border edge).
    pub fn is_border_vertex(&self, v: VertexId) -> bool {
        self.neighbours(v)
            .into_iter()
            .any(|w| self.edge(v, w).map(|e| e.is_border()).unwrap_or(false))
    }

    // ----- low-level slot operations, used by `edit` and the constructors only -----

    /// An empty mesh with room for `vertices` vertex slots and `faces` face slots.
    fn with_capacity(vertices: usize, faces: usize) -> Mesh {
        Mesh {
            rest: Vec::with_capacity(vertices),
            vertex_live: Vec::with_capacity(vertices),
            vertex_generation: Vec::with_capacity(vertices),
            pinned: Vec::with_capacity(vertices),
            vertex_faces: Vec::with_capacity(vertices),
            lower_edges: Vec::with_capacity(vertices),
            faces: Vec::with_capacity(faces),
            face_live: Vec::with_capacity(faces),
            face_generation: Vec::with_capacity(faces),
            ..Mesh::default()
        }
    }

    fn push_vertex(&mut self, rest: Vec2) -> VertexId {
        self.version += 1;
        if let Some(slot) = self.free_vertices.pop_first() {
            let i = slot as usize;
            self.rest[i] = rest;
            self.vertex_live[i] = true;
            self.pinned[i] = false;
            self.vertex_faces[i].clear();
            self.lower_edges[i].clear();
            return VertexId(slot);
        }
        self.rest.push(rest);
        self.vertex_live.push(true);
        self.vertex_generation.push(0);
        self.pinned.push(false);
        // Room for an interior vertex's faces (six to eight on the meshes made here).
        self.vertex_faces.push(Vec::with_capacity(8));
        self.lower_edges.push(Vec::new());
        VertexId(self.rest.len() as u32 - 1)
    }

    fn free_vertex(&mut self, v: VertexId) {
        self.version += 1;
        let i = v.0 as usize;
        debug_assert!(self.vertex_faces[i].is_empty());
        self.vertex_live[i] = false;
        self.pinned[i] = false;
        self.vertex_generation[i] = self.vertex_generation[i].wrapping_add(1);
        self.free_vertices.insert(v.0);
    }

    fn push_face(&mut self, vs: [VertexId; 3]) -> FaceId {
        self.version += 1;
        let f = if let Some(slot) = self.free_faces.pop_first() {
            self.faces[slot as usize] = vs;
            self.face_live[slot as usize] = true;
            FaceId(slot)
        } else {
            self.faces.push(vs);
            self.face_live.push(true);
            self.face_generation.push(0);
            FaceId(self.faces.len() as u32 - 1)
        };
        for k in 0..3 {
            let v = vs[k];
            let list = &mut self.vertex_faces[v.0 as usize];
            let pos = list.partition_point(|&g| g < f);
            list.insert(pos, f);
            let key = EdgeKey::new(vs[k], vs[(k + 1) % 3]);
            let list = &mut self.lower_edges[key.0 .0 as usize];
            match list.binary_search_by_key(&key.1, |&(b, _)| b) {
                Err(at) => {
                    let faces = EdgeFaces {
                        first: f,
                        second: None,
                        extra: 0,
                    };
                    list.insert(at, (key.1, faces));
                    self.edge_count += 1;
                }
                Ok(at) => match list[at].1.second {
                    None => {
                        let e = &mut list[at].1;
                        if f < e.first {
                            e.second = Some(e.first);
                            e.first = f;
                        } else {
                            e.second = Some(f);
                        }
                    }
                    Some(_) => list[at].1.extra += 1,
                },
            }
        }
        f
    }

    fn free_face(&mut self, f: FaceId) {
        self.version += 1;
        let vs = self.faces[f.0 as usize];
        for k in 0..3 {
            let list = &mut self.vertex_faces[vs[k].0 as usize];
            if let Ok(pos) = list.binary_search(&f) {
                list.remove(pos);
            }
            let key = EdgeKey::new(vs[k], vs[(k + 1) % 3]);
            let list = &mut self.lower_edges[key.0 .0 as usize];
            if let Ok(at) = list.binary_search_by_key(&key.1, |&(b, _)| b) {
                let e = &mut list[at].1;
                if e.extra > 0 {
                    // Broken meshes only: which face stays listed no longer matters.
                    e.extra -= 1;
                } else if e.first == f {
                    match e.second {
                        Some(s) => {
                            e.first = s;
                            e.second = None;
                        }
                        None => {
                            list.remove(at);
                            self.edge_count -= 1;
                        }
                    }
                } else if e.second == Some(f) {
                    e.second = None;
                }
            }
        }
        self.face_live[f.0 as usize] = false;
        self.face_generation[f.0 as usize] = self.face_generation[f.0 as usize].wrapping_add(1);
        self.free_faces.insert(f.0);
    }
}
