//! Physics: derived material parameters, forces (MODEL.md §2-§3), time step and integrators (§4).
//!
//! In the step: the integrator advances positions and velocities through [`ForceModel`], which
//! evaluates every switched-on force over flat spring and bending arrays rebuilt only when the mesh
//! changes. Per-vertex arrays are indexed by vertex slot; free slots and pinned vertices have
//! `inv_mass = 0` and never move.

mod elements;
mod forces;
mod integrator;

