//! The local-remeshing strategy (`--strategy remesh`, MODEL.md §8.2): the adaptivity the source
//! thesis proposes. Edges selected by the shared criteria ([`crate::adapt::criteria`]) are grouped
//! into connected components; each component's region (the faces adjacent to its edges) is removed
//! and the hole re-meshed in rest space, finer or coarser, as one checked [`Edit`].
//!
//! Files, one concept each: `region` (components, regions, hole borders), `hole` (the spade
//! constrained-Delaunay mesher with lattice seeding and Laplacian smoothing), `plan` (the
//! elementary operation: density factor, cloth-border splits and merges, retries, the edit),
//! `strategy` (the [`Adaptivity`](crate::adapt::Adaptivity) implementation and the per-edge
//! refinement times for the hysteresis).
//!
//! The elementary operation is exposed for property tests: [`remesh_region`] applies it to an
//! [`EditTarget`], the bare mesh (topology alone) or the cloth through the same state-transfer
//! service every strategy uses ([`crate::adapt::ClothTarget`]), under the energy law of
//! [`crate::adapt::apply_edit_conserving`]: new vertices relaxed, and a re-meshing that would
//! raise the total energy refused unless the region's relative motion pays for it
//! (docs/model-notes.md, "Energy of a re-meshing"). It leaves the mesh (and the cloth) untouched on
//! error.

#[cfg(test)]
mod energy_tests;
mod hole;
mod plan;
mod region;
mod strategy;
#[cfg(test)]
mod tests;

pub use plan::{plan_region, Plan};
pub use region::{components, region_faces};
pub use strategy::Remesh;

pub use crate::adapt::Direction;

use crate::adapt::{AdaptParams, ConservingError, EditTarget, EnergyRefusal};
use crate::math::Real;
use crate::mesh::{EdgeKey, EditError, EditRecord, FaceId};

/// Parameters of the elementary re-meshing operation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RemeshParams {
    /// No refinement below this rest length (m); the edge floor is `floor_factor * l_min`
    /// (from `AdaptParams::refine_min_length`: `2 h_min` when `h_min` is set, so the floor is
    /// `h_min`).
    /// Default 0.08 (`l_min`).
    pub l_min: Real,
    /// Simplification never targets or merges cloth-border edges beyond this rest length (m).
    /// Default 0.25 (`l_max`).
    pub l_max: Real,
    /// Density-factor scale when refining (4.20-4.22). Default 1.01 (`density_refine`).
    pub density_refine: Real,
    /// Density-factor scale when simplifying. Default 0.35 (`density_simplify`).
    pub density_simplify: Real,
    /// Minimum angle the mesher keeps away from the hole border (degrees). Default 25
    /// (`remesh_min_angle`).
    pub angle_limit_deg: Real,
    /// New edges shorter than `floor_factor * l_min` (or than the shortest hole-border edge,
    /// whichever is smaller) make the attempt retry coarser. Default 0.5.
    pub floor_factor: Real,
    /// Spacing factor between attempts: divide to retry denser, multiply to retry coarser.
    /// Default 1.2.
    pub retry_factor: Real,
    /// Attempts before the region is refused. Default 8.
    pub max_attempts: usize,
    /// Refinement area limit as a multiple of the equilateral triangle of the target side.
    /// Default 1.5.
    pub area_slack: Real,
    /// Lattice seeds closer than this multiple of the spacing to the border are dropped.
    /// Default 0.5.
    pub seed_clearance: Real,
    /// Laplacian smoothing passes over new interior vertices. Default 3.
    pub smoothing_passes: usize,
    /// Budget of vertices spade's refinement may add per attempt. Default 2000.
    pub max_new_vertices: usize,
}

