//! The back-off every adaptive strategy applies to refused edits: an edge whose edit was refused
//! (by the energy law, or by remesh's mesher when coarsening) waits before the strategy tries it
//! again, instead of being tried, and refused, at every pass (each try is a trial on a patch).
//!
//! The wait is `t_simplify` after a first refusal, doubled by each further refusal of the edge up
//! to `MAX_WAIT` times `t_simplify`. An energy refusal ends early once the relative kinetic
//! energy of the refused edges' vertices could pay the refused gain (the edit would then be let
//! through); a coarsening refusal holds only coarsening (the edge may be refined). A refusal
//! quiet for twice its wait is forgotten: the edge's next refusal waits `t_simplify` afresh.

use super::{relative_kinetic_energy, EnergyRefusal};
use crate::cloth::Cloth;
use crate::math::Real;
use crate::mesh::{EdgeKey, Mesh, VertexId, VertexKey};
use std::collections::BTreeMap;
use std::sync::Arc;

/// Longest wait (in units of `t_simplify`) of an edge that keeps being refused.
pub const MAX_WAIT: Real = 16.0;

/// The direction of an edit: a finer mesh or a coarser one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub enum Direction {
    /// A finer mesh (more vertices).
    #[default]
    Refine,
    /// A coarser mesh (fewer vertices).
    Simplify,
}

/// Who refused an edit, which says what its edges wait for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cause {
    /// The energy law: the edit would have added `gain` (J). The edges wait, in either
    /// direction, until the wait ends or their vertices' relative motion could pay the gain.
    Energy {
        /// The energy (J) the edit would have added.
        gain: Real,
    },
    /// No acceptable coarser mesh was found. The edges are not coarsened again until the wait
    /// ends; they may be refined.
    Coarsening,
}

impl From<EnergyRefusal> for Cause {
    /// The energy law's refusal: the edges wait for motion that could pay its gain.
    fn from(r: EnergyRefusal) -> Self {
        Cause::Energy { gain: r.gain }
    }
}

/// The last refusal of an edit, shared by its edges.
#[derive(Clone, Debug, PartialEq)]
struct Refusal {
    /// Simulated time (s) of the refusal.
    at: Real,
    /// Who refused, and what the edges wait for.
    cause: Cause,
    /// How long (s) after `at` the edges wait.
    wait: Real,
    /// For an energy refusal, the ends of the refused edges, whose relative motion may pay the
    /// gain; empty for a coarsening.
    vertices: Vec<VertexKey>,
}

/// The refusals a strategy remembers, per edge (by its vertices' keys, which outlive the edits
/// around them).
#[derive(Clone, Debug, Default)]
pub struct RefusalMemory {
    refused_at: BTreeMap<(VertexKey, VertexKey), Arc<Refusal>>,
}

fn edge_keys(mesh: &Mesh, e: EdgeKey) -> (VertexKey, VertexKey) {
    (mesh.key(e.0), mesh.key(e.1))
}

impl RefusalMemory {
    /// Forgets refusals of edges whose vertices are gone and refusals quiet at time `now` (s)
    /// for twice their wait.
    pub fn prune(&mut self, mesh: &Mesh, now: Real) {
        self.refused_at.retain(|(a, b), r| {
            mesh.resolve(*a).is_some() && mesh.resolve(*b).is_some() && now - r.at < 2.0 * r.wait
        });
    }

    /// True when `edge` (between two vertices of the cloth, joined by a mesh edge or not) waits
    /// at time `now` (s) to be edited in `direction`: an edit of it was refused within that
    /// refusal's wait, by the energy law while the relative kinetic energy of that edit's
    /// vertices still cannot pay the refused gain, or for want of a coarser mesh and
    /// `direction` coarsens.
    pub fn waiting(&self, cloth: &Cloth, edge: EdgeKey, now: Real, direction: Direction) -> bool {
        let Some(r) = self.refused_at.get(&edge_keys(&cloth.mesh, edge)) else {
            return false;
        };
        if now - r.at >= r.wait {
            return false;
        }
        match r.cause {
            Cause::Energy { gain } => {
                let vertices: Vec<VertexId> = r
                    .vertices
                    .iter()
                    .filter_map(|&k| cloth.mesh.resolve(k))
                    .collect();
                relative_kinetic_energy(cloth, &vertices) < gain
            }
            Cause::Coarsening => direction == Direction::Simplify,
        }
    }

