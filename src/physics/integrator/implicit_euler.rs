//! `implicit_euler`: linearised backward Euler (Baraff & Witkin 1998), the large-step integrator.
//!
//! One Newton step of backward Euler on `(x, v)`:
//! `(M - dt df/dv - dt² df/dx) dv = dt (f + dt df/dx v)`, then `v += dv`, `x += dt v`.
//!
//! - The system is never assembled: it is `M + dt C + sum_j P_j^T B_j P_j`, with one symmetric
//!   3x3 block `B_j = dt D_j + dt² K_j` per spring (stored, rebuilt every step in place) and the
//!   per-vertex mass and drag; the product sweeps the springs like the force kernel does.
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
//!   are zeroed (Baraff-Witkin's filter), so `dv = 0` there.
//! - Preconditioned conjugate gradients with the block-Jacobi preconditioner (the inverse of each
//!   vertex's 3x3 diagonal block), starting from `dv = 0`, stopping at
//!   `|r| <= tolerance |b|` or the iteration cap (the step is then taken with the last iterate and
//!   [`StepStats::cg_capped`] set).
//!
//! Without a [`crate::physics::ForceModel`] behind the dynamics (no Jacobians), the matrix is `M`
//! and the scheme reduces to symplectic Euler.

// Index loops over parallel per-slot arrays read clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use super::{fit, Dynamics, Integrator, Step, StepStats};
use crate::math::{Mat3, Real, Vec3};
use crate::physics::forces::bend_modes;
use crate::physics::ForceModel;
use crate::physics::SpringMode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// CG iterations between two looks at the interrupt flag.
const INTERRUPT_CHECK: usize = 16;

/// Linearised backward Euler solved by block-Jacobi preconditioned conjugate gradients.
#[derive(Clone, Debug)]
pub struct ImplicitEuler {
    tolerance: Real,
    max_iterations: usize,
    /// Set when the run is interrupted: CG stops at its next check.
    interrupt: Option<Arc<AtomicBool>>,
    f: Vec<Vec3>,
    stiff: Vec<Mat3>,
    block: Vec<Mat3>,
    precond: Vec<Mat3>,
    bend_u: Vec<[Vec3; 4]>,
    bend_w: Vec<Real>,
    bend_ids: Vec<[u32; 4]>,
    diag: Vec<Real>,
    b: Vec<Vec3>,
    dv: Vec<Vec3>,
    r: Vec<Vec3>,
    z: Vec<Vec3>,
    p: Vec<Vec3>,
    q: Vec<Vec3>,
}

