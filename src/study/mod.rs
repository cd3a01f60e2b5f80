//! Studies: many runs, measured and tabulated. Above `eval` (which measures one run against a
//! reference) and below `report` (which presents what a study wrote).
//!
//! - [`file`]: study files (`adaptcloth study FILE.toml`): scenes, reference, runs, sweeps.
//! - [`config`]: run configurations (`strategy@resolution` x integrators, and study runs).
//! - [`plan`]: a study made concrete per scene, checked before anything runs.
//! - [`compare`]: a comparison of one scene: the reference, then every configuration on the pool.
//! - [`table`]: the comparison table (`comparison.csv` with named columns, `comparison.json`).
//! - [`pool`]: the parallel pool with one progress bar per run.
//! - [`shard`], [`merge`]: a study spread over machines and combined again.
//! - [`stability`]: the largest stable step and the hard cases (`adaptcloth stability`).
//! - [`integrators`]: seed 004's single-particle integrator experiments and convergence orders.

pub mod compare;
pub mod config;
pub mod file;
pub mod integrators;
pub mod merge;
pub mod plan;
pub mod pool;
pub mod shard;
pub mod stability;
pub mod table;

pub use compare::{compare, CompareOptions};
pub use config::{default_spec, parse_runs, RunConfig};
pub use file::{has_study_key, load_study, looks_like_study, parse_study, RunTemplate, Study};
pub use merge::merge;
pub use plan::{plan, ScenePlan};
pub use shard::Shard;
pub use table::{read_comparison, Comparison, Row};

use crate::eval::reference::ReferenceError;
use std::path::Path;

/// Why a study could not be run, merged or read.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// A configuration, shard, option or comparison folder is invalid (bad input).
    #[error("{0}")]
    Config(String),
    /// The reference could not be made.
    #[error("reference: {0}")]
    Reference(#[from] ReferenceError),
    /// Reading or writing outputs failed.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: String,
        /// The error.
        source: std::io::Error,
    },
    /// Comparison folders cannot be merged (bad input).
    #[error("merge: {0}")]
    Merge(String),
    /// Stopped by Ctrl-C before its outputs were complete (what was written is said).
    #[error("{0}")]
    Interrupted(String),
    /// A scene of the study is invalid (bad input).
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
}

/// Maps an I/O error on `path` to [`StudyError::Io`].
pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> StudyError + '_ {
    move |source| StudyError::Io {
        path: path.display().to_string(),
        source,
    }
}
