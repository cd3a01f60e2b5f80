//! The `bisect48` strategy: the shared criteria of MODEL.md §7 mapped onto the operations of
//! `ops.rs`.
//!
//! Each call of [`Adaptivity::adapt`]:
//! 1. (first call only) labels the mesh by its longest edges (`labels.rs`); the maximum level is
//!    `2 max_depth` (two bisections make one 1-to-4 quadrisection).
//! 2. Evaluates the criteria once ([`crate::adapt::select`]), with edge ages from the vertex birth
//!    times: an edge's age is the time since its youngest end was inserted (the edges around an
//!    inserted vertex are exactly those its bisection created).
//! 3. **Refine**, edges in key order, skipping those already gone: an edge that is the refinement
//!    edge of an adjacent face is bisected (`bisect(t)` of that face, with its cascade); an edge
//!    that is a leg of both its faces gets both faces bisected, which makes it the refinement
//!    edge of the children, so it is split by a later call if it is still selected. A cascade
//!    that would pass the maximum level is skipped.
//! 4. **Simplify**: every vertex inserted by bisection, in slot order, is merged when it is
//!    mergeable (rule 5) and every edge around it is selected for simplification.
//!
//! A bisection the energy law refused makes its selected edge wait, a merge it refused the edges
//! around the vertex, before they are tried again (the shared back-off, [`RefusalMemory`]).
//!
//! Hysteresis: the criteria's refine and simplify thresholds differ (`cos_refine` vs
//! `cos_simplify`, compression refines and never simplifies), a vertex is merged only when all of
//! its edges are simplify-selected and at least `t_simplify` old, and refined edges are never
//! simplify-selected in the same call. The transfer is the shared one,
//! [`AdaptContext::edit_target`], with `restore_momentum` and `restore_energy` from the scene.

use super::labels::Labels;
use super::ops::OpError;
use crate::adapt::{
    select, AdaptContext, AdaptError, AdaptParams, AdaptReport, Adaptivity, Direction, EdgeInfo,
    RefusalMemory,
};
use crate::cloth::Cloth;
use crate::math::Real;
use crate::mesh::{EdgeKey, EditError, Mesh, VertexId};

/// Newest-vertex bisection on the 4-8 mesh (MODEL.md §8.4).
#[derive(Clone, Debug, Default)]
pub struct Bisect48 {
    labels: Option<Labels>,
    /// Simulated time (s) each vertex slot's vertex was inserted; `-inf` for initial vertices.
    born: Vec<Real>,
    /// Edges whose bisection, or vertices whose merge (by the edges around them), the energy law
    /// refused, waiting before they are tried again.
    pub(super) refusals: RefusalMemory,
}

/// Edge ages seen by the criteria: time since the youngest end of the edge was inserted.
struct Ages<'a> {
    born: &'a [Real],
    now: Real,
}

impl EdgeInfo for Ages<'_> {
    fn age(&self, edge: EdgeKey) -> Option<Real> {
        let born = |v: VertexId| {
            self.born
                .get(v.0 as usize)
                .copied()
                .unwrap_or(Real::NEG_INFINITY)
        };
        let youngest = born(edge.0).max(born(edge.1));
        youngest.is_finite().then_some(self.now - youngest)
    }
}

impl Bisect48 {
    /// A strategy that labels the mesh on its first call.
    pub fn new() -> Self {
        Self::default()
    }

    /// The labels, once the first call made them.
    pub fn labels(&self) -> Option<&Labels> {
        self.labels.as_ref()
    }

    fn error(reason: impl ToString) -> AdaptError {
        AdaptError::Strategy {
            strategy: "bisect48",
            reason: reason.to_string(),
        }
    }

    /// Labels the mesh on the first call; afterwards checks the labels still describe it.
    fn prepare(&mut self, mesh: &Mesh, spec: &AdaptParams) -> Result<(), AdaptError> {
        match &self.labels {
            None => {
                // Two bisections make one 1-to-4 level.
                let max_level = 2 * spec.depth_limit(mesh.longest_rest_edge());
                self.labels = Some(Labels::new(mesh, max_level));
                self.born = vec![Real::NEG_INFINITY; mesh.vertex_slots()];
                Ok(())
            }
            Some(l) => l.ensure_current(mesh).map_err(Self::error),
        }
    }
}

