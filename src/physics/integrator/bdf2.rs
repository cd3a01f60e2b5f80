//! `bdf2`: the second-order backward differentiation formula, linearised (Choi & Ko 2002), the
//! second-order large-step integrator.
//!
//! With the previous state `(x_prev, v_prev)` from a step of the same size `dt`:
//! `v' = (4v - v_prev)/3 + h M^-1 f(x', v')` and `x' = (4x - x_prev)/3 + h v'`, `h = 2dt/3`.
//! One Newton step from `(x, v)`, with `dv = v' - v`:
//! `(M - h df/dv - h² df/dx) dv = h (f + h df/dx w) + M (v̂ - v)`, where `x̂ = (4x - x_prev)/3`,
//! `v̂ = (4v - v_prev)/3` and `w = v + (x̂ - x)/h`: backward Euler's system
//! ([`ImplicitEuler::solve_linearised`], same Jacobians, same solvers) at step `h`, with `w` in
//! place of `v` and one more term on the right.
//!
//! Why BDF2 (issue 13): like backward Euler it is A-stable and damps the stiff high frequencies
//! of a large step (L-stable), which the trapezoidal rule and implicit midpoint do not; unlike it,
//! its damping of the resolved motion falls as `dt²`. Observed order 2 on the damped spring (whose
//! Jacobian is exact); on cloth the Jacobians drop terms (compressed springs' geometric
//! stiffness, bending's second-order part), and a single Newton step is then first order in those
//! terms.
//!
//! History: kept from the previous step's start, so it includes the collision response and
//! transfer that followed it. It is forgotten (the step falls back to one backward Euler step)
//! on the first step, when the step size changes (a cut last step, dynamic steps), when the
//! number of slots changes, and when the mesh changes ([`Integrator::forget_history`], called
//! after every adaptation event). Fixed slots keep their position.

use super::implicit_euler::ImplicitEuler;
use super::{fit, Dynamics, Hold, Integrator, Step, StepStats};
use crate::math::{Real, Vec3};
use crate::physics::IntegratorParams;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Relative difference of two step sizes below which they count as equal.
const SAME_STEP: Real = 1e-9;

/// Linearised BDF2 over backward Euler's linear system and solvers.
#[derive(Debug)]
pub struct Bdf2 {
    solver: ImplicitEuler,
    /// The previous step's size (s) when its start state is in `x_prev`, `v_prev`.
    dt_prev: Option<Real>,
    x_prev: Vec<Vec3>,
    v_prev: Vec<Vec3>,
    /// Scratch: `w` (m/s) and the extra right-hand side `M (v̂ - v)` (N s).
    w: Vec<Vec3>,
    extra: Vec<Vec3>,
}

impl Bdf2 {
    /// An integrator with these solver options (those of `implicit_euler`), without history.
    pub fn new(params: &IntegratorParams) -> Bdf2 {
        Bdf2 {
            solver: ImplicitEuler::new(params),
            dt_prev: None,
            x_prev: Vec::new(),
            v_prev: Vec::new(),
            w: Vec::new(),
            extra: Vec::new(),
        }
    }

    /// Whether the next step of size `dt` (s) over `n` slots has a usable history.
    fn has_history(&self, dt: Real, n: usize) -> bool {
        self.dt_prev
            .is_some_and(|p| (p - dt).abs() <= SAME_STEP * dt.abs() && self.x_prev.len() == n)
    }
}

