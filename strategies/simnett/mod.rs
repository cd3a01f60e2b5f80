//! The `simnett` strategy (MODEL.md §8.3): edge-based 1-to-4 subdivision after Simnett et al.
//! 2009, with triangle states 0-7 and temporary (state -1) children that keep the mesh conforming.
//!
//! - [`hierarchy`]: the edge/triangle hierarchy, the states, the faces each state prescribes and
//!   the consistency checker [`Hierarchy::check`].
//! - [`ops`]: the elementary operations [`Hierarchy::split_edge`], [`Hierarchy::merge_edge`] (and
//!   the `force_completion` variant [`Hierarchy::split_edge_forced`]), each ONE checked
//!   [`crate::mesh::Edit`] applied to a [`crate::adapt::EditTarget`] (the bare mesh, or the cloth
//!   through [`crate::adapt::ClothTarget`]).
//! - [`strategy`]: the [`crate::adapt::Adaptivity`] implementation driven by the shared criteria.
//!
//! Design notes and the state table: `docs/strategies/simnett.md`.

pub mod hierarchy;
pub mod ops;
pub mod strategy;

#[cfg(test)]
mod tests;

pub use hierarchy::{
    bits_of, canonical, state_of, EdgeNode, EdgeRole, Hierarchy, TriKey, TriNode, TEMPORARY_STATE,
};
pub use ops::{OpError, OpKind, OpRecord};
pub use strategy::{depth_angle_limit, Simnett};
