//! `implicit_euler`: linearised backward Euler (Baraff & Witkin 1998), the large-step integrator.
//!
//! One Newton step of backward Euler on `(x, v)`:
//! `(M - dt df/dv - dt² df/dx) dv = dt (f + dt df/dx v)`, then `v += dv`, `x += dt v`.
//!
//! - The system is kept in element form ([`system`]): `M + dt C + sum_j P_j^T B_j P_j` plus the
//!   bending terms, with one symmetric 3x3 block `B_j = dt D_j + dt² K_j` per spring (stored,
//!   rebuilt every step in place) and the per-vertex mass and drag.
//! - Spring Jacobians: elastic `K_j = k [u uᵀ + max(0, 1 - L0/L) (I - u uᵀ)]` for a spring that
//!   resists (stretched, or any spring with `springs = "both"`), zero for a tension-only spring in
//!   compression; the `max(0, ...)` drops the indefinite geometric term of a compressed spring, so
//!   every block is positive semi-definite and conjugate gradients apply. Damping
//!   `D_j = kd u uᵀ` (its position derivative is dropped, as in Baraff-Witkin). Drag: `-C I`.
//! - Bending: its full Hessian is indefinite, so the matrix gets its Gauss-Newton part only:
//!   with the Bridson modes `u = dtheta/dx` (12-vector) and `c = k_b |e|²/(|N1|+|N2|)`,
//!   `df/dx ~ -(c/2) u uᵀ` (from `sin(theta/2) ~ theta/2`) and `df/dv = -k_bd |e| u uᵀ`, both
//!   negative semi-definite. Leaving bending explicit was tried first and measured unstable: on
//!   the tiny-elements case (1 cm cells, 1/240 s) the energy rose by 5 J, and it fell
//!   monotonically once bending was removed (see `docs/integrators.md`).
//! - Fixed slots (pinned vertices, free slots) are filtered constraints: their rows and columns
//!   are those of the identity with a zero right-hand side (Baraff-Witkin's filter), so `dv = 0`
//!   there. A vertex resting on an obstacle ([`Integrator::holds`]) is filtered along its
//!   surface normal `n` only (`S = I - n nᵀ` on its block, [`System::hold`]), so `dv . n = 0`
//!   there; the impulse the obstacle gave is reported back for the friction that follows.
//! - Solver (`integrator.solver`, [`LinearSolver`]): `pcg_springs` (the default) is conjugate
//!   gradients preconditioned by the sparse Cholesky factor ([`cholesky`], single precision) of
//!   `P = A_f + sum w s sᵀ`, the sum over the bending couplings `(k, l)` no spring shares (each
//!   element's two wings), `s` the 3n-vector holding `u_k` at slot `k` and `-u_l` at slot `l`
//!   (zero at a fixed slot, as the filter wants): `P` has the springs' pattern, whose factor
//!   costs a third of the whole matrix's at 4,225 vertices, and `P - A_f` is positive
//!   semi-definite, so `P` is positive definite and CG converges in a few iterations (3 to 6 a
//!   step on average on the results' runs, 10 at most); a step whose CG ends above its
//!   tolerance is solved again by Cholesky, and one whose factorisation of `P` fails by
//!   Cholesky at once.
//!   `cg` ([`cg`]) is matrix-free preconditioned
//!   conjugate gradients with the block-Jacobi preconditioner, from `dv = 0`, stopping at
//!   `|r| <= tolerance |b|` or the iteration cap (the step is then taken with the last iterate and
//!   [`StepStats::unconverged`] set). `cholesky` ([`cholesky`]) assembles the sparse matrix
//!   ([`assembly`]) and factorises it, reusing the symbolic analysis while the topology is
//!   unchanged; a step whose factorisation fails is solved by CG instead
//!   ([`StepStats::solver_fallback`]). The matrix is symmetric positive definite (mass plus
//!   positive semi-definite terms), so the factorisation fails only on round-off or a
//!   non-finite state. `auto` solves by CG, and a step whose CG ends above its
//!   tolerance (at its cap, or broken down) again by Cholesky ([`StepStats::direct_rescue`]); the
//!   next [`AUTO_FIRST_WINDOW`] steps then go straight to Cholesky, a window that doubles with
//!   every rescue (up to [`AUTO_MAX_WINDOW`]), before CG is tried again. Every step is thus
//!   solved to tolerance unless the factorisation fails too. Where CG converges but slowly
//!   (more than [`AUTO_SLOW_ITERATIONS`] `sqrt(slots)` iterations on [`AUTO_SLOW_STEPS`]
//!   consecutive steps of one topology: a CG step costs its iterations times the slots, a
//!   factorisation of a cloth grows like `slots^1.5`, and measured here the two cost the same
//!   near 2 `sqrt(slots)` iterations) a window opens the same way ([`StepStats::slow_switch`]).
//!   The rule counts iterations, never time, so a run is reproducible.
//!
//! Without a [`crate::physics::ForceModel`] behind the dynamics (no Jacobians), the matrix is `M`
//! and the scheme reduces to symplectic Euler.

