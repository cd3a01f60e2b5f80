//! The Verlet family over `(x, v)`: `verlet` (position Verlet, seed 004 (4.3f)),
//! `time_corrected_verlet` (seed 004 (4.4d), Qian & Schlick 2002) and `verlet_relaxation`
//! (seed 002: a Verlet step, then Gauss-Seidel passes restoring the bars' rest lengths).
//!
//! History: only the previous step `dt_prev` is kept; the previous positions are
//! `x_prev = x - v dt_prev`, where `v` is the backward-difference velocity `(x - x_prev)/dt_prev`
//! left by the previous step (see the `integrator` module doc for why this makes adaptation,
//! collisions and pinned vertices update the history consistently). Then
//! - `verlet`: `x' = x + (x - x_prev) + a dt²` (assumes `dt = dt_prev`; wrong under variable steps,
//!   which is seed 004's point);
//! - `time_corrected_verlet` and `verlet_relaxation`: `x' = x + (x - x_prev) dt/dt_prev + a dt²`;
//! - `v' = (x' - x) / dt`.
//!
//! The first step has no history and starts from the Taylor expansion `x' = x + v dt + a dt²/2`,
//! which makes the family exact under constant acceleration from the first step on.
//!
//! Velocity-dependent forces (damping, drag) need the velocity at `t`, which position Verlet
//! does not have (`v` lags half a step). When the dynamics says its accelerations depend on `v`,
//! a second-order velocity `v* = v + a(x, v) dt_prev/2` is predicted first (one more force
//! evaluation), and the step uses `a(x, v*)`: without it the family would be only first order on
//! a damped system.
//!
//! `verlet_relaxation` uses the time-corrected update (so variable and cut steps stay consistent;
//! with a constant step it is the position Verlet of seed 002), then `passes` Gauss-Seidel sweeps
//! over the springs in edge order: each bar's two ends move along the bar, in proportion to their
//! inverse masses (pinned ends do not move), to restore its rest length. With tension-only springs
//! (`material.springs = "tension"`) only stretched bars are shortened, so the cloth can still
//! buckle. The displacement made by relaxation becomes velocity through `v' = (x' - x)/dt`.

// Index loops over parallel per-slot arrays read clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use super::{fit, Dynamics, Integrator, Step, StepStats};
use crate::math::{Real, Vec3};
use crate::physics::SpringMode;

/// Which member of the Verlet family.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VerletKind {
    /// `verlet`: `x' = 2x - x_prev + a dt²`.
    Position,
    /// `time_corrected_verlet`: `x' = x + (x - x_prev) dt/dt_prev + a dt²`.
    TimeCorrected,
    /// `verlet_relaxation`: time-corrected Verlet, then `passes` relaxation sweeps.
    Relaxation {
        /// Gauss-Seidel sweeps over the edges per step.
        passes: usize,
    },
}

/// A Verlet-family integrator: second order, one force evaluation per step (two with damping).
#[derive(Clone, Debug)]
pub struct Verlet {
    kind: VerletKind,
    dt_prev: Option<Real>,
    a: Vec<Vec3>,
    vs: Vec<Vec3>,
    x_old: Vec<Vec3>,
}

impl Verlet {
    /// A fresh integrator (no history: the first step starts from `(x, v)`).
    pub fn new(kind: VerletKind) -> Verlet {
        Verlet {
            kind,
            dt_prev: None,
            a: Vec::new(),
            vs: Vec::new(),
            x_old: Vec::new(),
        }
    }

    /// The previous step (s), `None` before the first step.
    pub fn dt_prev(&self) -> Option<Real> {
        self.dt_prev
    }
}

impl Integrator for Verlet {
    fn name(&self) -> &'static str {
        match self.kind {
            VerletKind::Position => "verlet",
            VerletKind::TimeCorrected => "time_corrected_verlet",
            VerletKind::Relaxation { .. } => "verlet_relaxation",
        }
    }

    fn advance(&mut self, dynamics: &dyn Dynamics, Step { t, dt, x, v }: Step) -> StepStats {
        let n = fit(x.len(), [&mut self.a, &mut self.vs, &mut self.x_old]);
        self.x_old.copy_from_slice(x);
        let dt2 = dt * dt;
        match self.dt_prev {
            None => {
                dynamics.accelerations(t, x, v, &mut self.a);
                for i in 0..n {
                    x[i] += v[i] * dt + self.a[i] * (0.5 * dt2);
                }
            }
            Some(hp) => {
                if dynamics.velocity_dependent() {
                    dynamics.accelerations(t, x, v, &mut self.a);
                    for i in 0..n {
                        self.vs[i] = v[i] + self.a[i] * (0.5 * hp);
                    }
                    dynamics.constrain_velocities(&mut self.vs);
                    dynamics.accelerations(t, x, &self.vs, &mut self.a);
                } else {
                    dynamics.accelerations(t, x, v, &mut self.a);
                }
                // (x - x_prev) = v hp; scaled by dt/hp when time-corrected.
                let lag = match self.kind {
                    VerletKind::Position => hp,
                    _ => dt,
                };
                for i in 0..n {
                    x[i] += v[i] * lag + self.a[i] * dt2;
                }
            }
        }
        if let VerletKind::Relaxation { passes } = self.kind {
            if let Some(model) = dynamics.force_model() {
                relax(model, passes, x);
            }
        }
        let inv_dt = 1.0 / dt;
        for i in 0..n {
            v[i] = (x[i] - self.x_old[i]) * inv_dt;
        }
        dynamics.constrain_velocities(v);
        self.dt_prev = Some(dt);
        StepStats::default()
    }
}

/// `passes` Gauss-Seidel sweeps restoring rest lengths (seed 002's bar relaxation), moving each
/// end in proportion to its inverse mass; with tension-only springs only stretched bars move.
fn relax(model: &super::ForceModel, passes: usize, x: &mut [Vec3]) {
    let sp = model.springs();
    let w = model.inv_mass();
    let both = model.material().springs == SpringMode::Both;
    for _ in 0..passes {
        for j in 0..sp.len() {
            let (a, b) = (sp.a[j] as usize, sp.b[j] as usize);
            let (wa, wb) = (w[a], w[b]);
            let wsum = wa + wb;
            if wsum <= 0.0 {
                continue;
            }
            let d = x[b] - x[a];
            let len = d.norm();
            let stretch = len - sp.rest_length[j];
            if len <= 0.0 || (!both && stretch <= 0.0) {
                continue;
            }
            let corr = d * (stretch / (len * wsum));
            x[a] += corr * wa;
            x[b] -= corr * wb;
        }
    }
}
