//! The `simnett` strategy: the shared criteria (MODEL.md §7) drive splits and merges of the
//! hierarchy (MODEL.md §8.3), every edit applied through the shared state-transfer service
//! ([`crate::adapt::ClothTarget`]).
//!
//! Per call: the criteria evaluate every mesh edge, with this strategy's [`EdgeInfo`] (the age of
//! an edge since its parent was split, and the curvature limit `acos(cos_refine depth_factor^d)`
//! of an edge at depth `d`). Refinement, in the selection's key order: a hierarchy leaf is split
//! (blocked splits are skipped under the faithful rule, or forced with `force_completion`); an edge
//! between temporary children cannot split (with `force_completion` its triangle is completed).
//! An edge refined for collision has its new vertex projected onto the obstacle surface (plus
//! the collision margin). Simplification: a split edge is merged when both its children are
//! selected for simplification and the edge, and any state-7 triangle the merge would undo, are at
//! least `t_simplify` old; deepest first. A split or merge the energy law refused waits before it
//! is tried again (the shared back-off, [`RefusalMemory`]).

use super::hierarchy::{EdgeRole, Hierarchy};
use super::ops::{OpError, OpRecord};
use crate::adapt::AdaptParams;
use crate::adapt::RefineReason;
use crate::adapt::{
    select, AdaptContext, AdaptError, AdaptReport, Adaptivity, ClothTarget, Direction, EdgeInfo,
    RefusalMemory,
};
use crate::cloth::Cloth;
use crate::collision::Obstacles;
use crate::math::Real;
use crate::mesh::{EdgeKey, EditError, Mesh, VertexId};
use std::collections::BTreeSet;

/// The 1-to-4 edge-based strategy of Simnett et al. 2009. The hierarchy is built from the mesh at
/// the first call.
#[derive(Clone, Debug, Default)]
pub struct Simnett {
    hierarchy: Option<Hierarchy>,
    /// The depth limit (1-to-4 levels), fixed at the first adaptation from the initial mesh.
    depth_limit: u32,
    /// Edges whose split or merge the energy law refused, waiting before they are tried again.
    pub(super) refusals: RefusalMemory,
}

impl Simnett {
    /// The hierarchy (after the first adaptation).
    pub fn hierarchy(&self) -> Option<&Hierarchy> {
        self.hierarchy.as_ref()
    }
}

/// What the criteria need to know from the hierarchy.
struct Info<'a> {
    h: &'a Hierarchy,
    mesh: &'a Mesh,
    now: Real,
    spec: &'a AdaptParams,
}

impl EdgeInfo for Info<'_> {
    fn age(&self, e: EdgeKey) -> Option<Real> {
        match self.h.role(self.mesh, e)? {
            EdgeRole::Hierarchy(k) => self.h.edge(k)?.born.map(|b| self.now - b),
            EdgeRole::Temporary(t) => Some(self.now - self.h.triangle(t)?.changed),
        }
    }

    fn refine_angle_limit(&self, e: EdgeKey, _area_scaled: Real) -> Real {
        depth_angle_limit(self.spec, edge_depth(self.h, self.mesh, e))
    }
}

/// The depth of a mesh edge: its hierarchy depth, or one below its triangle for an edge between
/// temporary children.
fn edge_depth(h: &Hierarchy, mesh: &Mesh, e: EdgeKey) -> u32 {
    match h.role(mesh, e) {
        Some(EdgeRole::Hierarchy(k)) => h.edge(k).map_or(0, |n| n.depth),
        Some(EdgeRole::Temporary(t)) => h.triangle(t).map_or(0, |t| t.depth + 1),
        None => 0,
    }
}

/// The curvature refinement limit (rad) at depth `d`: the cosine limit times `depth_factor^d`
/// (MODEL.md §8.3, Table 5.5).
pub fn depth_angle_limit(spec: &AdaptParams, depth: u32) -> Real {
    (spec.cos_refine * spec.depth_factor.powi(depth as i32))
        .clamp(-1.0, 1.0)
        .acos()
}

