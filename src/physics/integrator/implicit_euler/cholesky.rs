//! The direct solver: sparse Cholesky (`L Lᵀ`, `faer`) of the assembled filtered system, in double
//! precision; and the preconditioner of `pcg_springs`, the same in single precision for the
//! matrix with the bending couplings outside the springs' pattern moved to the diagonal.
//!
//! The symbolic analysis (the slots' approximate-minimum-degree ordering, [`Pattern::new`], and
//! the structure of `L`) depends only on the pattern, so it is kept while the topology is
//! unchanged (same slots, springs and bending elements as the previous step) and redone after a
//! mesh edit; each step then costs one numeric factorisation and, per solve (one for the direct
//! solver, one per CG iteration for the preconditioner), two triangular solves
//! ([`super::supernodal_solve`], shared by two threads on a large factor). The factorisation is
//! sequential (`Par::Seq`) and the solves' arithmetic does not depend on the thread count, so
//! neither do the results. Allocation-free in steady state.

use super::assembly::{Pattern, Precision};
use super::supernodal_solve::{inverse_diagonal, Factor, SolveScratch, TreeSplit};
use super::system::System;
use crate::math::{Mat3, Vec3};
use crate::physics::ForceModel;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{FaerError, SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Par, Side};

/// The direct solve of a step failed: the matrix is not numerically positive definite (a
/// non-positive or non-finite pivot), or its symbolic analysis could not be done (out of memory).
/// The caller falls back to conjugate gradients.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct DirectFailure;

/// The analysis of one pattern: the pattern, its symbolic factorisation, the scratch memory
/// the numeric factorisation needs and the split of the factor's supernodes for the solves.
struct Analysis {
    pattern: Pattern,
    symbolic: SymbolicCholesky<usize>,
    scratch: MemBuffer,
    split: TreeSplit,
}

/// The numeric side in one precision: the matrix's values, its factor and the reciprocals of
/// the factor's diagonal, a right-hand side and the solves' buffers, each reused across steps.
#[derive(Default)]
struct Numeric<T> {
    values: Vec<T>,
    factor: Vec<T>,
    inverse_diagonal: Vec<T>,
    rhs: Vec<T>,
    solve_scratch: SolveScratch<T>,
}

impl<T: Precision> Numeric<T> {
    /// Factorises the matrix of `system` (built from `model`) in `analysis`'s pattern; `blocks`
    /// and `diagonal` are scratch.
    fn factorize(
        &mut self,
        analysis: &mut Analysis,
        system: &System,
        model: &ForceModel,
        blocks: &mut Vec<Mat3>,
        diagonal: &mut Vec<Mat3>,
    ) -> Result<(), DirectFailure> {
        let Analysis {
            pattern,
            symbolic,
            scratch,
            ..
        } = analysis;
        pattern.fill(system, model, blocks, diagonal, &mut self.values);
        let n = pattern.dim();
        let a_lower = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &pattern.col_ptr, None, &pattern.row_idx),
            &self.values,
        );
        self.factor.resize(symbolic.len_val(), T::from_f64(0.0));
        symbolic
            .factorize_numeric_llt(
                &mut self.factor,
                a_lower,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(scratch),
                Default::default(),
            )
            .map_err(|_| DirectFailure)?;
        inverse_diagonal(
            supernodal(symbolic),
            &self.factor,
            &mut self.inverse_diagonal,
        );
        Ok(())
    }

    /// Solves with the factor of the last successful [`Numeric::factorize`] in `analysis`.
    fn solve(&mut self, analysis: &Analysis, b: &[Vec3], x: &mut [Vec3]) {
        let Analysis {
            pattern,
            symbolic,
            split,
            ..
        } = analysis;
        let n = pattern.dim();
        self.rhs.clear();
        self.rhs.resize(n, T::from_f64(0.0));
        for (i, bi) in b.iter().enumerate() {
            let p = 3 * pattern.position(i);
            for k in 0..3 {
                self.rhs[p + k] = T::from_f64(bi[k]);
            }
        }
        let factor = Factor {
            symbolic: supernodal(symbolic),
            values: &self.factor,
            inverse_diagonal: &self.inverse_diagonal,
        };
        split.solve(factor, &mut self.rhs, &mut self.solve_scratch);
        for (i, xi) in x.iter_mut().enumerate() {
            let p = 3 * pattern.position(i);
            *xi = Vec3::from_fn(|k, _| self.rhs[p + k].to_f64());
        }
    }
}

