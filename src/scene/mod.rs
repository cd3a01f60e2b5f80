//! Scenes: TOML files (serde) describing the cloth, material, forces, time stepping, integrator,
//! collision, obstacles, adaptivity and tracked points; `--set section.key=value` overrides;
//! validation with clear errors.
mod spec;
pub use spec::*;
