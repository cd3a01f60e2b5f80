//! Studies: measurements the project reports in `docs/` and regenerates with one command each.
//! They sit above the simulation (they build scenes and step [`crate::sim::Simulation`]s) and
//! below the binary, so the integration tests call the same code with smaller settings.
//!
//! - [`stability`]: the integrator stability suite behind `adaptcloth stability` and
//!   `docs/stability.md` (largest stable steps by bisection, the hard cases).

pub mod stability;
