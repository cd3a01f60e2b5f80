//! `rk4`: classic fourth-order Runge-Kutta on `(x, v)` (the main seed's choice).
//!
//! Stage `s` evaluates `a_s = a(t + c_s dt, x_s, v_s)`; its slopes are `(v_s, a_s)`, so the stage
//! velocity doubles as the position slope and five buffers suffice: the stage state, the stage
//! acceleration and the two weighted slope sums.

use super::{fit, Dynamics, Integrator, Step, StepStats};
use crate::math::{Real, Vec3};

/// Classic RK4: fourth order, four force evaluations per step.
#[derive(Clone, Debug, Default)]
pub struct Rk4 {
    xs: Vec<Vec3>,
    vs: Vec<Vec3>,
    a: Vec<Vec3>,
    sum_x: Vec<Vec3>,
    sum_v: Vec<Vec3>,
}

impl Integrator for Rk4 {
    fn name(&self) -> &'static str {
        "rk4"
    }

    /// RK4's real-axis limit (2.785; its imaginary-axis one is 2.828).
    fn stability_limit(&self) -> Option<Real> {
        Some(2.785)
    }

    fn advance(&mut self, dynamics: &dyn Dynamics, Step { t, dt, x, v }: Step) -> StepStats {
        let n = fit(x.len(), [&mut self.xs, &mut self.vs, &mut self.a]);
        fit(n, [&mut self.sum_x, &mut self.sum_v]);
        // Stage 1 at (t, x, v): its slopes initialise the sums.
        dynamics.accelerations(t, x, v, &mut self.a);
        let h = 0.5 * dt;
        for i in 0..n {
            let (kx, kv) = (v[i], self.a[i]);
            self.sum_x[i] = kx;
            self.sum_v[i] = kv;
            self.xs[i] = x[i] + kx * h;
            self.vs[i] = v[i] + kv * h;
        }
        // Stages 2 and 3 (weight 2), each preparing the next stage's state.
        for next in [h, dt] {
            dynamics.accelerations(t + h, &self.xs, &self.vs, &mut self.a);
            for i in 0..n {
                let (kx, kv) = (self.vs[i], self.a[i]);
                self.sum_x[i] += kx * 2.0;
                self.sum_v[i] += kv * 2.0;
                self.xs[i] = x[i] + kx * next;
                self.vs[i] = v[i] + kv * next;
            }
        }
        // Stage 4 at t + dt, then the weighted update.
        dynamics.accelerations(t + dt, &self.xs, &self.vs, &mut self.a);
        let w = dt / 6.0;
        for i in 0..n {
            x[i] += (self.sum_x[i] + self.vs[i]) * w;
            v[i] += (self.sum_v[i] + self.a[i]) * w;
        }
        StepStats::default()
    }
}