impl ImplicitEuler {
    /// A solver stopping at relative residual `tolerance` or after `max_iterations`.
    pub fn new(tolerance: Real, max_iterations: usize) -> ImplicitEuler {
        ImplicitEuler {
            tolerance,
            max_iterations,
            interrupt: None,
            f: Vec::new(),
            stiff: Vec::new(),
            block: Vec::new(),
            precond: Vec::new(),
            bend_u: Vec::new(),
            bend_w: Vec::new(),
            bend_ids: Vec::new(),
            diag: Vec::new(),
            b: Vec::new(),
            dv: Vec::new(),
            r: Vec::new(),
            z: Vec::new(),
            p: Vec::new(),
            q: Vec::new(),
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

    fn advance(&mut self, dynamics: &dyn Dynamics, Step { t, dt, x, v }: Step) -> StepStats {
        let n = fit(x.len(), [&mut self.f, &mut self.b, &mut self.dv]);
        fit(n, [&mut self.r, &mut self.z, &mut self.p, &mut self.q]);
        let Some(model) = dynamics.force_model() else {
            dynamics.accelerations(t, x, v, &mut self.f);
            for i in 0..n {
                v[i] += self.f[i] * dt;
                x[i] += v[i] * dt;
            }
            return StepStats::default();
        };
        model.forces(x, v, &mut self.f);
        self.build(model, dt, x, v);
        let stats = self.solve(model);
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

impl ImplicitEuler {
    /// Per-spring blocks, the right-hand side `dt (f + dt K v)` and the preconditioner.
    fn build(&mut self, model: &ForceModel, dt: Real, x: &[Vec3], v: &[Vec3]) {
        let n = x.len();
        let sp = model.springs();
        let ns = sp.len();
        let sw = model.switches();
        let both = model.material().springs == SpringMode::Both;
        self.stiff.resize(ns, Mat3::zeros());
        self.block.resize(ns, Mat3::zeros());
        self.precond.resize(n, Mat3::zeros());
        self.diag.resize(n, 0.0);
        let (mass, drag) = (model.mass(), model.drag());
        for i in 0..n {
            self.diag[i] = mass[i] + if sw.drag { dt * drag[i] } else { 0.0 };
            self.precond[i] = Mat3::identity() * self.diag[i];
            self.b[i] = self.f[i];
        }
        let dt2 = dt * dt;
        for j in 0..ns {
            let (a, b) = (sp.a[j] as usize, sp.b[j] as usize);
            let d = x[b] - x[a];
            let len2 = d.norm_squared();
            let (mut kj, mut dj) = (Mat3::zeros(), Mat3::zeros());
            if len2 > 0.0 {
                let len = len2.sqrt();
                let u = d / len;
                let uu = u * u.transpose();
                if sw.springs && (both || len > sp.rest_length[j]) {
                    let geo = (1.0 - sp.rest_length[j] / len).max(0.0);
                    kj = (uu + (Mat3::identity() - uu) * geo) * sp.k[j];
                }
                if sw.spring_damping {
                    dj = uu * sp.kd[j];
                }
            }
            self.stiff[j] = kj;
            let bj = dj * dt + kj * dt2;
            self.block[j] = bj;
            self.precond[a] += bj;
            self.precond[b] += bj;
            // f + dt K v: (K v)_a = K_j (v_b - v_a), (K v)_b = -K_j (v_b - v_a).
            let kv = kj * (v[b] - v[a]) * dt;
            self.b[a] += kv;
            self.b[b] -= kv;
        }
        // Bending, Gauss-Newton: B = w u uᵀ with w = dt² (c/2) + dt k_bd |e|.
        self.bend_u.clear();
        self.bend_w.clear();
        self.bend_ids.clear();
        if sw.bending || sw.bending_damping {
            let kb = if sw.bending {
                model.material().k_b
            } else {
                0.0
            };
            let kbd = if sw.bending_damping {
                model.material().k_bd
            } else {
                0.0
            };
            for &[i1, i2, i3, i4] in &model.bends().v {
                let ids = [i1 as usize, i2 as usize, i3 as usize, i4 as usize];
                let Some(m) = bend_modes(x[ids[0]], x[ids[1]], x[ids[2]], x[ids[3]]) else {
                    continue;
                };
                let stiff = 0.5 * kb * m.elastic_scale;
                let wgt = dt2 * stiff + dt * kbd * m.damping_scale;
                let uv: Real = (0..4).map(|k| m.u[k].dot(&v[ids[k]])).sum();
                for k in 0..4 {
                    self.precond[ids[k]] += m.u[k] * m.u[k].transpose() * wgt;
                    // dt K v with K = -stiff u uᵀ.
                    self.b[ids[k]] -= m.u[k] * (dt * stiff * uv);
                }
                self.bend_u.push(m.u);
                self.bend_w.push(wgt);
                self.bend_ids.push([i1, i2, i3, i4]);
            }
        }
        let w = model.inv_mass();
        for i in 0..n {
            self.b[i] *= dt;
            if w[i] == 0.0 {
                self.b[i] = Vec3::zeros();
                self.precond[i] = Mat3::identity();
            } else {
                self.precond[i] = self.precond[i].try_inverse().unwrap_or_else(|| {
                    Mat3::identity() * (1.0 / self.diag[i].max(Real::MIN_POSITIVE))
                });
            }
        }
    }

    /// `q = S A S p`: the filtered system matrix times `p`.
    fn apply(&mut self, model: &ForceModel) {
        let sp = model.springs();
        let w = model.inv_mass();
        for i in 0..self.p.len() {
            self.q[i] = self.p[i] * self.diag[i];
        }
        for j in 0..sp.len() {
            let (a, b) = (sp.a[j] as usize, sp.b[j] as usize);
            let t = self.block[j] * (self.p[a] - self.p[b]);
            self.q[a] += t;
            self.q[b] -= t;
        }
        for ((ids, u), &wgt) in self.bend_ids.iter().zip(&self.bend_u).zip(&self.bend_w) {
            let s: Real = (0..4).map(|k| u[k].dot(&self.p[ids[k] as usize])).sum();
            for k in 0..4 {
                self.q[ids[k] as usize] += u[k] * (s * wgt);
            }
        }
        for (qi, &wi) in self.q.iter_mut().zip(w) {
            if wi == 0.0 {
                *qi = Vec3::zeros();
            }
        }
    }

    /// Preconditioned conjugate gradients on the filtered system, from `dv = 0`.
    fn solve(&mut self, model: &ForceModel) -> StepStats {
        let n = self.b.len();
        let dot = |a: &[Vec3], b: &[Vec3]| -> Real { a.iter().zip(b).map(|(x, y)| x.dot(y)).sum() };
        self.dv.fill(Vec3::zeros());
        self.r.copy_from_slice(&self.b);
        let b_norm = dot(&self.b, &self.b).sqrt();
        if b_norm == 0.0 || !b_norm.is_finite() {
            return StepStats::default();
        }
        let stop = self.tolerance * b_norm;
        for i in 0..n {
            self.z[i] = self.precond[i] * self.r[i];
        }
        self.p.copy_from_slice(&self.z);
        let mut rz = dot(&self.r, &self.z);
        let mut iterations = 0;
        while iterations < self.max_iterations {
            let interrupted = || {
                self.interrupt
                    .as_ref()
                    .is_some_and(|f| f.load(Ordering::Relaxed))
            };
            if iterations % INTERRUPT_CHECK == 0 && interrupted() {
                break;
            }
            iterations += 1;
            self.apply(model);
            let pq = dot(&self.p, &self.q);
            if pq.is_nan() || pq <= 0.0 {
                break; // breakdown (p = 0 or round-off): keep the current iterate
            }
            let alpha = rz / pq;
            for i in 0..n {
                self.dv[i] += self.p[i] * alpha;
                self.r[i] -= self.q[i] * alpha;
            }
            if dot(&self.r, &self.r).sqrt() <= stop {
                return StepStats {
                    cg_iterations: iterations,
                    cg_capped: false,
                };
            }
            for i in 0..n {
                self.z[i] = self.precond[i] * self.r[i];
            }
            let rz_new = dot(&self.r, &self.z);
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..n {
                self.p[i] = self.z[i] + self.p[i] * beta;
            }
        }
        StepStats {
            cg_iterations: iterations,
            cg_capped: dot(&self.r, &self.r).sqrt() > stop,
        }
    }
}
