//! Where the operations' edits go: [`MeshTarget`] is the bare mesh ([`Mesh::replace`], for
//! topology tests) or the cloth ([`ClothTarget`], through [`apply_edit`] for the physics).

use crate::adapt::{apply_edit, AdaptReport, Transfer};
use crate::cloth::Cloth;
use crate::collision::Obstacles;
use crate::mesh::{Edit, EditError, EditRecord, Mesh};

/// Where an operation's edit goes: the bare mesh, or the cloth with state transfer.
pub trait MeshTarget {
    /// The mesh as it is now.
    fn mesh(&self) -> &Mesh;
    /// Applies the edit (checked; nothing changes on error).
    fn apply(&mut self, edit: &Edit) -> Result<EditRecord, EditError>;
}

impl MeshTarget for Mesh {
    fn mesh(&self) -> &Mesh {
        self
    }

    fn apply(&mut self, edit: &Edit) -> Result<EditRecord, EditError> {
        self.replace(edit)
    }
}

/// The cloth as a [`MeshTarget`]: every edit goes through [`apply_edit`] (midpoint `x`, `v`
/// averaged, push-out, masses, momentum restoration) and is added to `report`.
pub struct ClothTarget<'a> {
    /// The cloth.
    pub cloth: &'a mut Cloth,
    /// Obstacles new vertices are pushed out of.
    pub obstacles: Option<&'a Obstacles>,
    /// Restore the touched vertices' linear momentum (MODEL.md §6; needed by merges).
    pub restore_momentum: bool,
    /// The applied edits so far.
    pub report: AdaptReport,
    /// The last applied transfer.
    pub last: Option<Transfer>,
}

impl<'a> ClothTarget<'a> {
    /// A target over `cloth`.
    pub fn new(
        cloth: &'a mut Cloth,
        obstacles: Option<&'a Obstacles>,
        restore_momentum: bool,
    ) -> Self {
        ClothTarget {
            cloth,
            obstacles,
            restore_momentum,
            report: AdaptReport::default(),
            last: None,
        }
    }
}

impl MeshTarget for ClothTarget<'_> {
    fn mesh(&self) -> &Mesh {
        &self.cloth.mesh
    }

    fn apply(&mut self, edit: &Edit) -> Result<EditRecord, EditError> {
        let t = apply_edit(self.cloth, edit, self.obstacles, self.restore_momentum)?;
        self.report.add(&t);
        let record = t.record.clone();
        self.last = Some(t);
        Ok(record)
    }
}