    /// Remembers a refusal for `cause` at `now` (s) of the edit of `edges`: they wait
    /// `t_simplify` (s), or twice the longest wait of an edge among them still remembered, at
    /// most `MAX_WAIT` times `t_simplify`.
    pub fn remember(
        &mut self,
        mesh: &Mesh,
        edges: &[EdgeKey],
        now: Real,
        cause: Cause,
        t_simplify: Real,
    ) {
        let mut vertices: Vec<VertexKey> = match cause {
            Cause::Energy { .. } => edges
                .iter()
                .flat_map(|e| {
                    let faces = mesh.edge(e.0, e.1).into_iter().flat_map(|ef| ef.iter());
                    faces.flat_map(|f| mesh.face(f)).chain([e.0, e.1])
                })
                .map(|v| mesh.key(v))
                .collect(),
            Cause::Coarsening => Vec::new(),
        };
        vertices.sort_unstable();
        vertices.dedup();
        let wait = edges
            .iter()
            .filter_map(|&e| self.refused_at.get(&edge_keys(mesh, e)))
            .map(|r| (2.0 * r.wait).min(MAX_WAIT * t_simplify))
            .fold(t_simplify, Real::max);
        let refusal = Arc::new(Refusal {
            at: now,
            cause,
            wait,
            vertices,
        });
        for &e in edges {
            self.refused_at.insert(edge_keys(mesh, e), refusal.clone());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn e(a: u32, b: u32) -> EdgeKey {
        EdgeKey::new(VertexId(a), VertexId(b))
    }

    /// An edge of an edit the energy law refused waits `t_simplify`, twice that after a second
    /// refusal, at most 16 times that; not at all once its vertices' relative motion could pay
    /// the refused gain; and `prune` forgets an old refusal without losing a newer one.
    #[test]
    fn an_energy_refused_edge_waits_longer_each_time_unless_its_motion_can_pay() {
        use Direction::{Refine, Simplify};
        let mut cloth = crate::testing::flat_cloth(3, Vec3::zeros());
        let (t_simplify, gain) = (0.1, 1e-6);
        let energy = Cause::Energy { gain };
        let (edge, other) = (e(0, 1), e(7, 8));
        let mut m = RefusalMemory::default();
        m.remember(&cloth.mesh, &[edge], 0.0, energy, t_simplify);
        assert!(m.waiting(&cloth, edge, 0.09, Refine) && !m.waiting(&cloth, edge, 0.11, Refine));
        assert!(
            m.waiting(&cloth, edge, 0.09, Simplify),
            "either direction waits"
        );
        assert!(
            !m.waiting(&cloth, other, 0.05, Refine),
            "an edge never refused"
        );
        m.remember(&cloth.mesh, &[edge], 0.1, energy, t_simplify);
        assert!(m.waiting(&cloth, edge, 0.29, Refine) && !m.waiting(&cloth, edge, 0.31, Refine));
        for _ in 0..10 {
            m.remember(&cloth.mesh, &[edge], 0.3, energy, t_simplify);
        }
        assert!(
            m.waiting(&cloth, edge, 0.3 + 1.59, Refine)
                && !m.waiting(&cloth, edge, 0.3 + 1.61, Refine)
        );

        // The edge's two vertices moving apart hold more than the gain: tried at once.
        cloth.v[0] = Vec3::new(-1.0, 0.0, 0.0);
        cloth.v[1] = Vec3::new(1.0, 0.0, 0.0);
        let payable = relative_kinetic_energy(&cloth, &[VertexId(0), VertexId(1)]);
        assert!(payable > gain, "{payable}");
        assert!(!m.waiting(&cloth, edge, 0.31, Refine));
        cloth.v[0] = Vec3::zeros();
        cloth.v[1] = Vec3::zeros();

        // A later refusal of another edge survives pruning the first (quiet for twice its wait).
        m.remember(&cloth.mesh, &[other], 3.45, energy, t_simplify);
        m.prune(&cloth.mesh, 0.3 + 2.0 * 1.6 + 0.01);
        assert!(m.waiting(&cloth, other, 3.52, Refine), "kept");
        m.remember(&cloth.mesh, &[edge], 3.6, energy, t_simplify);
        assert!(
            m.waiting(&cloth, edge, 3.69, Refine) && !m.waiting(&cloth, edge, 3.71, Refine),
            "after being forgotten, an edge waits t_simplify again"
        );
    }

    /// An edge the mesher could not coarsen waits to be coarsened again (`t_simplify`, doubled
    /// by a further refusal), not to be refined.
    #[test]
    fn an_edge_that_could_not_be_coarsened_waits_to_be_coarsened_not_refined() {
        use Direction::{Refine, Simplify};
        let cloth = crate::testing::flat_cloth(3, Vec3::zeros());
        let (edge, t_simplify) = (e(0, 1), 0.1);
        let mut m = RefusalMemory::default();
        m.remember(&cloth.mesh, &[edge], 0.0, Cause::Coarsening, t_simplify);
        assert!(m.waiting(&cloth, edge, 0.09, Simplify));
        assert!(!m.waiting(&cloth, edge, 0.11, Simplify));
        assert!(!m.waiting(&cloth, edge, 0.05, Refine));
        m.remember(&cloth.mesh, &[edge], 0.1, Cause::Coarsening, t_simplify);
        assert!(m.waiting(&cloth, edge, 0.29, Simplify));
        assert!(!m.waiting(&cloth, edge, 0.31, Simplify));
    }

    /// The wait of an energy refusal ends once the motion of the vertices of the refused edge's
    /// faces could pay (the vertices whose relative motion the law's payment draws on), the
    /// opposite corners included.
    #[test]
    fn the_motion_of_the_refused_edges_faces_can_end_the_wait() {
        let mut cloth = crate::testing::flat_cloth(3, Vec3::zeros());
        let mut m = RefusalMemory::default();
        let edge = e(0, 4);
        let faces: Vec<_> = cloth.mesh.edge(edge.0, edge.1).unwrap().iter().collect();
        let opposite = cloth
            .mesh
            .face(faces[0])
            .into_iter()
            .find(|&v| v != edge.0 && v != edge.1);
        let opposite = opposite.expect("a triangle has a third corner");
        m.remember(&cloth.mesh, &[edge], 0.0, Cause::Energy { gain: 1e-3 }, 0.1);
        assert!(m.waiting(&cloth, edge, 0.05, Direction::Refine));
        cloth.v[opposite.0 as usize] = Vec3::new(0.0, 0.0, 10.0);
        assert!(!m.waiting(&cloth, edge, 0.05, Direction::Refine));
    }

    /// A refusal shared by several edges (a bisect48 vertex's star, a remesh region) holds each
    /// of them, and pruning forgets an edge whose vertex is gone.
    #[test]
    fn a_refusal_of_several_edges_holds_each_and_dies_with_their_vertices() {
        // Vertex 7 of the 5x5 grid has valence 4: neighbours 2, 8, 12, 6 counter-clockwise.
        let mut cloth = crate::testing::flat_cloth(5, Vec3::zeros());
        let mut m = RefusalMemory::default();
        let star = [e(7, 2), e(7, 8), e(7, 12), e(7, 6)];
        m.remember(&cloth.mesh, &star, 0.0, Cause::Energy { gain: 1.0 }, 0.1);
        for &s in &star {
            assert!(m.waiting(&cloth, s, 0.05, Direction::Simplify), "{s:?}");
        }
        assert_eq!(m.refused_at.len(), 4);
        let faces: Vec<_> = cloth.mesh.faces().collect();
        let remove: Vec<_> = faces
            .into_iter()
            .filter(|&f| cloth.mesh.face(f).contains(&VertexId(7)))
            .collect();
        // The star becomes two faces: vertex 7 is gone.
        let old = |i| crate::mesh::VertexRef::Old(VertexId(i));
        let edit = crate::mesh::Edit {
            remove,
            new_vertices: Vec::new(),
            add: vec![[old(2), old(8), old(12)], [old(2), old(12), old(6)]],
        };
        cloth.mesh.replace(&edit).unwrap();
        m.prune(&cloth.mesh, 0.05);
        assert!(m.refused_at.is_empty(), "{:?}", m.refused_at.keys());
    }
}
