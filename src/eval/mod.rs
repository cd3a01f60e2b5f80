//! Evaluation: how accurate is one run, and how much did its accuracy cost? Measuring only: the
//! studies that run many configurations are in `crate::study`, their presentation in
//! `crate::report`.
//!
//! Where it sits: above the run driver. A run records the world positions of a fixed grid of
//! material points at every output frame (the optional sampler of [`crate::sim::run`],
//! [`crate::sim::SamplePoints`]); this module compares those trajectories with a reference's.
//!
//! - [`metrics`]: `e(t)`, `e_rms`, `e_final`, tracked-point error, point-sampled Hausdorff
//!   distance, Pareto front, static-curve interpolation.
//! - `nearest`: the exact nearest-point and nearest-triangle search behind the surface distances.
//! - [`reference`]: the reference (static strategy, fine grid, small step), its compact cache keyed
//!   by a stable hash of the physics parameters, and its error floor.
//! - [`error_map`]: `e(u, v)` over the sample grid at a few times (where the error is).
//! - [`frame_diff`]: the distance between two frames of the same mesh (`adaptcloth frame-diff`).

pub mod error_map;
pub mod frame_diff;
pub mod metrics;
mod nearest;
pub mod reference;

pub use frame_diff::{frame_distance, FrameDiffError};
pub use metrics::{hausdorff, pareto_front, static_time_at_error, ErrorReport};
pub use reference::{ensure_reference, fnv1a, Reference, ReferenceSettings, FNV_OFFSET};
