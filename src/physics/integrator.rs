//! Time integrators behind one interface (MODEL.md §4).
//!
//! An integrator sees the physics only through [`Dynamics`] (accelerations of the whole state), so
//! every integrator runs over the same force code. One file per integrator under `integrator/`,
//! named after the scene's `integrator.name`; adding one is adding its file, its `mod` line and
//! its line in [`REGISTRY`] (which also feeds [`INTEGRATORS`]).

mod rk4;
mod symplectic_euler;

pub use rk4::Rk4;
pub use symplectic_euler::SymplecticEuler;

use crate::math::{Real, Vec3};

/// The physics an integrator advances: accelerations as a function of time and state.
pub trait Dynamics {
    /// Accelerations (m/s²) at time `t` (s) for positions `x` (m) and velocities `v` (m/s); `a` is
    /// overwritten; zero for fixed slots (pinned vertices and free slots).
    fn accelerations(&self, t: Real, x: &[Vec3], v: &[Vec3], a: &mut [Vec3]);

    /// Sets the velocity of every fixed slot to zero, so fixed slots never move even when handed a
    /// non-zero velocity. Integrators call it at the start of every step. Default: no fixed slot.
    fn constrain_velocities(&self, v: &mut [Vec3]) {
        let _ = v;
    }
}

/// A time integrator over `(x, v)`.
pub trait Integrator: Send {
    /// The integrator's name as written in a scene (`integrator.name`).
    fn name(&self) -> &'static str;

    /// Advances positions `x` (m) and velocities `v` (m/s) from time `t` by `dt` (s). Fixed slots
    /// keep their position and get zero velocity. Allocation-free in steady state: scratch
    /// buffers are kept and resized only when the number of slots changes.
    fn step(&mut self, dynamics: &dyn Dynamics, t: Real, dt: Real, x: &mut [Vec3], v: &mut [Vec3]);
}

/// One registered integrator: its scene name and its constructor.
type Entry = (&'static str, fn() -> Box<dyn Integrator>);

/// Every integrator, by scene name.
const REGISTRY: [Entry; 2] = [
    ("rk4", || Box::new(Rk4::default())),
    ("symplectic_euler", || Box::new(SymplecticEuler::default())),
];

/// Names of every available integrator, in registry order.
pub const INTEGRATORS: &[&str] = &{
    let mut names = [""; REGISTRY.len()];
    let mut i = 0;
    while i < REGISTRY.len() {
        names[i] = REGISTRY[i].0;
        i += 1;
    }
    names
};

/// A scene named an integrator that does not exist.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown integrator `{name}`; valid: {}", INTEGRATORS.join(", "))]
pub struct UnknownIntegrator {
    /// The name given.
    pub name: String,
}

/// A new integrator by scene name (one of [`INTEGRATORS`]).
pub fn make_integrator(name: &str) -> Result<Box<dyn Integrator>, UnknownIntegrator> {
    REGISTRY
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, make)| make())
        .ok_or_else(|| UnknownIntegrator {
            name: name.to_owned(),
        })
}

/// Resizes a scratch buffer to `n` slots; allocates only when `n` grows past the capacity.
pub(crate) fn fit(buf: &mut Vec<Vec3>, n: usize) {
    if buf.len() != n {
        buf.resize(n, Vec3::zeros());
    }
}
