//! `--strategy bisect48`: newest-vertex bisection on the union-jack 4-8 mesh (MODEL.md §8.4;
//! Velho & Zorin 2001, Birra & Santos 2008), driven by the shared criteria of §7.
//!
//! Files, one concept each: `labels.rs` (newest vertex and level per face, split origin per
//! inserted vertex, the initial longest-edge labelling), `ops.rs` (block bisection, `bisect(t)`
//! with its forced cascade and `merge(v)` as checked edits, through an [`EditTarget`]: the bare
//! mesh or a cloth via the state-transfer service), `strategy.rs` (the [`Adaptivity`] impl: how
//! the criteria's selections map onto the operations). The rules as built are in
//! `docs/strategies/bisect48.md`.
//!
//! [`Adaptivity`]: crate::adapt::Adaptivity

mod labels;
mod ops;
mod strategy;

pub use labels::{opposite_longest_edge, FaceLabel, LabelMismatch, Labels, SplitOrigin};
pub use ops::{Bisection, OpError};
pub use strategy::Bisect48;

#[cfg(test)]
mod proptests;
#[cfg(test)]
mod strategy_tests;
#[cfg(test)]
mod tests;
