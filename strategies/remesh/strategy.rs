//! The [`Adaptivity`] implementation of local remeshing (MODEL.md §8.2) and its per-edge
//! bookkeeping: the time each edge was made by a refinement, for the simplification hysteresis
//! (`t_simplify`) and the 10 % smoothing rule of the shared criteria, and the last refusal of a
//! region holding it, by the energy law or by the mesher when coarsening (the shared back-off,
//! [`RefusalMemory`]).

use super::{components, region_faces, remesh_region, Direction, RemeshError, RemeshParams};
use crate::adapt::criteria::{select, EdgeInfo};
use crate::adapt::{AdaptContext, AdaptError, AdaptReport, Adaptivity, ClothTarget};
use crate::adapt::{Cause, RefusalMemory};
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
type RegionKey = (Direction, Vec<[VertexKey; 3]>);

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
    /// The last refusal (by the energy law, or by the mesher when coarsening) of a region
    /// selected by each edge, shared by the region's edges (the cloth's motion and the regions
    /// around change that answer, so such edges wait, they are not refused for good).
    pub(super) refusals: RefusalMemory,
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

    /// Forgets entries whose vertices are gone, refinement times that reached `t_simplify` (both
    /// thresholds of the criteria are at most `t_simplify`, so such an edge counts as old either
    /// way), and refusals quiet for twice their wait ([`RefusalMemory::prune`]).
    pub(super) fn prune(&mut self, mesh: &Mesh, now: Real, t_simplify: Real) {
        let alive = |(a, b): &(VertexKey, VertexKey)| {
            mesh.resolve(*a).is_some() && mesh.resolve(*b).is_some()
        };
        self.refined_at
            .retain(|e, t| alive(e) && now - *t < t_simplify);
        self.refusals.prune(mesh, now);
        self.refused_plans
            .retain(|(_, faces), _| faces.iter().flatten().all(|&k| mesh.resolve(k).is_some()));
    }

    /// The key of the region `edges` select, `None` when an edge is gone.
    fn region_key(mesh: &Mesh, edges: &[EdgeKey], mode: Direction) -> Option<RegionKey> {
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

    /// Re-meshes each component of `edges` in `mode` through the shared edit target, but for
    /// the edges that wait (taken out before the components are formed); stops when
    /// interrupted. A refusal leaves the cloth as it was and is counted.
    fn apply_components(
        &mut self,
        target: &mut ClothTarget,
        ctx: &AdaptContext,
        edges: impl IntoIterator<Item = EdgeKey>,
        mode: Direction,
        fresh: &mut BTreeSet<FaceId>,
    ) {
        let edges: Vec<EdgeKey> = edges
            .into_iter()
            .filter(|&e| !self.refusals.waiting(target.cloth, e, ctx.time, mode))
            .collect();
        let params = RemeshParams::from_adapt(ctx.params);
        for group in components(&target.cloth.mesh, &edges) {
            if ctx.interrupted() {
                return;
            }
            self.apply(target, ctx, &group, mode, &params, fresh);
        }
    }

    /// Re-meshes one component through the shared edit target; a refusal leaves the cloth as it
    /// was and is counted, an energy refusal or the mesher's refusal to coarsen remembered.
    fn apply(
        &mut self,
        target: &mut ClothTarget,
        ctx: &AdaptContext,
        edges: &[EdgeKey],
        mode: Direction,
        params: &RemeshParams,
        fresh: &mut BTreeSet<FaceId>,
    ) {
        let now = ctx.time;
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
                    Direction::Refine => {
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
                    Direction::Simplify => self.counters.simplified += 1,
                }
            }
            Err(e) => {
                self.counters.refused += 1;
                let cause = match (&e, mode) {
                    (RemeshError::AddsEnergy(r), _) => {
                        self.counters.energy_refused += 1;
                        Some(Cause::from(*r))
                    }
                    (RemeshError::NoAcceptableMesh(_), Direction::Simplify) => {
                        Some(Cause::Coarsening)
                    }
                    _ => None,
                };
                if let Some(cause) = cause {
                    let t_simplify = ctx.params.t_simplify;
                    self.refusals
                        .remember(&target.cloth.mesh, edges, now, cause, t_simplify);
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
        let mut target = ctx.edit_target(cloth);
        let mut fresh = BTreeSet::new();
        let refine = selection.refine.iter().map(|(e, _)| *e);
        self.apply_components(&mut target, ctx, refine, Direction::Refine, &mut fresh);
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
            })
            .collect();
        if !ctx.interrupted() {
            self.apply_components(&mut target, ctx, simplify, Direction::Simplify, &mut fresh);
        }
        Ok(target.report)
    }
}
