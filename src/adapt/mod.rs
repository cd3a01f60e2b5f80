//! Adaptivity: the [`Adaptivity`] trait every strategy implements (MODEL.md §6) and the shared
//! services strategies call to change the mesh while keeping the physics consistent.
//!
//! In the step: after integration and the collision pass, the simulation calls
//! [`Adaptivity::adapt`]; a strategy decides what to change (the criteria are shared:
//! [`criteria`]), and applies every elementary change through the one shared edit target
//! ([`AdaptContext::edit_target`], a [`ClothTarget`] over [`apply_edit_with`]), which checks
//! conformity, transfers state to new vertices, recomputes touched masses, restores the region's
//! linear momentum and records the kinetic-energy change. Spring and bending arrays and `dt` are
//! rebuilt by the simulation before the next step. The strategies apply their edits under the
//! energy law ([`EditTarget::apply_conserving`], module `energy`: new vertices relaxed, no edit
//! raises the total energy); plain [`EditTarget::apply`] serves edits that only restore what the
//! cloth had (bisect48's rollback of a refused cascade). A refused edit's edges wait before they
//! are tried again ([`RefusalMemory`], module `backoff`), in every strategy alike.

mod backoff;
pub mod criteria;
mod crossing_check;
mod energy;
#[cfg(test)]
mod energy_tests;
mod params;
mod relax;
pub mod sizing;
mod target;
mod transfer;

pub use backoff::{Cause, Direction, RefusalMemory, MAX_WAIT};
pub use criteria::{select, EdgeInfo, NoHistory, RefineReason, Selection};
pub use crossing_check::{edit_crosses, CrossingGuard};
pub use energy::{
    apply_edit_conserving, energy_trial, relative_kinetic_energy, ConservingError, EnergyRefusal,
    EnergyTrial,
};
pub use params::{AdaptParams, Criteria};
pub use relax::relax;
pub use target::{ClothTarget, EditTarget};
pub use transfer::{
    apply_edit, apply_edit_with, restore_kinetic_energy, Transfer, TransferOptions,
};

use crate::cloth::Cloth;
use crate::collision::Obstacles;
use crate::math::Real;
use crate::mesh::EditError;
use std::sync::atomic::{AtomicBool, Ordering};

/// What a strategy sees besides the cloth.
pub struct AdaptContext<'a> {
    /// The static obstacles (for the collision criterion and pushing new vertices out).
    pub obstacles: &'a Obstacles,
    /// Simulated time (s) at the end of the step just taken.
    pub time: Real,
    /// The adaptivity parameters.
    pub params: &'a AdaptParams,
    /// Set when the run is interrupted: strategies stop editing at their next edit (each edit
    /// leaves a conforming mesh), so a long pass answers Ctrl-C or SIGTERM at once.
    pub interrupt: Option<&'a AtomicBool>,
}

impl AdaptContext<'_> {
    /// Whether the run was interrupted: the pass should stop before its next edit.
    pub fn interrupted(&self) -> bool {
        self.interrupt.is_some_and(|f| f.load(Ordering::Relaxed))
    }

    /// The cloth edited through the shared state-transfer service with the scene's options:
    /// new vertices pushed out of the obstacles, momentum and kinetic energy restored as
    /// `restore_momentum` and `restore_energy` say. Every strategy applies its edits through it,
    /// so these options mean the same for all of them.
    pub fn edit_target<'c>(&self, cloth: &'c mut Cloth) -> ClothTarget<'c, '_> {
        ClothTarget::new(
            cloth,
            TransferOptions {
                obstacles: Some(self.obstacles),
                restore_momentum: self.params.restore_momentum,
                restore_energy: self.params.restore_energy,
                refuse_crossings: self.params.refuse_crossings,
                crossing_guard: None,
            },
        )
    }
}

/// What one call of [`Adaptivity::adapt`] changed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AdaptReport {
    /// Elementary operations applied (edits).
    pub events: usize,
    /// Vertices created.
    pub vertices_added: usize,
    /// Vertices removed.
    pub vertices_removed: usize,
    /// Kinetic energy after minus before, summed over the events (J).
    pub kinetic_energy_change: Real,
    /// Largest linear-momentum change of one event after restoration (kg m/s).
    pub momentum_change: Real,
}

impl AdaptReport {
    /// Adds the report of a later round of the same pass.
    pub fn merge(&mut self, other: &AdaptReport) {
        self.events += other.events;
        self.vertices_added += other.vertices_added;
        self.vertices_removed += other.vertices_removed;
        self.kinetic_energy_change += other.kinetic_energy_change;
        self.momentum_change = self.momentum_change.max(other.momentum_change);
    }

    /// Adds one applied edit to the report.
    pub fn add(&mut self, t: &Transfer) {
        self.events += 1;
        self.vertices_added += t.record.added_vertices.len();
        self.vertices_removed += t.record.removed_vertices.len();
        self.kinetic_energy_change += t.kinetic_energy_change;
        self.momentum_change = self.momentum_change.max(t.momentum_change);
    }
}

/// Why adaptation failed (the run stops with the message).
#[derive(Debug, thiserror::Error)]
pub enum AdaptError {
    /// A mesh edit was refused.
    #[error("mesh edit refused: {0}")]
    Edit(#[from] EditError),
    /// The strategy cannot go on (its own bookkeeping failed or the mesh does not suit it).
    #[error("{strategy}: {reason}")]
    Strategy {
        /// The strategy's name.
        strategy: &'static str,
        /// What went wrong.
        reason: String,
    },
}

/// A mesh-adaptivity strategy. Contract (MODEL.md §6): the mesh is conforming after every
/// elementary operation; new vertices get `x`, `v` by interpolation in rest space; masses and
/// elements of touched regions are recomputed and total mass is unchanged; linear momentum is
/// unchanged; every elementary operation is exposed for property tests.
pub trait Adaptivity: Send {
    /// The strategy's name as given to `--strategy`.
    fn name(&self) -> &'static str;

    /// Inspects the state after a step and changes the mesh through
    /// [`AdaptContext::edit_target`].
    fn adapt(&mut self, cloth: &mut Cloth, ctx: &AdaptContext) -> Result<AdaptReport, AdaptError>;
}
