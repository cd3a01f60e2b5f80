//! The static strategy (MODEL.md §8.1): never changes the mesh. The baseline every adaptive
//! strategy is measured against, at coarse and fine resolutions.

use crate::adapt::{AdaptContext, AdaptError, AdaptReport, Adaptivity};
use crate::cloth::Cloth;

/// The mesh never changes.
#[derive(Clone, Copy, Debug, Default)]
pub struct StaticMesh;

impl Adaptivity for StaticMesh {
    fn name(&self) -> &'static str {
        "static"
    }

    fn adapt(
        &mut self,
        _cloth: &mut Cloth,
        _ctx: &AdaptContext,
    ) -> Result<AdaptReport, AdaptError> {
        Ok(AdaptReport::default())
    }
}
