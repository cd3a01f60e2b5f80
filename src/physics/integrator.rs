//! Time integrators behind one interface (MODEL.md §4).
//!
//! An integrator sees the physics only through [`Dynamics`] (accelerations of the whole state), so
//! every integrator runs over the same force code. One file per integrator (or family: `euler`,
//! `verlet`) under `integrator/`, named after the scene's `integrator.name`; adding one is adding
//! its file, its `mod` line and its line in [`REGISTRY`] (which also feeds [`INTEGRATORS`]).
//! Integrators implement [`Integrator::advance`]; the provided [`Integrator::step`] does what
//! every step starts with (fixed slots' velocities zeroed).
//!
//! **State and history.** The state is `(x, v)` and nothing else: integrators never keep
//! per-vertex history across steps. The multi-step schemes (`verlet`, `time_corrected_verlet`,
//! `verlet_relaxation`) keep only the previous step size `dt_prev` (a scalar) and derive the
//! previous positions as `x_prev = x - v dt_prev`, where `v` is the backward-difference velocity
//! `(x - x_prev) / dt_prev` they leave behind. Whatever acts on `(x, v)` between steps therefore
//! updates the history consistently: the collision response (a bounce changes `v`, hence the
//! history), pinned and driven vertices, and above all the adaptation transfer: a new vertex gets
//! `x` and `v` interpolated linearly from its origin, so its history is the same interpolation of
//! its parents' histories (exact for uniform motion, see the test
//! `verlet_history_of_a_split_vertex_comes_from_the_transfer`).

mod bdf2;
mod euler;
mod implicit_euler;
mod rk4;
mod velocity_verlet;
mod verlet;

pub use bdf2::Bdf2;
pub use euler::{Euler, EulerKind};
pub use implicit_euler::ImplicitEuler;
pub use rk4::Rk4;
pub use velocity_verlet::VelocityVerlet;
pub use verlet::{Verlet, VerletKind};

use super::ForceModel;
use super::IntegratorParams;
use super::PressedFace;
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

    /// Whether the accelerations depend on the velocities (damping, drag). Position Verlet then
    /// predicts a second-order velocity before evaluating them. Default: true (the safe answer).
    fn velocity_dependent(&self) -> bool {
        true
    }

    /// Optional capability: the mass-spring model behind the accelerations, for integrators that
    /// need more than accelerations (force Jacobians for `implicit_euler`, the edge list for
    /// `verlet_relaxation`). Default: none (those integrators then fall back as documented).
    fn force_model(&self) -> Option<&ForceModel> {
        None
    }

    /// The faces pressed by an obstacle in this step, whose penalty
    /// ([`crate::physics::penalty`]) the accelerations include; integrators that solve with
    /// [`Dynamics::force_model`] add it themselves. Default: none.
    fn pressed_faces(&self) -> &[PressedFace] {
        &[]
    }
}

/// What one integrator step reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepStats {
    /// Conjugate-gradient iterations of the step (`implicit_euler`; 0 for the others).
    pub cg_iterations: usize,
    /// True when the step's linear solve ended above its tolerance: conjugate gradients stopped
    /// at their iteration cap (or broke down) first. The step was taken with the last iterate.
    /// False for a solve cut short by an interrupt (the run stops after that step anyway).
    pub unconverged: bool,
    /// True when a factorisation failed on the step (the matrix was not numerically positive
    /// definite): `integrator.solver = "cholesky"` or `"auto"`, whose direct solve then falls
    /// back to conjugate gradients; `"pcg_springs"`, whose preconditioner's failure sends the
    /// step to the whole Cholesky (and to conjugate gradients if that fails too).
    pub solver_fallback: bool,
    /// True when conjugate gradients ended above their tolerance and sparse Cholesky solved the
    /// step again (`integrator.solver = "auto"` or `"pcg_springs"`); `cg_iterations` are CG's.
    pub direct_rescue: bool,
    /// True when conjugate gradients converged but slowly for the run of steps after which
    /// `integrator.solver = "auto"` solves the next steps by sparse Cholesky.
    pub slow_switch: bool,
}

/// A time integrator over `(x, v)`.
pub trait Integrator: Send {
    /// The integrator's name as written in a scene (`integrator.name`).
    fn name(&self) -> &'static str;

    /// Advances positions `x` (m) and velocities `v` (m/s) from time `t` by `dt` (s). Fixed slots
    /// keep their position and get zero velocity. Allocation-free in steady state: scratch
    /// buffers are kept and resized only when the number of slots changes.
    ///
    /// Provided: zeroes the velocities of the fixed slots ([`Dynamics::constrain_velocities`]),
    /// then calls [`Integrator::advance`]. Integrators implement `advance`, not this.
    fn step(
        &mut self,
        dynamics: &dyn Dynamics,
        t: Real,
        dt: Real,
        x: &mut [Vec3],
        v: &mut [Vec3],
    ) -> StepStats {
        debug_assert_eq!(x.len(), v.len());
        dynamics.constrain_velocities(v);
        self.advance(dynamics, Step { t, dt, x, v })
    }

