//! # adaptcloth
//!
//! Cloth simulation on an adaptive triangle mesh: a mass-spring-damper cloth (edges are springs,
//! Bridson dihedral bending, gravity, air drag), time integrators, collision with static obstacles,
//! and one `Adaptivity` trait implemented by several mesh-adaptivity strategies so they can
//! be compared head to head on the same scenes, physics and metrics.
#![warn(missing_docs)]

pub mod collision;
pub mod math;
pub mod mesh;
pub mod physics;
pub mod scene;
