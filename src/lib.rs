//! # adaptcloth
//!
//! Cloth simulation on an adaptive triangle mesh: a mass-spring-damper cloth (edges are springs,
//! Bridson dihedral bending, gravity, air drag), time integrators, collision with static obstacles,
//! and one [`adapt::Adaptivity`] trait implemented by several mesh-adaptivity strategies so they can
//! be compared head to head on the same scenes, physics and metrics.
//!
//! Module map; data flows one way, from the command line down to the core (see
//! `docs/architecture.md`):
//!
//! ```text
//! cli -> report -> study -> eval -> sim -> scene -> core (cloth, adapt, strategies, physics,
//!                                                         collision, mesh) -> io, math
//! ```
//!
//! - [`math`]: scalar and vector aliases over nalgebra.
//! - [`parallel`]: whether work may be split over the thread pool.
//! - [`console`]: status lines on stdout and stderr that a closed pipe cannot turn into a panic
//!   (`say!`, `note!`), and the clipping of long values they echo.
//! - [`io`]: files: the one OBJ reader/writer, the metrics table, numeric CSV, atomic writes.
//! - [`mesh`]: topology and rest (pattern) geometry, the one checked edit, the conformity checker,
//!   generators, OBJ cloths, material-point location.
//! - [`physics`]: derived material parameters, forces, integrators.
//! - [`collision`]: static obstacles through parry3d (the only module that imports it).
//! - [`cloth`]: the simulated body: mesh + world state + physical parameters.
//! - [`adapt`]: the `Adaptivity` trait and the shared edit and state-transfer services.
//! - [`strategies`]: one module per adaptivity strategy.
//! - [`scene`]: TOML scenes, `--set` overrides and validation.
//! - [`sim`]: the step loop and the run driver (frames, metrics, summary).
//! - [`eval`]: measuring one run: error metrics against a cached reference.
//! - [`study`]: many runs: configurations, the parallel pool, shards, merge, the comparison
//!   table; the stability and integrator studies.
//! - [`report`]: presenting studies: markdown, plots, pictures, the HTML report, results.md.
//! - [`cli`]: the commands of the `adaptcloth` binary.
#![warn(missing_docs)]

pub mod adapt;
pub mod cli;
pub mod cloth;
pub mod collision;
pub mod console;
pub mod eval;
pub mod io;
pub mod math;
pub mod mesh;
pub mod parallel;
pub mod physics;
pub mod report;
pub mod scene;
pub mod sim;
#[path = "../strategies/mod.rs"]
pub mod strategies;
pub mod study;
#[cfg(test)]
mod testing;
