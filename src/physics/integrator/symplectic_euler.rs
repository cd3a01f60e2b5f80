//! `symplectic_euler`: `v += dt a(x, v); x += dt v` (the Euler of seed 004).

use super::{fit, Dynamics, Integrator, StepStats};
use crate::math::{Real, Vec3};

/// Semi-implicit (symplectic) Euler: first order, one force evaluation per step.
#[derive(Clone, Debug, Default)]
pub struct SymplecticEuler {
    a: Vec<Vec3>,
}

impl Integrator for SymplecticEuler {
    fn name(&self) -> &'static str {
        "symplectic_euler"
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
            *vi += ai * dt;
            *xi += *vi * dt;
        }
        StepStats::default()
    }
}
