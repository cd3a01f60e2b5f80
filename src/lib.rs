//! # adaptcloth
//!
//! Cloth simulation on an adaptive triangle mesh: a mass-spring-damper cloth (edges are springs,
//! Bridson dihedral bending, gravity, air drag), time integrators, collision with static obstacles,
//! and one [`adapt::Adaptivity`] trait implemented by several mesh-adaptivity strategies so they can
//! be compared head to head on the same scenes, physics and metrics.
//!
//! Module map (dependency order; see `docs/architecture.md`):
//! - [`math`]: scalar and vector aliases over nalgebra.
//! - [`mesh`]: topology and rest (pattern) geometry, the one checked edit, the conformity checker,
//!   generators, OBJ loading, material-point location.
//! - [`scene`]: TOML scenes, `--set` overrides and validation.
//! - [`physics`]: derived material parameters, forces, integrators.
//! - [`collision`]: static obstacles through parry3d (the only module that imports it).
//! - [`cloth`]: the simulated body: mesh + world state + physical parameters.
//! - [`adapt`]: the `Adaptivity` trait and the shared state-transfer services.
//! - [`strategies`]: one module per adaptivity strategy.
//! - [`sim`]: the step loop and the run driver.
//! - [`output`]: frames, metrics, summaries.
//! - [`render`]: pictures of runs: OBJ frames and obstacles through a small software rasteriser
//!   to PNG (snapshot grids, single pictures); outside the step loop.
//! - [`report_html`]: the self-contained `report.html`: markdown sections, embedded images and an
//!   interactive 3D replay per run.
//! - [`eval`]: error metrics against a cached reference, comparisons, plots and reports.
//! - [`study`]: measurement suites behind the report commands (stability).
#![warn(missing_docs)]

pub mod adapt;
pub mod cloth;
pub mod collision;
pub mod eval;
pub mod math;
pub mod mesh;
pub mod output;
pub mod physics;
pub mod render;
pub mod report_html;
pub mod scene;
pub mod sim;
#[path = "../strategies/mod.rs"]
pub mod strategies;
pub mod study;
#[cfg(test)]
mod testing;
