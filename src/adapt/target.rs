//! Where a strategy's elementary operations send their edits: the bare mesh (pure-topology
//! property tests) or the cloth through the state-transfer service (the physics path). One
//! interface, so every strategy's operations are written once and tested both ways.

use super::energy::{apply_edit_conserving, ConservingError};
use super::transfer::{apply_edit_with, Transfer, TransferOptions};
use super::AdaptReport;
use super::CrossingGuard;
use crate::cloth::Cloth;
use crate::math::Vec3;
use crate::mesh::{Edit, EditError, EditRecord, Mesh, VertexId};

/// Where the operations apply their edits.
pub trait EditTarget {
    /// The mesh being edited.
    fn mesh(&self) -> &Mesh;
    /// Applies one checked edit (the mesh is unchanged on error).
    fn apply(&mut self, edit: &Edit) -> Result<EditRecord, EditError>;

    /// Applies one checked edit under the energy law of [`apply_edit_conserving`] (unchanged on
    /// error). A bare mesh has no energy: it applies the edit as [`EditTarget::apply`] does.
    fn apply_conserving(&mut self, edit: &Edit) -> Result<EditRecord, ConservingError> {
        Ok(self.apply(edit)?)
    }
}

impl EditTarget for Mesh {
    fn mesh(&self) -> &Mesh {
        self
    }

    fn apply(&mut self, edit: &Edit) -> Result<EditRecord, EditError> {
        self.replace(edit)
    }
}

/// A cloth edited through the state-transfer service ([`apply_edit_with`]: interpolated state,
/// push-out, masses, momentum and optional energy restoration); every applied edit is added to
/// `report`. With `refuse_crossings`, the edits are checked through one [`CrossingGuard`] built
/// at the first edit: between edits a strategy may move the vertices its edits added, through
/// [`ClothTarget::place`], never the others.
pub struct ClothTarget<'a, 'o> {
    /// The cloth.
    pub cloth: &'a mut Cloth,
    /// How state is transferred (obstacles, momentum and energy restoration).
    pub options: TransferOptions<'o>,
    /// What the applied edits changed.
    pub report: AdaptReport,
    /// The crossing check's faces near an edit (with `refuse_crossings`, from the first edit).
    guard: Option<CrossingGuard>,
}

impl<'a, 'o> ClothTarget<'a, 'o> {
    /// A target over `cloth` with these transfer options and an empty report.
    pub fn new(cloth: &'a mut Cloth, options: TransferOptions<'o>) -> Self {
        ClothTarget {
            cloth,
            options,
            report: AdaptReport::default(),
            guard: None,
        }
    }

    /// The cloth and the options of its next edit: with `refuse_crossings`, through the guard.
    fn cloth_and_options(&mut self) -> (&mut Cloth, TransferOptions<'_>) {
        if self.options.refuse_crossings && self.guard.is_none() {
            self.guard = Some(CrossingGuard::new(self.cloth));
        }
        let options = TransferOptions {
            crossing_guard: self.guard.as_ref(),
            ..self.options
        };
        (self.cloth, options)
    }

    /// Adds an applied edit to the report and the guard.
    fn applied(&mut self, t: &Transfer) {
        self.report.add(t);
        if let Some(guard) = &mut self.guard {
            guard.applied(self.cloth, &t.record);
        }
    }

    /// Moves vertex `v`, which an edit through this target added, to `x` (m), keeping the
    /// crossing check informed (a strategy must not move the cloth's other vertices).
    pub fn place(&mut self, v: VertexId, x: Vec3) {
        self.cloth.x[v.0 as usize] = x;
        if let Some(guard) = &mut self.guard {
            guard.moved(self.cloth, v);
        }
    }
}

impl EditTarget for ClothTarget<'_, '_> {
    fn mesh(&self) -> &Mesh {
        &self.cloth.mesh
    }

    fn apply(&mut self, edit: &Edit) -> Result<EditRecord, EditError> {
        let (cloth, options) = self.cloth_and_options();
        let t = apply_edit_with(cloth, edit, &options)?;
        self.applied(&t);
        Ok(t.record)
    }

    fn apply_conserving(&mut self, edit: &Edit) -> Result<EditRecord, ConservingError> {
        let (cloth, options) = self.cloth_and_options();
        let t = apply_edit_conserving(cloth, edit, &options)?;
        self.applied(&t);
        Ok(t.record)
    }
}