impl Default for RemeshParams {
    fn default() -> Self {
        RemeshParams {
            l_min: 0.08,
            l_max: 0.25,
            density_refine: 1.01,
            density_simplify: 0.35,
            angle_limit_deg: 25.0,
            floor_factor: 0.5,
            retry_factor: 1.2,
            max_attempts: 8,
            area_slack: 1.5,
            seed_clearance: 0.5,
            smoothing_passes: 3,
            max_new_vertices: 2000,
        }
    }
}

impl RemeshParams {
    /// The parameters set by the adaptivity parameters, defaults for the rest.
    pub fn from_adapt(params: &AdaptParams) -> Self {
        RemeshParams {
            l_min: params.refine_min_length(),
            l_max: params.l_max,
            density_refine: params.density_refine,
            density_simplify: params.density_simplify,
            angle_limit_deg: params.remesh_min_angle,
            ..RemeshParams::default()
        }
    }
}

/// What one re-meshing did, measured in rest space.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RemeshStats {
    /// Refine or simplify.
    pub mode: Direction,
    /// Faces removed (the region).
    pub removed_faces: usize,
    /// Faces created.
    pub added_faces: usize,
    /// Vertices created (cloth-border midpoints and interior points).
    pub new_vertices: usize,
    /// Cloth-border edges bisected.
    pub border_splits: usize,
    /// Edges of the hole border after splits and merges.
    pub border_edges: usize,
    /// New triangles with a rest angle below the mesher's limit.
    pub small_angle: usize,
    /// Of those, the ones with no vertex on the hole border (the border does not force them).
    pub small_angle_interior: usize,
    /// Mesher attempts (1 = first try accepted).
    pub attempts: usize,
    /// Target edge length from the density factor, after retries (m).
    pub target_length: Real,
    /// Mean rest length of the region's edges before (m).
    pub mean_length_before: Real,
    /// Mean rest length of the new faces' edges (m).
    pub mean_length_after: Real,
}

/// Why a region could not be re-meshed; the mesh is unchanged.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RemeshError {
    /// An edge of the selection does not exist.
    #[error("edge {0:?} does not exist")]
    NoSuchEdge(EdgeKey),
    /// A face of the region is not live.
    #[error("face {0:?} is not live")]
    StaleFace(FaceId),
    /// The region is empty.
    #[error("empty region")]
    EmptyRegion,
    /// The mesher failed on the hole.
    #[error("mesher failed: {0}")]
    Mesher(String),
    /// No attempt met the acceptance rules (the last reason given).
    #[error("no acceptable mesh of the hole: {0}")]
    NoAcceptableMesh(String),
    /// The mesh refused the edit.
    #[error("edit refused: {0}")]
    Edit(#[from] EditError),
    /// The re-meshing would add energy its region's relative motion cannot pay (the energy law,
    /// [`crate::adapt::apply_edit_conserving`]).
    #[error(transparent)]
    AddsEnergy(#[from] EnergyRefusal),
}

/// Re-meshes the region of `edges` in `mode` through an [`EditTarget`]: the bare mesh (property
/// tests of the topology) or the cloth through the state-transfer service
/// ([`crate::adapt::ClothTarget`]: new vertices interpolated barycentrically, pushed out of the
/// obstacles, masses recomputed, momentum and energy restored as its options say) under the
/// energy law: a re-meshing that would raise the cloth's total energy is applied only when the
/// region's relative motion pays the gain, and refused otherwise
/// ([`crate::adapt::apply_edit_conserving`]). The target is untouched on error. On a cloth, call
/// [`crate::cloth::Cloth::refresh`] before the next force evaluation.
pub fn remesh_region<T: EditTarget + ?Sized>(
    target: &mut T,
    edges: &[EdgeKey],
    mode: Direction,
    params: &RemeshParams,
) -> Result<(EditRecord, RemeshStats), RemeshError> {
    let faces = region_faces(target.mesh(), edges)?;
    let plan = plan_region(target.mesh(), &faces, mode, params)?;
    let record = target
        .apply_conserving(&plan.edit)
        .map_err(ConservingError::into_error::<RemeshError>)?;
    Ok((record, plan.stats))
}