    /// The integrator's own update of one step, called by [`Integrator::step`] once the fixed
    /// slots' velocities are zero; `x` and `v` have the same length.
    fn advance(&mut self, dynamics: &dyn Dynamics, step: Step<'_>) -> StepStats;

    /// The scheme's stability limit on the linear damped system: the largest `dt r` on a decay
    /// rate `r` and `dt w` on an oscillation of frequency `w` (the smaller of its real- and
    /// imaginary-axis limits), which caps dynamic steps ([`crate::physics::StabilityLimit`]).
    /// `None` for a scheme stable at any step (`implicit_euler`). Default: 2 (explicit Euler's
    /// real-axis limit, leapfrog's imaginary one).
    fn stability_limit(&self) -> Option<Real> {
        Some(2.0)
    }

    /// Lets a long step end early once `flag` is set (a run being interrupted: that step's
    /// result is then inexact, and the run stops after it). Default: ignored, for integrators
    /// whose step has no long inner loop; `implicit_euler` checks it between CG iterations.
    fn set_interrupt(&mut self, flag: std::sync::Arc<std::sync::atomic::AtomicBool>) {
        let _ = flag;
    }

    /// Drops any history of earlier steps kept outside `(x, v)`: the mesh changed (an adaptation
    /// event moved, added or removed slots). Default: nothing to drop (every scheme whose
    /// history lives in `(x, v)`, the Verlet family included); `bdf2` restarts from a backward
    /// Euler step.
    fn forget_history(&mut self) {}

    /// The contacts this integrator holds in its solve, for the caller to fill before each step
    /// (every vertex resting on an obstacle) and to read after it (each one's impulse). `None`
    /// (the default) for an integrator that leaves contact to the collision response after the
    /// step; `implicit_euler` and `bdf2` hold them ([`Hold`]).
    fn holds(&mut self) -> Option<&mut Vec<Hold>> {
        None
    }
}

/// A vertex resting on an obstacle, held on its surface through one implicit step: Baraff &
/// Witkin's filter `S = I - n nᵀ` on its slot, so the step leaves its velocity along `n`
/// unchanged (`dv . n = 0`) and solves the rest of the system with that constraint in it.
///
/// Released (not held; `impulse` 0) when the forces at the step's start pull it off the surface
/// (`f . n >= 0`), when its slot is fixed, or when an earlier hold in the list holds its slot
/// (an earlier hold that was released does not).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hold {
    /// The vertex's slot.
    pub slot: usize,
    /// The obstacle's outward unit normal at the vertex.
    pub normal: Vec3,
    /// Set by the step: whether it was held.
    pub held: bool,
    /// Set by the step: the normal impulse the obstacle gave the vertex over the step (N s),
    /// `n . (A dv - b)` of the unfiltered system; 0 when released. Negative when the solve's
    /// neighbours pulled a held vertex off (it was held for that one step all the same).
    pub impulse: Real,
}

/// One step to take: the state `(x, v)` at time `t` and the step size.
pub struct Step<'a> {
    /// Time at the start of the step (s).
    pub t: Real,
    /// Step size (s).
    pub dt: Real,
    /// Positions per slot (m), advanced in place.
    pub x: &'a mut [Vec3],
    /// Velocities per slot (m/s), advanced in place.
    pub v: &'a mut [Vec3],
}

/// One registered integrator: its scene name and its constructor from the options.
type Entry = (&'static str, fn(&IntegratorParams) -> Box<dyn Integrator>);

/// Every integrator, by scene name.
const REGISTRY: [Entry; 9] = [
    ("explicit_euler", |_| {
        Box::new(Euler::new(EulerKind::Explicit))
    }),
    ("symplectic_euler", |_| {
        Box::new(Euler::new(EulerKind::Symplectic))
    }),
    ("velocity_verlet", |_| Box::new(VelocityVerlet::default())),
    ("verlet", |_| Box::new(Verlet::new(VerletKind::Position))),
    ("time_corrected_verlet", |_| {
        Box::new(Verlet::new(VerletKind::TimeCorrected))
    }),
    ("verlet_relaxation", |s| {
        Box::new(Verlet::new(VerletKind::Relaxation {
            passes: s.relaxation_passes,
        }))
    }),
    ("rk4", |_| Box::new(Rk4::default())),
    ("implicit_euler", |s| Box::new(ImplicitEuler::new(s))),
    ("bdf2", |s| Box::new(Bdf2::new(s))),
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

/// A new integrator called `name` (one of [`INTEGRATORS`]) with these options.
pub fn make_integrator(
    name: &str,
    params: &IntegratorParams,
) -> Result<Box<dyn Integrator>, UnknownIntegrator> {
    REGISTRY
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, make)| make(params))
        .ok_or_else(|| UnknownIntegrator {
            name: name.to_owned(),
        })
}

/// A new integrator by name with default options (tests, experiments).
pub fn integrator_named(name: &str) -> Result<Box<dyn Integrator>, UnknownIntegrator> {
    make_integrator(name, &IntegratorParams::default())
}

/// Resizes scratch buffers to `n` slots and returns `n`; allocates only when `n` grows past a
/// capacity.
pub(crate) fn fit<const N: usize>(n: usize, bufs: [&mut Vec<Vec3>; N]) -> usize {
    for buf in bufs {
        if buf.len() != n {
            buf.resize(n, Vec3::zeros());
        }
    }
    n
}