mod assembly;
mod cg;
mod cholesky;
#[cfg(test)]
mod diagnosis;
#[cfg(test)]
mod holds_tests;
mod supernodal_solve;
mod system;
#[cfg(test)]
mod tests;

use super::{fit, Dynamics, Hold, Integrator, Step, StepStats};
use crate::math::{Real, Vec3};
use crate::physics::{IntegratorParams, LinearSolver};
use assembly::Topology;
use cg::{Cg, Preconditioner};
use cholesky::{Cholesky, Factored};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use system::System;

/// Steps `auto` solves straight by Cholesky after its first rescue of a CG solve.
pub const AUTO_FIRST_WINDOW: u32 = 8;

/// Longest such window (steps): a run whose CG keeps failing retries it at least this often.
pub const AUTO_MAX_WINDOW: u32 = 1024;

/// A converged CG solve is slow for `auto` above this many iterations per `sqrt(slots)`
/// (dimensionless): about 1.75 times the break-even with a factorisation measured on the sphere
/// at 289 to 4,225 vertices (docs/performance.md, "Which solver is the default"), where the
/// static grids of docs/results.md stay below 2.6.
pub const AUTO_SLOW_ITERATIONS: Real = 3.5;

/// Consecutive slow CG solves of one topology after which `auto` opens a Cholesky window.
pub const AUTO_SLOW_STEPS: u32 = 24;

/// Linearised backward Euler, solved by conjugate gradients or sparse Cholesky.
#[derive(Debug)]
pub struct ImplicitEuler {
    solver: LinearSolver,
    /// `auto`: steps left to solve straight by Cholesky, and the window the next rescue opens.
    direct_steps_left: u32,
    next_window: u32,
    /// `auto`: consecutive slow converged CG solves, all on `slow_topology`.
    slow_streak: u32,
    slow_topology: Topology,
    /// Set when the run is interrupted: CG stops at its next check.
    interrupt: Option<Arc<AtomicBool>>,
    system: System,
    cg: Cg,
    cholesky: Cholesky,
    /// `pcg_springs`: the factorisation of the matrix without its bending couplings.
    springs_factor: Cholesky,
    f: Vec<Vec3>,
    dv: Vec<Vec3>,
    /// The contacts to hold in the next step ([`Integrator::holds`]), and scratch for their
    /// impulses.
    holds: Vec<Hold>,
    product: Vec<Vec3>,
}

impl ImplicitEuler {
    /// An integrator with these options: `solver`, and CG's `cg_tolerance` (relative residual)
    /// and `cg_max_iterations` (also used by a Cholesky step that falls back to CG).
    pub fn new(params: &IntegratorParams) -> ImplicitEuler {
        ImplicitEuler {
            solver: params.solver,
            direct_steps_left: 0,
            next_window: AUTO_FIRST_WINDOW,
            slow_streak: 0,
            slow_topology: Topology::default(),
            interrupt: None,
            system: System::default(),
            cg: Cg::new(params.cg_tolerance, params.cg_max_iterations),
            cholesky: Cholesky::new(Factored::Whole),
            springs_factor: Cholesky::new(Factored::SpringsSingle),
            f: Vec::new(),
            dv: Vec::new(),
            holds: Vec::new(),
            product: Vec::new(),
        }
    }
}

