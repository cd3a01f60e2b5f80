//! The [`Adaptivity`] implementation of local remeshing (MODEL.md §8.2) and its per-edge
//! bookkeeping: the time each edge was made by a refinement, for the simplification hysteresis
//! (`t_simplify`) and the 10 % smoothing rule of the shared criteria, and the time the energy law
//! last refused a region holding it (such edges wait `t_simplify` before being tried again).

use super::{components, region_faces, remesh_region, Mode, RemeshError, RemeshParams};
use crate::adapt::criteria::{select, EdgeInfo};
use crate::adapt::{AdaptContext, AdaptError, AdaptReport, Adaptivity, ClothTarget};
use crate::cloth::Cloth;
use crate::math::Real;
use crate::mesh::{EdgeKey, FaceId, Mesh, VertexKey};
use std::collections::{BTreeMap, BTreeSet};

/// Counters of a run of the strategy.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RemeshCounters {
    /// Regions re-meshed finer.
    pub refined: usize,
    /// Regions re-meshed coarser.
    pub simplified: usize,
    /// Regions the mesher or the mesh refused (left as they were).
    pub refused: usize,
    /// Of the refusals, the ones answered from memory (the same region refused before).
    pub remembered: usize,
    /// Of the refusals, the regions whose re-meshing would have added energy (the energy law).
    pub energy_refused: usize,
    /// Why the last region was refused.
    pub last_refusal: String,
    /// New triangles below the mesher's angle limit, all regions.
    pub small_angle: usize,
    /// Triangles created, all regions.
    pub added_faces: usize,
}

/// A region by its faces' vertex keys (each triple sorted, the list sorted) and the mode asked:
/// the planner works in rest space, where a vertex never moves, so the same key under the same
/// parameters always gets the same answer.
type RegionKey = (Mode, Vec<[VertexKey; 3]>);

/// Local remeshing: regions of selected edges are removed and re-meshed in rest space.
#[derive(Clone, Debug, Default)]
pub struct Remesh {
    /// Simulated time (s) at which each edge (by its vertices' keys) was created by a refinement.
    refined_at: BTreeMap<(VertexKey, VertexKey), Real>,
    /// Regions the planner refused, with the parameters they were refused under: asked again,
    /// they are refused again without re-meshing (a refined region next to the floor is selected
    /// again at every pass; re-planning it was most of the adaptation's time).
    refused_plans: BTreeMap<RegionKey, String>,
    /// The parameters `refused_plans` holds for.
    refused_under: Option<RemeshParams>,
    /// Simulated time (s) at which the energy law last refused a region selected by each edge
    /// (the cloth's motion changes that answer, so such edges only wait `t_simplify`).
    refused_at: BTreeMap<(VertexKey, VertexKey), Real>,
    /// What the strategy did so far.
    pub counters: RemeshCounters,
}

/// The criteria's view of the refinement times at one instant.
struct Ages<'a> {
    mesh: &'a Mesh,
    refined_at: &'a BTreeMap<(VertexKey, VertexKey), Real>,
    now: Real,
}

fn edge_keys(mesh: &Mesh, e: EdgeKey) -> (VertexKey, VertexKey) {
    (mesh.key(e.0), mesh.key(e.1))
}

impl EdgeInfo for Ages<'_> {
    fn age(&self, edge: EdgeKey) -> Option<Real> {
        self.refined_at
            .get(&edge_keys(self.mesh, edge))
            .map(|t| self.now - t)
    }
}

impl Remesh {
    /// A strategy with no history.
    pub fn new() -> Self {
        Remesh::default()
    }

    /// Seconds since `edge` was created by a refinement, at time `now` (s); `None` for edges no
    /// refinement made (or made longer ago than the hysteresis needs to remember).
    pub fn age(&self, mesh: &Mesh, edge: EdgeKey, now: Real) -> Option<Real> {
        Ages {
            mesh,
            refined_at: &self.refined_at,
            now,
        }
        .age(edge)
    }

    /// Forgets entries whose vertices are gone or whose age reached `t_simplify` (both thresholds
    /// of the criteria are at most `t_simplify`, so such an edge counts as old either way; a
    /// refused edge may be tried again).
    pub(super) fn prune(&mut self, mesh: &Mesh, now: Real, t_simplify: Real) {
        let live = |(a, b): &(VertexKey, VertexKey), t: &mut Real| {
            mesh.resolve(*a).is_some() && mesh.resolve(*b).is_some() && now - *t < t_simplify
        };
        self.refined_at.retain(live);
        self.refused_at.retain(live);
        self.refused_plans
            .retain(|(_, faces), _| faces.iter().flatten().all(|&k| mesh.resolve(k).is_some()));
    }