impl Integrator for Bdf2 {
    fn name(&self) -> &'static str {
        "bdf2"
    }

    fn stability_limit(&self) -> Option<Real> {
        None
    }

    fn set_interrupt(&mut self, flag: Arc<AtomicBool>) {
        self.solver.set_interrupt(flag);
    }

    fn forget_history(&mut self) {
        self.dt_prev = None;
    }

    fn holds(&mut self) -> Option<&mut Vec<Hold>> {
        self.solver.holds()
    }

    fn advance(&mut self, dynamics: &dyn Dynamics, step: Step) -> StepStats {
        let Some(model) = dynamics.force_model() else {
            self.dt_prev = None;
            return self.solver.advance(dynamics, step);
        };
        let Step { t, dt, x, v } = step;
        let n = x.len();
        let history = self.has_history(dt, n);
        fit(
            n,
            [
                &mut self.x_prev,
                &mut self.v_prev,
                &mut self.w,
                &mut self.extra,
            ],
        );
        let stats = if history {
            let h = 2.0 * dt / 3.0;
            let mass = model.mass();
            let x_hat = |x_prev: &[Vec3], x: &[Vec3], i: usize| (x[i] * 4.0 - x_prev[i]) / 3.0;
            for i in 0..n {
                let v_hat = (v[i] * 4.0 - self.v_prev[i]) / 3.0;
                self.w[i] = v[i] + (x_hat(&self.x_prev, x, i) - x[i]) / h;
                self.extra[i] = (v_hat - v[i]) * mass[i];
            }
            let pressed = dynamics.pressed_faces();
            let f = self.solver.forces_buffer(n);
            model.forces(x, v, f);
            for face in pressed {
                face.add_forces(x, f);
            }
            let stats =
                self.solver
                    .solve_linearised(model, pressed, h, x, &self.w, Some(&self.extra));
            let (inv, dv) = (model.inv_mass(), self.solver.dv());
            for i in 0..n {
                let (start, next) = (x[i], x_hat(&self.x_prev, x, i));
                self.v_prev[i] = v[i];
                self.x_prev[i] = start;
                if inv[i] != 0.0 {
                    v[i] += dv[i];
                    x[i] = next + v[i] * h;
                }
            }
            stats
        } else {
            self.x_prev.copy_from_slice(x);
            self.v_prev.copy_from_slice(v);
            self.solver.advance(dynamics, Step { t, dt, x, v })
        };
        self.dt_prev = Some(dt);
        stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{union_jack, VertexId};
    use crate::physics::{Forces, LinearSolver, Material};
    use crate::study::integrators::damped_spring_error;
    use crate::testing::{built, random_state};

    /// A 6x6 sheet pinned at one corner, randomly deformed, under gravity.
    fn sheet() -> (crate::physics::ForceModel, Vec<Vec3>, Vec<Vec3>, Real) {
        let mut mesh = union_jack(6, 6, 1.0, 1.0);
        mesh.set_pinned(VertexId(0), true);
        let model = built(&mesh, &Material::default(), &Forces::default());
        let (x, v) = random_state(&mesh, 3, 0.02);
        let dt = 20.0 * model.stable_step(1.0);
        (model, x, v, dt)
    }

    #[test]
    fn without_history_a_step_is_a_backward_euler_step() {
        let (model, x0, v0, dt) = sheet();
        let params = IntegratorParams::default();
        let (mut xb, mut vb) = (x0.clone(), v0.clone());
        let (mut xe, mut ve) = (x0.clone(), v0.clone());
        let mut bdf2 = Bdf2::new(&params);
        let mut euler = ImplicitEuler::new(&params);
        // The first step, and the step after the history is forgotten.
        for k in 0..2 {
            bdf2.step(&model, 0.0, dt, &mut xb, &mut vb);
            euler.step(&model, 0.0, dt, &mut xe, &mut ve);
            assert_eq!((&xb, &vb), (&xe, &ve), "step {k}");
            if k == 0 {
                bdf2.forget_history();
            }
        }
        // With history it is another scheme; a different step size starts over.
        bdf2.step(&model, 0.0, dt, &mut xb, &mut vb);
        euler.step(&model, 0.0, dt, &mut xe, &mut ve);
        assert_ne!(xb, xe);
        let (mut xh, mut vh) = (xb.clone(), vb.clone());
        let (mut xc, mut vc) = (xb.clone(), vb.clone());
        bdf2.step(&model, 0.0, 0.5 * dt, &mut xh, &mut vh);
        ImplicitEuler::new(&params).step(&model, 0.0, 0.5 * dt, &mut xc, &mut vc);
        assert_eq!((xh, vh), (xc, vc));
    }

    #[test]
    fn pinned_vertices_stay_and_large_steps_stay_finite() {
        let (model, mut x, mut v, dt) = sheet();
        let pinned = x[0];
        let mut bdf2 = Bdf2::new(&IntegratorParams {
            solver: LinearSolver::Cg,
            ..IntegratorParams::default()
        });
        for k in 0..50 {
            let stats = bdf2.step(&model, k as Real * dt, dt, &mut x, &mut v);
            assert!(!stats.unconverged, "{stats:?}");
        }
        assert_eq!(x[0], pinned);
        assert!(x.iter().chain(&v).all(|p| p.iter().all(|c| c.is_finite())));
    }

    #[test]
    fn at_large_steps_it_damps_the_motion_less_than_backward_euler() {
        // The damped spring (period 0.63 s) with 20 to 80 steps per second: backward Euler's
        // error is mostly its numerical damping of the oscillation.
        for n in [20, 40, 80] {
            let (b, e) = (
                damped_spring_error("bdf2", n),
                damped_spring_error("implicit_euler", n),
            );
            assert!(
                b < 0.2 * e,
                "{n} steps: bdf2 {b:.3e} m, implicit Euler {e:.3e} m"
            );
        }
    }
}