impl Integrator for ImplicitEuler {
    fn name(&self) -> &'static str {
        "implicit_euler"
    }

    fn stability_limit(&self) -> Option<Real> {
        None
    }

    fn set_interrupt(&mut self, flag: Arc<AtomicBool>) {
        self.interrupt = Some(flag);
    }

    fn holds(&mut self) -> Option<&mut Vec<Hold>> {
        Some(&mut self.holds)
    }

    fn advance(&mut self, dynamics: &dyn Dynamics, Step { t, dt, x, v }: Step) -> StepStats {
        let n = fit(x.len(), [&mut self.f, &mut self.dv]);
        let Some(model) = dynamics.force_model() else {
            for h in &mut self.holds {
                (h.held, h.impulse) = (false, 0.0);
            }
            dynamics.accelerations(t, x, v, &mut self.f);
            for i in 0..n {
                v[i] += self.f[i] * dt;
                x[i] += v[i] * dt;
            }
            return StepStats::default();
        };
        model.forces(x, v, &mut self.f);
        let pressed = dynamics.pressed_faces();
        for face in pressed {
            face.add_forces(x, &mut self.f);
        }
        let stats = self.solve_linearised(model, pressed, dt, x, v, None);
        let w = model.inv_mass();
        for i in 0..n {
            if w[i] != 0.0 {
                v[i] += self.dv[i];
            }
            x[i] += v[i] * dt;
        }
        stats
    }
}

/// Runs `solve` (a CG solve) with the pool's other thread kept awake when `shared` (its
/// iterations split work over two threads), else as it is.
fn awake_if<R>(shared: bool, solve: impl FnOnce() -> R) -> R {
    if shared {
        crate::parallel::with_partner_awake(solve)
    } else {
        solve()
    }
}

impl ImplicitEuler {
    /// Solves `(M - h df/dv - h² df/dx) dv = h (f + h df/dx w) + extra` for `dv` (m/s, left in
    /// [`ImplicitEuler::dv`]), the Jacobians taken at positions `x` (m), with `f` (N) the forces
    /// already in `self.f` (the penalties of `pressed` included) and `extra` (N s, per slot;
    /// ignored at fixed slots) added to the right-hand side, the stiffness of the faces
    /// `pressed` in the matrix (`System::press`), and the contacts of [`Integrator::holds`] held
    /// (`dv . n = 0` there; each one's impulse set). Backward Euler is `h = dt`, `w = v`, no `extra`; [`super::Bdf2`] uses
    /// it with its own `h`, `w` and `extra`.
    pub(super) fn solve_linearised(
        &mut self,
        model: &crate::physics::ForceModel,
        pressed: &[crate::physics::PressedFace],
        h: Real,
        x: &[Vec3],
        w: &[Vec3],
        extra: Option<&[Vec3]>,
    ) -> StepStats {
        self.system.build(model, h, x, w, &self.f);
        if let Some(extra) = extra {
            let inv = model.inv_mass();
            for (i, e) in extra.iter().enumerate() {
                if inv[i] != 0.0 {
                    self.system.b[i] += e;
                }
            }
        }
        self.system.press(pressed, h, x, w, model.inv_mass());
        self.system.hold(&mut self.holds, &self.f, model.inv_mass());
        let stats = self.solve(model);
        // A direct solve leaves round-off along a held normal; CG's iterates have none.
        self.system.project(&mut self.dv);
        let (system, dv) = (&self.system, &self.dv);
        system.impulses(model, dv, &mut self.product, &mut self.holds);
        stats
    }

    /// Solves the built system by the chosen solver (see the module's documentation).
    fn solve(&mut self, model: &crate::physics::ForceModel) -> StepStats {
        match self.solver {
            LinearSolver::Cg => self.solve_cg(model),
            LinearSolver::Cholesky => self.solve_direct(model),
            LinearSolver::PcgSprings => self.solve_pcg_springs(model),
            LinearSolver::Auto if self.direct_steps_left > 0 => {
                self.direct_steps_left -= 1;
                self.solve_direct(model)
            }
            LinearSolver::Auto => {
                let cg = self.solve_cg(model);
                if !cg.unconverged {
                    let slow_switch = self.slow_streak_ends(model, cg.cg_iterations);
                    if slow_switch {
                        self.open_direct_window();
                    }
                    return StepStats { slow_switch, ..cg };
                }
                self.slow_streak = 0;
                self.open_direct_window();
                self.rescue(model, cg)
            }
        }
    }

