//! Evaluation: how accurate is a run, and how much did its accuracy cost? The measurement half of
//! the head-to-head comparison.
//!
//! Where it sits: above the run driver. A run records the world positions of a fixed grid of
//! material points at every output frame (the optional sampler of [`crate::sim::run`],
//! [`crate::sim::SamplePoints`]); this module compares those trajectories with a reference's.
//!
//! - [`metrics`]: `e(t)`, `e_rms`, `e_final`, tracked-point error, point-sampled Hausdorff
//!   distance, Pareto front, static-curve interpolation.
//! - [`reference`]: the reference (static strategy, fine grid, small step), its compact cache keyed
//!   by a stable hash of the physics parameters, and its error floor.
//! - [`compare`]: configurations, parallel runs, shards and merge, `comparison.csv`.
//! - [`plots`]: speed-error and time-series plots (plotters, embedded font).
//! - [`report`]: `report.md`, the computed reading, `docs/results.md`.
//! - [`render_hook`]: the calls into the rendering code (snapshots, `report.html`).
//!
//! Naming rule: one file per stage of the evaluation, named after what it produces.

pub mod compare;
pub mod metrics;
pub mod plots;
pub mod reference;
pub mod render_hook;
pub mod report;

pub use compare::{
    compare, default_configs, merge, parse_configs, CompareError, CompareOptions, Comparison,
    RunConfig, Shard,
};
pub use metrics::{hausdorff, pareto_front, static_time_at_error, ErrorReport};
pub use reference::{ensure_reference, Reference, ReferenceSettings};
pub use report::{write_docs, write_report};