/// What a [`Cholesky`] factorises, and in which precision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Factored {
    /// The whole `A_f`, in double precision: the direct solve.
    Whole,
    /// `A_f` with the bending couplings outside the springs' pattern moved to the diagonal, in
    /// single precision: the preconditioner of [`super::LinearSolver::PcgSprings`].
    SpringsSingle,
}

/// Sparse Cholesky of `A_f`, or of the preconditioner `P` of [`Factored::SpringsSingle`], with
/// the symbolic analysis kept across steps.
pub(super) struct Cholesky {
    analysis: Option<Analysis>,
    /// Whether the numbers hold the factorisation of the current analysis's last fill.
    factored: bool,
    /// Symbolic analyses done so far (one per topology met).
    pub(super) analyses: u64,
    blocks: Vec<Mat3>,
    diagonal: Vec<Mat3>,
    numbers: Numbers,
}

/// The numeric side of a [`Cholesky`], in the precision of what it factorises.
enum Numbers {
    /// [`Factored::Whole`].
    Whole(Numeric<f64>),
    /// [`Factored::SpringsSingle`].
    SpringsSingle(Numeric<f32>),
}

impl std::fmt::Debug for Cholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Cholesky")
            .field("what", &self.what())
            .field("analyses", &self.analyses)
            .field("factored", &self.factored)
            .finish_non_exhaustive()
    }
}

impl Cholesky {
    /// A factorisation of `what`, none done yet.
    pub(super) fn new(what: Factored) -> Cholesky {
        Cholesky {
            analysis: None,
            factored: false,
            analyses: 0,
            blocks: Vec::new(),
            diagonal: Vec::new(),
            numbers: match what {
                Factored::Whole => Numbers::Whole(Numeric::default()),
                Factored::SpringsSingle => Numbers::SpringsSingle(Numeric::default()),
            },
        }
    }

    /// What this factorises.
    fn what(&self) -> Factored {
        match self.numbers {
            Numbers::Whole(_) => Factored::Whole,
            Numbers::SpringsSingle(_) => Factored::SpringsSingle,
        }
    }

    /// Solves `A_f dv = b` of `system` (built from `model`) for `dv` (m/s, overwritten; 0 at
    /// fixed slots); only for [`Factored::Whole`]. On failure `dv` is unspecified and the
    /// symbolic analysis is kept.
    pub(super) fn solve(
        &mut self,
        system: &System,
        model: &ForceModel,
        dv: &mut [Vec3],
    ) -> Result<(), DirectFailure> {
        assert_eq!(self.what(), Factored::Whole, "a solve of the whole system");
        self.factorize(system, model)?;
        self.solve_factored(&system.b, dv);
        Ok(())
    }

    /// Factorises `system`'s matrix (built from `model`) as [`Factored`] says, redoing the
    /// symbolic analysis when the topology changed. On failure no factorisation is held and the
    /// symbolic analysis is kept.
    pub(super) fn factorize(
        &mut self,
        system: &System,
        model: &ForceModel,
    ) -> Result<(), DirectFailure> {
        self.factored = false;
        let analysis = match &mut self.analysis {
            Some(a) if a.pattern.fits(model) => a,
            slot => {
                *slot = None; // free the old analysis first
                let fresh = slot.insert(match &self.numbers {
                    Numbers::Whole(_) => analyse::<f64>(Pattern::new(model, true)),
                    Numbers::SpringsSingle(_) => analyse::<f32>(Pattern::new(model, false)),
                }?);
                self.analyses += 1;
                fresh
            }
        };
        let (blocks, diagonal) = (&mut self.blocks, &mut self.diagonal);
        match &mut self.numbers {
            Numbers::Whole(n) => n.factorize(analysis, system, model, blocks, diagonal)?,
            Numbers::SpringsSingle(n) => n.factorize(analysis, system, model, blocks, diagonal)?,
        }
        self.factored = true;
        Ok(())
    }