impl Adaptivity for Bisect48 {
    fn name(&self) -> &'static str {
        "bisect48"
    }

    fn adapt(&mut self, cloth: &mut Cloth, ctx: &AdaptContext) -> Result<AdaptReport, AdaptError> {
        let spec = ctx.params;
        self.prepare(&cloth.mesh, spec)?;
        let now = ctx.time;
        self.refusals.prune(&cloth.mesh, now);
        let selection = select(
            cloth,
            ctx.obstacles,
            spec,
            &Ages {
                born: &self.born,
                now,
            },
        );
        let Some(labels) = self.labels.as_mut() else {
            return Ok(AdaptReport::default());
        };
        let mut target = ctx.edit_target(cloth);

        // Refinement.
        for &(e, _) in &selection.refine {
            if ctx.interrupted() {
                return Ok(target.report);
            }
            if self
                .refusals
                .waiting(target.cloth, e, now, Direction::Refine)
            {
                continue;
            }
            let mesh = &target.cloth.mesh;
            let Some(faces) = mesh.edge(e.0, e.1) else {
                continue; // split earlier in this call
            };
            let faces: Vec<_> = faces.iter().collect();
            let owner = faces
                .iter()
                .copied()
                .find(|&f| labels.refinement_edge(mesh, f) == Some(e));
            let to_bisect = owner.map_or(faces, |f| vec![f]);
            for f in to_bisect {
                if !target.cloth.mesh.is_face(f) {
                    continue; // bisected by the cascade of the other face
                }
                match labels.bisect(&mut target, f) {
                    Ok(done) => {
                        for v in done.new_vertices() {
                            let i = v.0 as usize;
                            if self.born.len() <= i {
                                self.born.resize(i + 1, Real::NEG_INFINITY);
                            }
                            self.born[i] = now;
                        }
                    }
                    // Refused because the new faces would add energy the region's motion cannot
                    // pay: the edge waits.
                    Err(OpError::AddsEnergy(refusal)) => {
                        let mesh = &target.cloth.mesh;
                        self.refusals
                            .remember(mesh, &[e], now, refusal.into(), spec.t_simplify);
                        break;
                    }
                    // At the depth limit, or refused because the new faces would cross the cloth.
                    Err(OpError::MaxLevel { .. } | OpError::Edit(EditError::CrossesCloth)) => {}
                    Err(other) => return Err(Self::error(other)),
                }
            }
        }

        // Simplification.
        let simplify = &selection.simplify;
        let candidates: Vec<VertexId> = target
            .cloth
            .mesh
            .vertices()
            .filter(|&v| labels.split_origin(&target.cloth.mesh, v).is_some())
            .collect();
        for p in candidates {
            if ctx.interrupted() {
                break;
            }
            let mesh = &target.cloth.mesh;
            if !mesh.is_vertex(p) || !labels.is_mergeable(mesh, p) {
                continue;
            }
            let star: Vec<EdgeKey> = mesh
                .neighbours(p)
                .into_iter()
                .map(|w| EdgeKey::new(p, w))
                .collect();
            let all_selected = star.iter().all(|e| simplify.binary_search(e).is_ok());
            let waiting = || {
                star.iter().any(|&e| {
                    self.refusals
                        .waiting(target.cloth, e, now, Direction::Simplify)
                })
            };
            if !all_selected || waiting() {
                continue;
            }
            match labels.merge_conserving(&mut target, p) {
                // Refused: the merged faces would cross the cloth.
                Ok(_) | Err(OpError::Edit(EditError::CrossesCloth)) => {}
                // Refused: the merge would add energy the region's motion cannot pay; the edges
                // around the vertex wait.
                Err(OpError::AddsEnergy(refusal)) => {
                    let mesh = &target.cloth.mesh;
                    self.refusals
                        .remember(mesh, &star, now, refusal.into(), spec.t_simplify);
                }
                Err(other) => return Err(Self::error(other)),
            }
        }
        Ok(target.report)
    }
}
