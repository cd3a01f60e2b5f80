//! The simulated body: the mesh, the world state of its vertices, and the derived physical
//! parameters ([`ForceModel`]) kept in step with the mesh.
//!
//! Per-vertex arrays (`x`, `v`, masses) are indexed by vertex slot; free slots hold zeros and have
//! zero inverse mass, so integrators can sweep every slot without branching on liveness.

use crate::math::{Real, Vec3};
use crate::mesh::{Barycentric, Mesh};
use crate::physics::{ForceModel, Forces, Material};

/// Mesh + world state + physical parameters.
pub struct Cloth {
    /// Topology and rest geometry.
    pub mesh: Mesh,
    /// World positions per vertex slot (m).
    pub x: Vec<Vec3>,
    /// Velocities per vertex slot (m/s).
    pub v: Vec<Vec3>,
    /// Masses, drag, springs and bending elements derived from the mesh and the material.
    pub model: ForceModel,
    elements_version: u64,
}

impl Cloth {
    /// A cloth from a mesh and world positions per vertex slot (m), all with velocity `velocity`
    /// (m/s; pinned vertices get zero).
    pub fn new(
        mesh: Mesh,
        positions: Vec<Vec3>,
        velocity: Vec3,
        material: &Material,
        forces: &Forces,
    ) -> Cloth {
        let mut model = ForceModel::new(material, forces);
        model.rebuild(&mesh);
        let mut v = vec![Vec3::zeros(); mesh.vertex_slots()];
        for i in mesh.vertices() {
            if !mesh.is_pinned(i) {
                v[i.0 as usize] = velocity;
            }
        }
        let elements_version = mesh.version();
        Cloth {
            mesh,
            x: positions,
            v,
            model,
            elements_version,
        }
    }

    /// Rebuilds the spring and bending arrays if the mesh changed since they were built, and sizes
    /// the state arrays to the slot count. Returns true when a rebuild happened.
    pub fn refresh(&mut self) -> bool {
        self.refresh_state_len();
        if self.elements_version == self.mesh.version() {
            return false;
        }
        self.model.rebuild_elements(&self.mesh);
        self.elements_version = self.mesh.version();
        true
    }

    /// Sizes the state arrays to the mesh's vertex slot count (new slots hold zeros).
    pub fn refresh_state_len(&mut self) {
        let slots = self.mesh.vertex_slots();
        self.x.resize(slots, Vec3::zeros());
        self.v.resize(slots, Vec3::zeros());
    }

    /// World position (m) of a located material point.
    pub fn world_position(&self, at: &Barycentric) -> Vec3 {
        let vs = self.mesh.face(at.face);
        (0..3)
            .map(|k| self.x[vs[k].0 as usize] * at.weights[k])
            .sum()
    }

    /// Total linear momentum (kg m/s).
    pub fn linear_momentum(&self) -> Vec3 {
        let m = self.model.mass();
        self.mesh
            .vertices()
            .map(|i| self.v[i.0 as usize] * m[i.0 as usize])
            .sum()
    }

    /// Total kinetic energy (J).
    pub fn kinetic_energy(&self) -> Real {
        let m = self.model.mass();
        self.mesh
            .vertices()
            .map(|i| 0.5 * m[i.0 as usize] * self.v[i.0 as usize].norm_squared())
            .sum()
    }
}
