//! Preconditioned conjugate gradients on the filtered system, matrix-free.
//!
//! The preconditioner ([`Preconditioner`]) is the inverse of each slot's 3x3 diagonal block of
//! `A_f` (block Jacobi), or a factorisation of `A_f` without its bending couplings. CG starts
//! from `dv = 0` and stops at `|r| <= tolerance |b|` (relative to the right-hand side) or at the
//! iteration cap, keeping its last iterate either way.

// Index loops over parallel per-slot arrays read clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use super::cholesky::Cholesky;
use super::system::System;
use crate::math::{Mat3, Real, Vec3};
use crate::physics::integrator::{fit, StepStats};
use crate::physics::ForceModel;
use std::sync::atomic::{AtomicBool, Ordering};

/// CG iterations between two looks at the interrupt flag.
const INTERRUPT_CHECK: usize = 16;

/// What CG preconditions with.
pub(super) enum Preconditioner<'a> {
    /// The inverse of each slot's 3x3 diagonal block of `A_f`.
    BlockJacobi,
    /// A factorisation of the system's matrix without its bending couplings
    /// ([`Cholesky::factorize`] done on this system).
    Factor(&'a mut Cholesky),
}

/// The CG solver: its stopping rule and its scratch buffers (reused across steps).
#[derive(Clone, Debug)]
pub(super) struct Cg {
    tolerance: Real,
    max_iterations: usize,
    precond: Vec<Mat3>,
    r: Vec<Vec3>,
    z: Vec<Vec3>,
    p: Vec<Vec3>,
    q: Vec<Vec3>,
}

impl Cg {
    /// A solver stopping at relative residual `tolerance` (dimensionless) or after
    /// `max_iterations`.
    pub(super) fn new(tolerance: Real, max_iterations: usize) -> Cg {
        Cg {
            tolerance,
            max_iterations,
            precond: Vec::new(),
            r: Vec::new(),
            z: Vec::new(),
            p: Vec::new(),
            q: Vec::new(),
        }
    }

    /// Solves `A_f dv = b` of `system` (built from `model`) for `dv` (m/s, overwritten), from
    /// `dv = 0`, preconditioned by `preconditioner`. Stops early, with the current iterate, once
    /// `interrupt` is set (checked every few iterations). Reports the iterations and whether the
    /// solve ended above tolerance (at the cap or at a breakdown; an interrupted solve is not
    /// counted as unconverged).
    pub(super) fn solve(
        &mut self,
        system: &System,
        model: &ForceModel,
        interrupt: Option<&AtomicBool>,
        mut preconditioner: Preconditioner,
        dv: &mut [Vec3],
    ) -> StepStats {
        let b = &system.b;
        let n = fit(
            b.len(),
            [&mut self.r, &mut self.z, &mut self.p, &mut self.q],
        );
        let dot = |a: &[Vec3], b: &[Vec3]| -> Real { a.iter().zip(b).map(|(x, y)| x.dot(y)).sum() };
        dv.fill(Vec3::zeros());
        self.r.copy_from_slice(b);
        let b_norm = dot(b, b).sqrt();
        if b_norm == 0.0 || !b_norm.is_finite() {
            return StepStats::default();
        }
        if let Preconditioner::BlockJacobi = preconditioner {
            self.precond.resize(n, Mat3::zeros());
            for i in 0..n {
                self.precond[i] = system.diag_blocks[i].try_inverse().unwrap_or_else(|| {
                    Mat3::identity() * (1.0 / system.diag[i].max(Real::MIN_POSITIVE))
                });
            }
        }
        let stop = self.tolerance * b_norm;
        self.precondition(system, &mut preconditioner);
        self.p.copy_from_slice(&self.z);
        let mut rz = dot(&self.r, &self.z);
        let mut iterations = 0;
        while iterations < self.max_iterations {
            let interrupted = || interrupt.is_some_and(|f| f.load(Ordering::Relaxed));
            if iterations % INTERRUPT_CHECK == 0 && interrupted() {
                return StepStats {
                    cg_iterations: iterations,
                    ..StepStats::default()
                };
            }
            iterations += 1;
            system.apply(model, &self.p, &mut self.q);
            let pq = dot(&self.p, &self.q);
            if pq.is_nan() || pq <= 0.0 {
                break; // breakdown (p = 0 or round-off): keep the current iterate
            }
            let alpha = rz / pq;
            for i in 0..n {
                dv[i] += self.p[i] * alpha;
                self.r[i] -= self.q[i] * alpha;
            }
            if dot(&self.r, &self.r).sqrt() <= stop {
                return StepStats {
                    cg_iterations: iterations,
                    ..StepStats::default()
                };
            }
            self.precondition(system, &mut preconditioner);
            let rz_new = dot(&self.r, &self.z);
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..n {
                self.p[i] = self.z[i] + self.p[i] * beta;
            }
        }
        StepStats {
            cg_iterations: iterations,
            unconverged: dot(&self.r, &self.r).sqrt() > stop,
            ..StepStats::default()
        }
    }

    /// `z = P⁻¹ r`, without its part along a held contact's normal (so every iterate stays
    /// where the filter wants it).
    fn precondition(&mut self, system: &System, preconditioner: &mut Preconditioner) {
        match preconditioner {
            Preconditioner::BlockJacobi => {
                for ((z, p), r) in self.z.iter_mut().zip(&self.precond).zip(&self.r) {
                    *z = p * r;
                }
            }
            Preconditioner::Factor(factor) => factor.solve_factored(&self.r, &mut self.z),
        }
        system.project(&mut self.z);
    }
}
