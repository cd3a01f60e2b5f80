//! Physics: derived material parameters, forces (MODEL.md §2-§3), time step and integrators (§4).
//!
//! In the step: the integrator advances positions and velocities through [`ForceModel`], which
//! evaluates every switched-on force over flat spring and bending arrays rebuilt only when the mesh
//! changes. Per-vertex arrays are indexed by vertex slot; free slots and pinned vertices have
//! `inv_mass = 0` and never move.
//!
//! Files: `elements` (the flat [`Springs`] and [`Bends`] arrays), `forces` ([`ForceModel`]: vertex
//! parameters and force kernels), `integrator` (the [`Dynamics`] and [`Integrator`] traits, the
//! registry) with one file per integrator under `integrator/`.

mod elements;
mod forces;
mod integrator;
mod limits;

#[cfg(test)]
mod tests;

pub use elements::{Bends, Springs};
pub use forces::ForceModel;
pub use integrator::{
    make_integrator, Dynamics, Integrator, Rk4, SymplecticEuler, UnknownIntegrator, INTEGRATORS,
};