    /// True when the solves with the current analysis's factor are shared by two threads
    /// ([`TreeSplit::shares_solves`]).
    pub(super) fn shares_solves(&self) -> bool {
        self.analysis
            .as_ref()
            .is_some_and(|a| a.split.shares_solves(supernodal(&a.symbolic)))
    }

    /// Solves `A x = b` (`b` in N s, `x` in m/s, one per slot) with the matrix of the last
    /// successful [`Cholesky::factorize`], which must have been of a model with these slots.
    pub(super) fn solve_factored(&mut self, b: &[Vec3], x: &mut [Vec3]) {
        let Some(analysis) = self.analysis.as_ref().filter(|_| self.factored) else {
            unreachable!("a solve after a successful factorisation");
        };
        match &mut self.numbers {
            Numbers::Whole(n) => n.solve(analysis, b, x),
            Numbers::SpringsSingle(n) => n.solve(analysis, b, x),
        }
    }
}

#[cfg(test)]
impl Cholesky {
    /// [`TreeSplit::check`] of the current analysis's split, if there is an analysis.
    pub(super) fn check_split(&self) -> Option<Result<[usize; 3], String>> {
        let a = self.analysis.as_ref()?;
        Some(a.split.check(supernodal(&a.symbolic)))
    }
}

/// The symbolic analysis of `pattern` (lower triangle, already in elimination order,
/// supernodal; a pattern that could not be built fails), its scratch memory for factorising in
/// precision `T` and the split of its supernodes for the solves.
fn analyse<T: Precision>(pattern: Result<Pattern, FaerError>) -> Result<Analysis, DirectFailure> {
    let pattern = pattern.map_err(|_| DirectFailure)?;
    let n = pattern.dim();
    // Without an ordering of its own, faer's symbolic analysis reads the upper triangle.
    let (upper_ptr, upper_row) = transpose(n, &pattern.col_ptr, &pattern.row_idx);
    let structure = SymbolicSparseColMatRef::new_checked(n, n, &upper_ptr, None, &upper_row);
    let symbolic = factorize_symbolic_cholesky(
        structure,
        Side::Lower,
        // The pattern is in its elimination order already.
        SymmetricOrdering::Identity,
        // Supernodal always: faer's automatic choice takes the simplicial (scalar) factorisation
        // for small meshes, three times slower here (17x17 sphere_peer: 1.9 against 0.65 ms a
        // step); the 3x3 blocks make supernodes of every vertex.
        CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        },
    )
    .map_err(|_| DirectFailure)?;
    let need = symbolic.factorize_numeric_llt_scratch::<T>(Par::Seq, Default::default());
    let scratch = MemBuffer::try_new(need).map_err(|_| DirectFailure)?;
    let split = TreeSplit::new(supernodal(&symbolic));
    Ok(Analysis {
        pattern,
        symbolic,
        scratch,
        split,
    })
}

/// The supernodal structure of `symbolic` (the analysis is forced supernodal).
fn supernodal(symbolic: &SymbolicCholesky<usize>) -> &SymbolicSupernodalCholesky<usize> {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(supernodal) => supernodal,
        SymbolicCholeskyRaw::Simplicial(_) => unreachable!("the analysis is forced supernodal"),
    }
}

/// The transpose of the `n x n` compressed-column structure `(ptr, row)`, rows sorted in each
/// column.
fn transpose(n: usize, ptr: &[usize], row: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut t_ptr = vec![0; n + 1];
    for &r in row {
        t_ptr[r + 1] += 1;
    }
    for c in 0..n {
        t_ptr[c + 1] += t_ptr[c];
    }
    let mut next = t_ptr.clone();
    let mut t_row = vec![0; row.len()];
    for c in 0..n {
        for &r in &row[ptr[c]..ptr[c + 1]] {
            t_row[next[r]] = c;
            next[r] += 1;
        }
    }
    (t_ptr, t_row)
}