impl Adaptivity for Simnett {
    fn name(&self) -> &'static str {
        "simnett"
    }

    fn adapt(&mut self, cloth: &mut Cloth, ctx: &AdaptContext) -> Result<AdaptReport, AdaptError> {
        let spec = ctx.params;
        if self.hierarchy.is_none() {
            self.depth_limit = spec.depth_limit(cloth.mesh.longest_rest_edge());
        }
        let depth_limit = self.depth_limit;
        let h = self
            .hierarchy
            .get_or_insert_with(|| Hierarchy::new(&cloth.mesh));
        let now = ctx.time;
        self.refusals.prune(&cloth.mesh, now);
        let sel = select(
            cloth,
            ctx.obstacles,
            spec,
            &Info {
                h,
                mesh: &cloth.mesh,
                now,
                spec,
            },
        );
        if sel.refine.is_empty() && sel.simplify.is_empty() {
            return Ok(AdaptReport::default());
        }
        let mut target = ctx.edit_target(cloth);
        for (e, reason) in sel.refine {
            if ctx.interrupted() {
                return Ok(target.report);
            }
            if self
                .refusals
                .waiting(target.cloth, e, now, Direction::Refine)
            {
                continue;
            }
            let x = &target.cloth.x;
            let length = (x[e.1 .0 as usize] - x[e.0 .0 as usize]).norm();
            let done: Result<Vec<OpRecord>, OpError> = if spec.force_completion {
                h.split_edge_forced(&mut target, e, depth_limit, now)
            } else {
                h.split_edge(&mut target, e, depth_limit, now)
                    .map(|r| vec![r])
            };
            match done {
                Ok(records) => {
                    if reason == RefineReason::Collision {
                        if let Some(r) = records.iter().find(|r| r.edge == e) {
                            project_onto_surface(&mut target, ctx.obstacles, r.mid, length);
                        }
                    }
                }
                Err(OpError::Edit(err)) if err != EditError::CrossesCloth => return Err(err.into()),
                Err(OpError::AddsEnergy(refusal)) => {
                    let mesh = &target.cloth.mesh;
                    self.refusals
                        .remember(mesh, &[e], now, refusal.into(), spec.t_simplify);
                }
                // Refused by the physics (crossing), or a precondition: blocked by the
                // faithful rule, at the maximum depth, already split by an earlier operation of
                // this call, or not a hierarchy edge.
                Err(_) => {}
            }
        }
        for p in merge_candidates(h, &sel.simplify, now, spec.t_simplify) {
            if ctx.interrupted() {
                break;
            }
            if self
                .refusals
                .waiting(target.cloth, p, now, Direction::Simplify)
            {
                continue;
            }
            match h.merge_edge(&mut target, p, now) {
                Ok(_) => {}
                Err(OpError::Edit(err)) if err != EditError::CrossesCloth => return Err(err.into()),
                Err(OpError::AddsEnergy(refusal)) => {
                    let mesh = &target.cloth.mesh;
                    self.refusals
                        .remember(mesh, &[p], now, refusal.into(), spec.t_simplify);
                }
                Err(_) => {}
            }
        }
        Ok(target.report)
    }
}

/// Split edges whose two children are both selected for simplification, old enough (the edge and
/// every state-7 triangle next to it changed at least `t_simplify` ago), deepest first, then in
/// key order.
fn merge_candidates(
    h: &Hierarchy,
    simplify: &[EdgeKey],
    now: Real,
    t_simplify: Real,
) -> Vec<EdgeKey> {
    let selected: BTreeSet<EdgeKey> = simplify.iter().copied().collect();
    let mut out: Vec<(std::cmp::Reverse<u32>, EdgeKey)> = Vec::new();
    for c in &selected {
        let Some(p) = h.edge(*c).and_then(|n| n.parent) else {
            continue;
        };
        let Some(node) = h.edge(p) else {
            continue;
        };
        let Some(children) = node.children(p) else {
            continue;
        };
        let old = now - node.split_at >= t_simplify
            && node.tris.iter().all(|t| {
                h.triangle(*t)
                    .is_none_or(|t| t.state != 7 || now - t.changed >= t_simplify)
            });
        if old && children.iter().all(|k| selected.contains(k)) {
            out.push((std::cmp::Reverse(node.depth), p));
        }
    }
    out.sort();
    out.dedup();
    out.into_iter().map(|(_, p)| p).collect()
}

/// Moves the new vertex of a collision split onto the obstacle surface, at the collision margin
/// along the outward normal, when the closest surface is within half the edge's world `length`
/// (m). Positions only: the velocity (and so the momentum) is the transferred one. Vertex contact
/// only: with face contact the split edge lies outside, at least the margin off the obstacle, and
/// snapping its midpoint to the closest surface (the far side of a bunny's ear under a large
/// face) would fold the new faces around the obstacle.
fn project_onto_surface(
    target: &mut ClothTarget,
    obstacles: &Obstacles,
    v: VertexId,
    length: Real,
) {
    if obstacles.face_contact() {
        return;
    }
    if let Some(sp) = obstacles.closest_surface(target.cloth.x[v.0 as usize]) {
        if sp.distance.abs() <= 0.5 * length {
            target.place(v, sp.point + sp.normal * obstacles.margin());
        }
    }
}
