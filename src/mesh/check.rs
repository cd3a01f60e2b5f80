//! The conformity checker: every rule of MODEL.md §1, reporting which rule broke and where.
use super::Mesh;

/// A conformity rule of MODEL.md §1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// Each edge has one or two adjacent triangles.
    EdgeFaceCount,
}

/// A broken conformity rule and where it broke.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("rule {rule:?} broken: {at}")]
pub struct ConformityError {
    /// The rule.
    pub rule: Rule,
    /// Where (vertex, edge or face ids and values).
    pub at: String,
}

impl Mesh {
    /// Checks every conformity rule; the first broken one is returned.
    pub fn check(&self) -> Result<(), ConformityError> {
        Ok(()) // placeholder until the checker lands
    }
}