    /// True when the energy law refused a region of `edge` less than `t_simplify` ago (pruned).
    fn waiting(&self, mesh: &Mesh, edge: EdgeKey) -> bool {
        self.refused_at.contains_key(&edge_keys(mesh, edge))
    }

    /// The key of the region `edges` select, `None` when an edge is gone.
    fn region_key(mesh: &Mesh, edges: &[EdgeKey], mode: Mode) -> Option<RegionKey> {
        let faces = region_faces(mesh, edges).ok()?;
        let mut keys: Vec<[VertexKey; 3]> = faces
            .iter()
            .map(|&f| {
                let mut k = mesh.face(f).map(|v| mesh.key(v));
                k.sort();
                k
            })
            .collect();
        keys.sort();
        Some((mode, keys))
    }

    /// Re-meshes one component through the shared edit target; a refusal leaves the cloth as it
    /// was and is counted.
    fn apply(
        &mut self,
        target: &mut ClothTarget,
        now: Real,
        edges: &[EdgeKey],
        mode: Mode,
        params: &RemeshParams,
        fresh: &mut BTreeSet<FaceId>,
    ) {
        if self.refused_under.as_ref() != Some(params) {
            self.refused_plans.clear();
            self.refused_under = Some(*params);
        }
        let key = Self::region_key(&target.cloth.mesh, edges, mode);
        if let Some(why) = key.as_ref().and_then(|k| self.refused_plans.get(k)) {
            self.counters.refused += 1;
            self.counters.remembered += 1;
            self.counters.last_refusal = why.clone();
            return;
        }
        match remesh_region(target, edges, mode, params) {
            Ok((record, stats)) => {
                fresh.extend(record.added_faces.iter().copied());
                self.counters.small_angle += stats.small_angle;
                self.counters.added_faces += stats.added_faces;
                match mode {
                    Mode::Refine => {
                        self.counters.refined += 1;
                        let mesh = &target.cloth.mesh;
                        for &f in &record.added_faces {
                            let vs = mesh.face(f);
                            for k in 0..3 {
                                let e = EdgeKey::new(vs[k], vs[(k + 1) % 3]);
                                self.refined_at.insert(edge_keys(mesh, e), now);
                            }
                        }
                    }
                    Mode::Simplify => self.counters.simplified += 1,
                }
            }
            Err(e) => {
                self.counters.refused += 1;
                if matches!(e, RemeshError::AddsEnergy { .. }) {
                    self.counters.energy_refused += 1;
                    let mesh = &target.cloth.mesh;
                    for &e in edges {
                        self.refused_at.insert(edge_keys(mesh, e), now);
                    }
                }
                self.counters.last_refusal = e.to_string();
                if let (Some(k), RemeshError::NoAcceptableMesh(_)) = (key, &e) {
                    self.refused_plans.insert(k, e.to_string());
                }
            }
        }
    }
}

impl Adaptivity for Remesh {
    fn name(&self) -> &'static str {
        "remesh"
    }

    fn adapt(&mut self, cloth: &mut Cloth, ctx: &AdaptContext) -> Result<AdaptReport, AdaptError> {
        let spec = ctx.params;
        self.prune(&cloth.mesh, ctx.time, spec.t_simplify);
        let selection = select(
            cloth,
            ctx.obstacles,
            spec,
            &Ages {
                mesh: &cloth.mesh,
                refined_at: &self.refined_at,
                now: ctx.time,
            },
        );
        let params = RemeshParams::from_adapt(spec);
        let mut target = ctx.edit_target(cloth);
        let mut fresh = BTreeSet::new();
        let refine: Vec<EdgeKey> = selection
            .refine
            .iter()
            .map(|(e, _)| *e)
            .filter(|&e| !self.waiting(&target.cloth.mesh, e))
            .collect();
        for group in components(&target.cloth.mesh, &refine) {
            if ctx.interrupted() {
                return Ok(target.report);
            }
            let mode = Mode::Refine;
            self.apply(&mut target, ctx.time, &group, mode, &params, &mut fresh);
        }
        // Simplify only what this pass did not just re-mesh.
        let simplify: Vec<EdgeKey> = selection
            .simplify
            .iter()
            .copied()
            .filter(|e| {
                target
                    .cloth
                    .mesh
                    .edge(e.0, e.1)
                    .is_some_and(|ef| ef.iter().all(|f| !fresh.contains(&f)))
                    && !self.waiting(&target.cloth.mesh, *e)
            })
            .collect();
        for group in components(&target.cloth.mesh, &simplify) {
            if ctx.interrupted() {
                break;
            }
            let mode = Mode::Simplify;
            self.apply(&mut target, ctx.time, &group, mode, &params, &mut fresh);
        }
        Ok(target.report)
    }
}
