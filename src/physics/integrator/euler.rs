//! The first-order Euler family: `explicit_euler` (`x += dt v; v += dt a(x, v)`, forward Euler:
//! both updates use the state at the start of the step) and `symplectic_euler`
//! (`v += dt a(x, v); x += dt v`, the Euler of seed 004).

use super::{fit, Dynamics, Integrator, Step, StepStats};
use crate::math::Vec3;

/// Which member of the Euler family.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EulerKind {
    /// `explicit_euler`: forward Euler; unstable for an undamped oscillator at any step (its
    /// amplification factor is `sqrt(1 + (omega dt)²) > 1`).
    Explicit,
    /// `symplectic_euler`: semi-implicit Euler, the velocity updated first.
    Symplectic,
}

/// An Euler-family integrator: first order, one force evaluation per step.
#[derive(Clone, Debug)]
pub struct Euler {
    kind: EulerKind,
    a: Vec<Vec3>,
}

impl Euler {
    /// A new integrator of this kind.
    pub fn new(kind: EulerKind) -> Euler {
        Euler {
            kind,
            a: Vec::new(),
        }
    }
}

impl Integrator for Euler {
    fn name(&self) -> &'static str {
        match self.kind {
            EulerKind::Explicit => "explicit_euler",
            EulerKind::Symplectic => "symplectic_euler",
        }
    }

    fn advance(&mut self, dynamics: &dyn Dynamics, Step { t, dt, x, v }: Step) -> StepStats {
        fit(x.len(), [&mut self.a]);
        dynamics.accelerations(t, x, v, &mut self.a);
        let pairs = x.iter_mut().zip(v.iter_mut()).zip(&self.a);
        match self.kind {
            EulerKind::Explicit => {
                for ((xi, vi), ai) in pairs {
                    *xi += *vi * dt;
                    *vi += ai * dt;
                }
            }
            EulerKind::Symplectic => {
                for ((xi, vi), ai) in pairs {
                    *vi += ai * dt;
                    *xi += *vi * dt;
                }
            }
        }
        StepStats::default()
    }
}