    /// `auto`: the next steps go straight to Cholesky, for a window twice as long as the last.
    fn open_direct_window(&mut self) {
        self.direct_steps_left = self.next_window;
        self.next_window = (2 * self.next_window).min(AUTO_MAX_WINDOW);
    }

    /// `auto`: counts a converged CG solve of `iterations` on `model` in the streak of slow ones
    /// (more than [`AUTO_SLOW_ITERATIONS`] `sqrt(slots)`, all on one topology; a new topology or
    /// a rescue starts a new streak); true when the streak has [`AUTO_SLOW_STEPS`] solves or more
    /// (it is kept through the window, so one more slow solve after it opens the next). The
    /// windows' length is shared with the rescues': each window, opened either way, doubles the
    /// next.
    fn slow_streak_ends(&mut self, model: &crate::physics::ForceModel, iterations: usize) -> bool {
        if !self.slow_topology.fits(model) {
            self.slow_topology = Topology::of(model);
            self.slow_streak = 0;
        }
        let slots = model.mass().len() as Real;
        if iterations as Real > AUTO_SLOW_ITERATIONS * slots.sqrt() {
            self.slow_streak += 1;
        } else {
            self.slow_streak = 0;
        }
        self.slow_streak >= AUTO_SLOW_STEPS
    }

    /// Solves the built system by block-Jacobi CG from `dv = 0`; on a chunked model, whose
    /// product an iteration is shared by two threads, the other kept awake.
    fn solve_cg(&mut self, model: &crate::physics::ForceModel) -> StepStats {
        let interrupt = self.interrupt.as_deref();
        let block_jacobi = Preconditioner::BlockJacobi;
        let (cg, system, dv) = (&mut self.cg, &self.system, &mut self.dv);
        awake_if(model.is_chunked(), || {
            cg.solve(system, model, interrupt, block_jacobi, dv)
        })
    }

    /// Solves the built system by CG preconditioned with the springs' factor; where that
    /// factorisation fails (a single-precision pivot), by the whole Cholesky in double precision
    /// (itself by block-Jacobi CG if it fails too), counted as a fallback; again by the whole
    /// Cholesky where the CG ends above its tolerance.
    fn solve_pcg_springs(&mut self, model: &crate::physics::ForceModel) -> StepStats {
        if self.springs_factor.factorize(&self.system, model).is_err() {
            return StepStats {
                solver_fallback: true,
                ..self.solve_direct(model)
            };
        }
        let interrupt = self.interrupt.as_deref();
        // Two triangular solves and a product an iteration, shared by two threads when the
        // factor is large or the model is chunked: keep the other awake.
        let shared = self.springs_factor.shares_solves() || model.is_chunked();
        let factor = Preconditioner::Factor(&mut self.springs_factor);
        let (cg, system, dv) = (&mut self.cg, &self.system, &mut self.dv);
        let pcg = awake_if(shared, || cg.solve(system, model, interrupt, factor, dv));
        if !pcg.unconverged {
            return pcg;
        }
        self.rescue(model, pcg)
    }

    /// Solves again by Cholesky a step whose CG (`cg`, its stats) ended above its tolerance: a
    /// rescue with CG's iterations, or, where the factorisation fails too, the fallback's own
    /// (unconverged) CG step.
    fn rescue(&mut self, model: &crate::physics::ForceModel, cg: StepStats) -> StepStats {
        let direct = self.solve_direct(model);
        if direct.solver_fallback {
            return direct;
        }
        StepStats {
            cg_iterations: cg.cg_iterations,
            direct_rescue: true,
            ..direct
        }
    }

    /// Solves the built system by sparse Cholesky, by CG where the factorisation fails.
    fn solve_direct(&mut self, model: &crate::physics::ForceModel) -> StepStats {
        match self.cholesky.solve(&self.system, model, &mut self.dv) {
            Ok(()) => StepStats::default(),
            Err(_) => StepStats {
                solver_fallback: true,
                ..self.solve_cg(model)
            },
        }
    }

    /// The forces buffer (N), sized to `n` slots: filled by the caller before
    /// [`ImplicitEuler::solve_linearised`].
    pub(super) fn forces_buffer(&mut self, n: usize) -> &mut Vec<Vec3> {
        fit(n, [&mut self.f, &mut self.dv]);
        &mut self.f
    }

    /// The last solve's `dv` (m/s).
    pub(super) fn dv(&self) -> &[Vec3] {
        &self.dv
    }
}
