//! Broad phase of self-contact: a bounding-volume hierarchy (parry's `Bvh`) over the cloth's
//! faces, each boxed over its motion in the step and grown by the thickness; rebuilt when the
//! mesh changes, refitted otherwise. The tree traversed against itself gives the pairs of faces
//! whose boxes meet.
//!
//! Each vertex and each edge is owned by one face holding it (the first in the face list), and a
//! face pair `(A, B)` yields the vertex-face pairs of the vertices A owns against B (and B's
//! against A) and the edge-edge pairs of the edges A owns against those B owns. A vertex's or an
//! edge's box lies inside its owner's, so every vertex-face and edge-edge pair whose boxes meet
//! comes from exactly one face pair: no pair is tested twice and none is missed.

use super::super::shape::to_glam;
use crate::math::{Real, Vec3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use std::collections::HashSet;

/// An axis-aligned box (m): lowest and highest corners.
pub type Bounds = [Vec3; 2];

/// The box of points `p`, grown by `pad` (m) on every side.
pub fn bounds_of(points: &[Vec3], pad: Real) -> Bounds {
    let mut lo = points[0];
    let mut hi = points[0];
    for p in &points[1..] {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let pad = Vec3::repeat(pad);
    [lo - pad, hi + pad]
}

/// Whether two boxes meet.
pub fn overlap(a: &Bounds, b: &Bounds) -> bool {
    (0..3).all(|k| a[0][k] <= b[1][k] && b[0][k] <= a[1][k])
}

/// The faces, the edges and vertices each owns, and the tree over the faces' swept boxes.
#[derive(Default)]
pub struct FaceTree {
    /// The faces (vertex slots).
    pub faces: Vec<[usize; 3]>,
    /// Start in `owned_vertices` of each face's vertices (one more entry than faces).
    vertex_start: Vec<usize>,
    owned_vertices: Vec<usize>,
    /// Start in `owned_edges` of each face's edges (one more entry than faces).
    edge_start: Vec<usize>,
    owned_edges: Vec<[usize; 2]>,
    /// Each face's swept box over the step, grown by the thickness (m).
    pub boxes: Vec<Bounds>,
    bvh: Bvh,
    workspace: BvhWorkspace,
    /// The pairs of faces whose boxes meet, from the last [`FaceTree::pairs`].
    pub pairs: Vec<(usize, usize)>,
}

impl FaceTree {
    /// Takes a new face list: the ownership of vertices and edges; the tree is built at the next
    /// [`FaceTree::update`].
    pub fn set_faces(&mut self, faces: impl Iterator<Item = [usize; 3]>) {
        self.faces.clear();
        self.faces.extend(faces);
        let mut vertex_seen = HashSet::new();
        let mut edge_seen = HashSet::new();
        self.vertex_start.clear();
        self.owned_vertices.clear();
        self.edge_start.clear();
        self.owned_edges.clear();
        for f in &self.faces {
            self.vertex_start.push(self.owned_vertices.len());
            self.edge_start.push(self.owned_edges.len());
            for k in 0..3 {
                if vertex_seen.insert(f[k]) {
                    self.owned_vertices.push(f[k]);
                }
                let (a, b) = (f[k], f[(k + 1) % 3]);
                let edge = [a.min(b), a.max(b)];
                if edge_seen.insert(edge) {
                    self.owned_edges.push(edge);
                }
            }
        }
        self.vertex_start.push(self.owned_vertices.len());
        self.edge_start.push(self.owned_edges.len());
        self.boxes.clear();
        self.bvh = Bvh::new();
    }

    /// The vertices face `f` owns.
    pub fn vertices_of(&self, f: usize) -> &[usize] {
        &self.owned_vertices[self.vertex_start[f]..self.vertex_start[f + 1]]
    }

    /// The indices in [`FaceTree::edges`] of the edges face `f` owns.
    pub fn edges_of(&self, f: usize) -> std::ops::Range<usize> {
        self.edge_start[f]..self.edge_start[f + 1]
    }

    /// Every edge of the faces once (vertex slots, ascending), grouped by owner face.
    pub fn edges(&self) -> &[[usize; 2]] {
        &self.owned_edges
    }

    /// Every vertex of the faces, once.
    pub fn vertices(&self) -> &[usize] {
        &self.owned_vertices
    }

    /// Boxes each face over its motion `x_start -> x` (m) grown by `pad` (m), and builds the
    /// tree (after [`FaceTree::set_faces`]) or refits it.
    pub fn update(&mut self, x_start: &[Vec3], x: &[Vec3], pad: Real) {
        let fresh = self.boxes.len() != self.faces.len();
        self.boxes.clear();
        for f in &self.faces {
            let corners = [
                x_start[f[0]],
                x_start[f[1]],
                x_start[f[2]],
                x[f[0]],
                x[f[1]],
                x[f[2]],
            ];
            self.boxes.push(bounds_of(&corners, pad));
        }
        let aabb = |b: &Bounds| Aabb::new(to_glam(b[0]), to_glam(b[1]));
        if fresh {
            let leaves: Vec<Aabb> = self.boxes.iter().map(aabb).collect();
            self.bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves);
        } else {
            for (i, b) in self.boxes.iter().enumerate() {
                self.bvh.insert_or_update_partially(aabb(b), i as u32, 0.0);
            }
            self.bvh.refit(&mut self.workspace);
        }
    }

    /// Lists in [`FaceTree::pairs`] the pairs of distinct faces whose boxes meet, each once, in
    /// the tree's order.
    pub fn find_pairs(&mut self) {
        self.pairs.clear();
        let pairs = &mut self.pairs;
        self.bvh
            .traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut |a, b| {
                if a != b {
                    pairs.push((a as usize, b as usize));
                }
            });
    }
}
