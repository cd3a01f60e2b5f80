//! `explicit_euler`: `x += dt v; v += dt a(x, v)` (forward Euler: both updates use the state at
//! the start of the step).

use super::{fit, Dynamics, Integrator, StepStats};
use crate::math::{Real, Vec3};

/// Forward (explicit) Euler: first order, one force evaluation per step; unstable for an undamped
/// oscillator at any step (its amplification factor is `sqrt(1 + (omega dt)²) > 1`).
#[derive(Clone, Debug, Default)]
pub struct ExplicitEuler {
    a: Vec<Vec3>,
}

impl Integrator for ExplicitEuler {
    fn name(&self) -> &'static str {
        "explicit_euler"
    }

    fn step(
        &mut self,
        dynamics: &dyn Dynamics,
        t: Real,
        dt: Real,
        x: &mut [Vec3],
        v: &mut [Vec3],
    ) -> StepStats {
        debug_assert_eq!(x.len(), v.len());
        fit(&mut self.a, x.len());
        dynamics.constrain_velocities(v);
        dynamics.accelerations(t, x, v, &mut self.a);
        for ((xi, vi), ai) in x.iter_mut().zip(v.iter_mut()).zip(&self.a) {
            *xi += *vi * dt;
            *vi += ai * dt;
        }
        StepStats::default()
    }
}
