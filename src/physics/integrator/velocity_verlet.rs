//! `velocity_verlet` (seed 004, (4.5g-h); Swope et al. 1982):
//! `x' = x + dt v + dt²/2 a(x, v)`, `a' = a(x', v*)` with the predicted velocity
//! `v* = v + dt a`, then `v' = v + dt (a + a')/2`.
//!
//! The acceleration at the start of the step is evaluated afresh every step rather than carried
//! over from the previous step's `a'`: two force evaluations per step, but no per-vertex history,
//! so a mesh edit between steps can never leave a stale acceleration behind (see the module doc of
//! `integrator`). With velocity-independent forces the scheme is the classic second-order,
//! time-reversible velocity Verlet; with damping the predicted `v*` keeps it second order.

// Index loops over parallel per-slot arrays read clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use super::{fit, Dynamics, Integrator, Step, StepStats};
use crate::math::Vec3;

/// Velocity Verlet: second order, two force evaluations per step.
#[derive(Clone, Debug, Default)]
pub struct VelocityVerlet {
    a0: Vec<Vec3>,
    a1: Vec<Vec3>,
    vs: Vec<Vec3>,
}

impl Integrator for VelocityVerlet {
    fn name(&self) -> &'static str {
        "velocity_verlet"
    }

    fn advance(&mut self, dynamics: &dyn Dynamics, Step { t, dt, x, v }: Step) -> StepStats {
        let n = fit(x.len(), [&mut self.a0, &mut self.a1, &mut self.vs]);
        dynamics.accelerations(t, x, v, &mut self.a0);
        let h2 = 0.5 * dt * dt;
        for i in 0..n {
            x[i] += v[i] * dt + self.a0[i] * h2;
            self.vs[i] = v[i] + self.a0[i] * dt;
        }
        dynamics.accelerations(t + dt, x, &self.vs, &mut self.a1);
        let h = 0.5 * dt;
        for i in 0..n {
            v[i] += (self.a0[i] + self.a1[i]) * h;
        }
        StepStats::default()
    }
}
