//! Physics: derived material parameters, forces (MODEL.md §2-§3), time step and integrators (§4).
//!
//! In the step: the integrator advances positions and velocities through [`ForceModel`], which
//! evaluates every switched-on force over flat spring and bending arrays rebuilt only when the mesh
//! changes. Per-vertex arrays are indexed by vertex slot; free slots and pinned vertices have
//! `inv_mass = 0` and never move.
//!
//! Files: `params` (the physics' own parameters: [`Material`], [`Forces`], [`IntegratorParams`]),
//! `elements` (the flat [`Springs`] and [`Bends`] arrays), `forces` ([`ForceModel`]: vertex
//! parameters and force evaluation), `kernels` (the spring and bending sweeps, four elements at a
//! time on `lanes`), `chunks` (the elements split by vertex windows, so a sweep runs on every
//! thread with the same result), `integrator` (the [`Dynamics`] and [`Integrator`] traits, the
//! registry) with one file per integrator under `integrator/`. Seed 004's single-particle
//! experiments that compare the integrators live in `crate::study::integrators`.

/// Runs `$call` (a generic function with its type parameters named) compiled for AVX2 when the
/// CPU has it, else for the build's baseline.
macro_rules! dispatch {
    ($avx2:ident, $portable:ident :: <$($c:ident),*> ($($arg:expr),*)) => {{
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { $avx2::<$($c),*>($($arg),*) };
        }
        $portable::<$($c),*>($($arg),*)
    }};
}

mod chunks;
mod elements;
mod forces;
mod integrator;
mod kernels;
mod lanes;
mod limits;
mod params;
pub mod penalty;

#[cfg(test)]
mod tests;

pub use elements::{Bends, Springs};
pub use forces::{Energies, ForceModel};
pub use integrator::{
    integrator_named, make_integrator, Dynamics, Euler, EulerKind, Hold, ImplicitEuler, Integrator,
    Rk4, Step, StepStats, UnknownIntegrator, VelocityVerlet, Verlet, VerletKind, INTEGRATORS,
};
pub use limits::{StabilityLimit, ITERATIONS_AFTER_EDIT, STEPS_PER_ITERATION};
pub use params::{Forces, IntegratorParams, LinearSolver, Material, SpringMode, StiffnessModel};
pub use penalty::{Pressed, PressedFace};
