//! Flat spring and bending arrays built from the mesh and the material (MODEL.md §2-§3).
//!
//! Both element sets are struct-of-arrays in edge-key order (sorted by the smaller vertex slot), so
//! a force sweep reads memory sequentially and touches vertices roughly in slot order. They depend
//! only on the mesh topology and rest geometry and are rebuilt when the mesh changes, reusing their
//! allocations.

use super::params::{Material, StiffnessModel};
use crate::math::Real;
use crate::mesh::{EdgeKey, Mesh, VertexId};

/// Every edge of the mesh as a spring, in edge-key order. All arrays have the same length.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Springs {
    /// First end (vertex slot), the smaller slot of the edge.
    pub a: Vec<u32>,
    /// Second end (vertex slot).
    pub b: Vec<u32>,
    /// Rest length `L_j` (m), from rest space.
    pub rest_length: Vec<Real>,
    /// Stiffness `k_j` (N/m): `E T S_j / L_j²` (`area_weighted`) or `E A0 / L_j` (`seed`).
    pub k: Vec<Real>,
    /// Damping coefficient `kd_j = alpha k_j` (N s/m).
    pub kd: Vec<Real>,
}

impl Springs {
    /// Number of springs.
    pub fn len(&self) -> usize {
        self.a.len()
    }

    /// True when there is no spring.
    pub fn is_empty(&self) -> bool {
        self.a.is_empty()
    }

    fn reserve(&mut self, springs: usize) {
        self.a.reserve(springs);
        self.b.reserve(springs);
        self.rest_length.reserve(springs);
        self.k.reserve(springs);
        self.kd.reserve(springs);
    }

    fn clear(&mut self) {
        self.a.clear();
        self.b.clear();
        self.rest_length.clear();
        self.k.clear();
        self.kd.clear();
    }

    /// Rebuilds the springs of `mesh` for `material`, reusing the allocations.
    pub(crate) fn rebuild(&mut self, mesh: &Mesh, material: &Material) {
        self.clear();
        self.reserve(mesh.edge_count());
        for (EdgeKey(a, b), faces) in mesh.edges() {
            let rest_length = mesh.rest_length(a, b);
            let k = match material.stiffness {
                StiffnessModel::AreaWeighted => {
                    let s: Real = faces.iter().map(|f| mesh.face_rest_area(f)).sum();
                    material.young * material.thickness * s / (rest_length * rest_length)
                }
                StiffnessModel::Seed => material.young * material.cross_section / rest_length,
            };
            self.a.push(a.0);
            self.b.push(b.0);
            self.rest_length.push(rest_length);
            self.k.push(k);
            self.kd.push(material.alpha * k);
        }
    }

    /// Keeps the springs having an end for which `keep` holds, in order.
    pub(crate) fn retain_touching(&mut self, keep: impl Fn(u32) -> bool) {
        let mut n = 0;
        for j in 0..self.len() {
            if keep(self.a[j]) || keep(self.b[j]) {
                self.a[n] = self.a[j];
                self.b[n] = self.b[j];
                self.rest_length[n] = self.rest_length[j];
                self.k[n] = self.k[j];
                self.kd[n] = self.kd[j];
                n += 1;
            }
        }
        self.a.truncate(n);
        self.b.truncate(n);
        self.rest_length.truncate(n);
        self.k.truncate(n);
        self.kd.truncate(n);
    }

    /// Largest stiffness (N/m), 0 when there is no spring.
    pub fn max_stiffness(&self) -> Real {
        self.k.iter().copied().fold(0.0, Real::max)
    }
}

/// Every interior edge (two adjacent faces) as a Bridson bending element, in edge-key order.
///
/// `v[j] = [x1, x2, x3, x4]` (vertex slots) with the notation of MODEL.md (4.10): `x1` and `x2`
/// are the vertices opposite the shared edge `x3 -> x4`. The order is taken from the faces: the
/// face holding `x1` traverses the edge as `x3 -> x4` and the other one as `x4 -> x3`, so both
/// face normals `N1 = (x1 - x3) x (x1 - x4)` and `N2 = (x2 - x4) x (x2 - x3)` point to the same
/// side of a flat cloth and the sign of the dihedral angle is consistent across the mesh. The
/// rest angle is flat (the pattern is flat), so no per-element constant is needed: the stiffness
/// `k_b` and damping `k_bd` are material constants.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bends {
    /// The four vertex slots `[x1, x2, x3, x4]` of each element.
    pub v: Vec<[u32; 4]>,
}

impl Bends {
    /// Number of bending elements.
    pub fn len(&self) -> usize {
        self.v.len()
    }

    /// True when there is no bending element.
    pub fn is_empty(&self) -> bool {
        self.v.is_empty()
    }

    /// Keeps the elements having a vertex for which `keep` holds, in order.
    pub(crate) fn retain_touching(&mut self, keep: impl Fn(u32) -> bool) {
        self.v.retain(|e| e.iter().any(|&i| keep(i)));
    }

    /// Rebuilds the bending elements of `mesh`, reusing the allocation. Edges with more than two
    /// faces (a broken mesh) use their first two.
    pub(crate) fn rebuild(&mut self, mesh: &Mesh) {
        self.v.clear();
        self.v.reserve(mesh.edge_count());
        for (EdgeKey(a, b), faces) in mesh.edges() {
            let Some(second) = faces.second else {
                continue;
            };
            let first = faces.first;
            let (x3, x4) = if traverses(mesh.face(first), a, b) {
                (a, b)
            } else {
                (b, a)
            };
            let (Some(x1), Some(x2)) = (mesh.opposite(first, a, b), mesh.opposite(second, a, b))
            else {
                continue;
            };
            self.v.push([x1.0, x2.0, x3.0, x4.0]);
        }
    }
}

/// True when the face's counter-clockwise cycle contains the directed edge `from -> to`.
fn traverses(face: [VertexId; 3], from: VertexId, to: VertexId) -> bool {
    (0..3).any(|k| face[k] == from && face[(k + 1) % 3] == to)
}
