//! The filtered system `A_f` (see [`super::system`]) as a sparse symmetric matrix: its lower
//! triangle in compressed sparse columns, three scalar rows and columns per vertex slot, for the
//! direct solver, in the elimination order: slot `i` owns rows `3 p..3 p + 3` with `p =`
//! [`Pattern::position`]`(i)`, its place in an approximate-minimum-degree ordering of the slots.
//!
//! The sparsity pattern depends only on the topology: a 3x3 block on the diagonal of every slot,
//! and one off-diagonal block per pair of slots joined by a spring or sharing a bending element.
//! [`Pattern::new`] orders the slots and builds the pattern once per topology together with, for
//! every element, where its blocks go; [`Pattern::fill`] writes a step's values straight into
//! it, already permuted, so the factorisation needs no ordering of its own and no permuted copy
//! of the matrix per step. Entries stay in the pattern when they are zero (a spring in
//! compression, a fixed slot's coupling), so the pattern, and with it the solver's symbolic
//! analysis, survives every step until the mesh changes.

use super::system::System;
use crate::math::{Mat3, Real};
use crate::physics::ForceModel;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::{FaerError, SymbolicSparseColMatRef};

/// Pairs `(k, l)` of an element's four vertices, each coupling block of a bending element.
const BEND_PAIRS: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];

/// A model's topology: its slot count, spring ends and bending elements, in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Topology {
    slots: usize,
    spring_a: Vec<u32>,
    spring_b: Vec<u32>,
    bends: Vec<[u32; 4]>,
}

impl Topology {
    /// The topology of `model`.
    pub(super) fn of(model: &ForceModel) -> Topology {
        let sp = model.springs();
        Topology {
            slots: model.mass().len(),
            spring_a: sp.a.clone(),
            spring_b: sp.b.clone(),
            bends: model.bends().v.clone(),
        }
    }

    /// True when `model` has this topology (same slots, springs and bending elements, in the
    /// same order).
    pub(super) fn fits(&self, model: &ForceModel) -> bool {
        let sp = model.springs();
        self.slots == model.mass().len()
            && self.spring_a == sp.a
            && self.spring_b == sp.b
            && self.bends == model.bends().v
    }
}

/// The lower-triangular pattern of `A_f` for one topology, in scalar and in block form, with or
/// without the bending elements' couplings.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Pattern {
    /// The topology it was built for.
    topology: Topology,
    /// Per slot, its place in the elimination order (block row and column).
    position: Vec<usize>,
    /// Per place in the elimination order, its slot (the inverse of `position`).
    slot_at: Vec<usize>,
    /// Off-diagonal blocks by block column: those of place `c` are `block_ptr[c]..block_ptr[c+1]`,
    /// with block rows `block_row` (places after `c`, ascending).
    block_ptr: Vec<usize>,
    block_row: Vec<usize>,
    /// Per spring, the index of its off-diagonal block.
    spring_block: Vec<usize>,
    /// Per bending element, the index of the block of each pair in [`BEND_PAIRS`]; `None` for
    /// a pair outside the pattern (a pattern without bending couplings), whose term goes to
    /// the two slots' diagonal blocks instead.
    bend_block: Vec<[Option<usize>; 6]>,
    /// Scalar column starts (`3 slots + 1` of them) and row indices, sorted within each column, in
    /// the elimination order.
    pub(super) col_ptr: Vec<usize>,
    pub(super) row_idx: Vec<usize>,
}

impl Pattern {
    /// The pattern of `model`'s topology, its slots in approximate-minimum-degree order (fails
    /// only when the ordering's memory cannot be had). With `bending` false, the pattern is the
    /// springs' alone: a bending element's coupling of two slots no spring joins (its two wings)
    /// is left out and compensated on the diagonal by [`Pattern::fill`]. The vertices of each
    /// element are distinct slots (a conforming mesh).
    pub(super) fn new(model: &ForceModel, bending: bool) -> Result<Pattern, FaerError> {
        let slots = model.mass().len();
        let (sp, all_bends) = (model.springs(), &model.bends().v);
        let bends: &[[u32; 4]] = if bending { all_bends } else { &[] };
        let coupled = |place: &dyn Fn(u32) -> usize| {
            // Every coupled pair once, as (column, row) with row > column, sorted.
            let ordered = |p: u32, q: u32| {
                let (p, q) = (place(p), place(q));
                (p.min(q), p.max(q))
            };
            let mut pairs: Vec<(usize, usize)> = (0..sp.len())
                .map(|j| ordered(sp.a[j], sp.b[j]))
                .chain(
                    bends
                        .iter()
                        .flat_map(|v| BEND_PAIRS.map(|(k, l)| ordered(v[k], v[l]))),
                )
                .collect();
            pairs.sort_unstable();
            pairs.dedup();
            let mut block_ptr = vec![0; slots + 1];
            for &(c, _) in &pairs {
                block_ptr[c + 1] += 1;
            }
            for c in 0..slots {
                block_ptr[c + 1] += block_ptr[c];
            }
            let block_row: Vec<usize> = pairs.iter().map(|&(_, r)| r).collect();
            (block_ptr, block_row)
        };
        let (slot_ptr, slot_row) = coupled(&|p| p as usize);
        let (slot_at, position) = minimum_degree_order(&slot_ptr, &slot_row)?;
        let (block_ptr, block_row) = coupled(&|p| position[p as usize]);
        let find =
            |p: u32, q: u32| block_index(&position, &block_ptr, &block_row, p as usize, q as usize);
        let spring_block = (0..sp.len())
            .map(|j| find(sp.a[j], sp.b[j]).expect("every spring is in the pattern"))
            .collect();
        let bend_block: Vec<[Option<usize>; 6]> = all_bends
            .iter()
            .map(|v| BEND_PAIRS.map(|(k, l)| find(v[k], v[l])))
            .collect();
        debug_assert!(
            !bending || bend_block.iter().flatten().all(Option::is_some),
            "the whole pattern holds every bending pair"
        );
        // Scalar column 3c + k: the diagonal block's rows 3c + k..3c + 3, then three rows per
        // off-diagonal block of column c.
        let mut col_ptr = Vec::with_capacity(3 * slots + 1);
        let mut row_idx = Vec::with_capacity(6 * slots + 9 * block_row.len());
        col_ptr.push(0);
        for c in 0..slots {
            for k in 0..3 {
                row_idx.extend(3 * c + k..3 * c + 3);
                for &r in &block_row[block_ptr[c]..block_ptr[c + 1]] {
                    row_idx.extend(3 * r..3 * r + 3);
                }
                col_ptr.push(row_idx.len());
            }
        }
        Ok(Pattern {
            topology: Topology::of(model),
            position,
            slot_at,
            block_ptr,
            block_row,
            spring_block,
            bend_block,
            col_ptr,
            row_idx,
        })
    }

    /// True when `model` has the topology this pattern was built for.
    pub(super) fn fits(&self, model: &ForceModel) -> bool {
        self.topology.fits(model)
    }

    /// The place of `slot` in the elimination order: its scalar rows are `3 p..3 p + 3`.
    pub(super) fn position(&self, slot: usize) -> usize {
        self.position[slot]
    }

    /// The index of the off-diagonal block coupling slots `a` and `b`, `None` when the pattern
    /// has none.
    fn block_of(&self, a: usize, b: usize) -> Option<usize> {
        block_index(&self.position, &self.block_ptr, &self.block_row, a, b)
    }

    /// Number of scalar rows (and columns): three per slot.
    pub(super) fn dim(&self) -> usize {
        3 * self.topology.slots
    }

    /// Writes into `values` (one per entry of [`Pattern::row_idx`]) the lower triangle of
    /// `system`'s `A_f` (kg) or, for a pattern without some bending couplings, of
    /// `P = A_f + sum w s sᵀ` over the couplings `(k, l)` left out, `s` the 3n-vector holding
    /// `u_k` at slot `k` and `-u_l` at slot `l` (zero at a fixed slot): their off-diagonal
    /// blocks cancel, the two diagonal blocks grow by `w u_k u_kᵀ` and `w u_l u_lᵀ`, so `P - A_f`
    /// is positive semi-definite and `P` positive definite; a held slot's rows and columns are
    /// filtered as in `A_f`. `blocks` and `diagonal` are scratch. `model` must fit the pattern
    /// ([`Pattern::fits`]) and be the one `system` was built from. Values are rounded to `T`'s
    /// precision (none for `f64`).
    pub(super) fn fill<T: Precision>(
        &self,
        system: &System,
        model: &ForceModel,
        blocks: &mut Vec<Mat3>,
        diagonal: &mut Vec<Mat3>,
        values: &mut Vec<T>,
    ) {
        blocks.clear();
        blocks.resize(self.block_row.len(), Mat3::zeros());
        diagonal.clear();
        diagonal.extend_from_slice(&system.diag_blocks);
        for (&p, bj) in self.spring_block.iter().zip(&system.spring_blocks) {
            blocks[p] -= bj;
        }
        let bend_terms = model.bends().v.iter().zip(&self.bend_block);
        for ((ids, at), (u, &w)) in bend_terms.zip(system.bend_u.iter().zip(&system.bend_w)) {
            for (&p, &(k, l)) in at.iter().zip(&BEND_PAIRS) {
                let Some(p) = p else {
                    diagonal[ids[k] as usize] += u[k] * u[k].transpose() * w;
                    diagonal[ids[l] as usize] += u[l] * u[l].transpose() * w;
                    continue;
                };
                // The block at (row r, column c), r after c, is w u_r u_cᵀ.
                let later = |k: usize, l: usize| {
                    self.position[ids[k] as usize] > self.position[ids[l] as usize]
                };
                let (r, c) = if later(k, l) { (k, l) } else { (l, k) };
                blocks[p] += u[r] * u[c].transpose() * w;
            }
        }
        for (face, weight) in &system.pressed {
            let nn = face.normal * face.normal.transpose();
            for (k, l) in [(0, 1), (0, 2), (1, 2)] {
                let term = nn * (weight * face.weights[k] * face.weights[l]);
                match self.block_of(face.slots[k], face.slots[l]) {
                    Some(p) => blocks[p] += term,
                    // Outside the pattern (never for a face: its edges are springs), the
                    // coupling goes to the diagonal as a bending pair's does.
                    None => {
                        diagonal[face.slots[k]] += term;
                        diagonal[face.slots[l]] += term;
                    }
                }
            }
        }
        let fixed = |i: usize| model.inv_mass()[i] == 0.0;
        // A held slot's filter `S = I - n nᵀ` on its rows and columns; `n nᵀ` on its diagonal.
        let filter = |i: usize| system.held_at[i].map(|n| Mat3::identity() - n * n.transpose());
        for (slot, d) in diagonal.iter_mut().enumerate() {
            if let (Some(s), Some(n)) = (filter(slot), system.held_at[slot]) {
                *d = s * *d * s + n * n.transpose();
            }
        }
        for c in 0..self.topology.slots {
            let col = filter(self.slot_at[c]);
            let range = self.block_ptr[c]..self.block_ptr[c + 1];
            for (block, &r) in blocks[range.clone()].iter_mut().zip(&self.block_row[range]) {
                let row = filter(self.slot_at[r]);
                if row.is_some() || col.is_some() {
                    let identity = Mat3::identity;
                    *block = row.unwrap_or_else(identity) * *block * col.unwrap_or_else(identity);
                }
            }
        }
        values.clear();
        values.resize(self.row_idx.len(), T::from_f64(0.0));
        for c in 0..self.topology.slots {
            let range = self.block_ptr[c]..self.block_ptr[c + 1];
            let slot = self.slot_at[c];
            for k in 0..3 {
                let start = self.col_ptr[3 * c + k];
                // A fixed slot's block is the identity's, whatever was added to it.
                let diag = if fixed(slot) {
                    &system.diag_blocks[slot]
                } else {
                    &diagonal[slot]
                };
                for i in k..3 {
                    values[start + i - k] = T::from_f64(diag[(i, k)]);
                }
                if fixed(slot) {
                    continue; // the column of a fixed slot is the identity's
                }
                for (q, p) in range.clone().enumerate() {
                    let row_slot = self.slot_at[self.block_row[p]];
                    if fixed(row_slot) {
                        continue;
                    }
                    for i in 0..3 {
                        values[start + 3 - k + 3 * q + i] = T::from_f64(blocks[p][(i, k)]);
                    }
                }
            }
        }
    }
}

/// The index of the off-diagonal block coupling slots `a` and `b` in a pattern's blocks
/// (`position`, `block_ptr`, `block_row` as in [`Pattern`]), `None` when it has none.
fn block_index(
    position: &[usize],
    block_ptr: &[usize],
    block_row: &[usize],
    a: usize,
    b: usize,
) -> Option<usize> {
    let (p, q) = (position[a], position[b]);
    let (c, r) = (p.min(q), p.max(q));
    let rows = &block_row[block_ptr[c]..block_ptr[c + 1]];
    rows.binary_search(&r).ok().map(|k| block_ptr[c] + k)
}

/// A floating-point type the factorisation can work in: `f64`, or `f32` for a preconditioner
/// (half the memory to stream through per solve).
pub(super) trait Precision:
    faer::traits::ComplexField
    + Copy
    + Send
    + Sync
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
    + std::ops::AddAssign
    + std::ops::SubAssign
{
    /// `x` rounded to this precision.
    fn from_f64(x: Real) -> Self;
    /// `self` as an `f64` (exact).
    fn to_f64(self) -> Real;
}

impl Precision for f64 {
    fn from_f64(x: Real) -> Self {
        x
    }
    fn to_f64(self) -> Real {
        self
    }
}

impl Precision for f32 {
    fn from_f64(x: Real) -> Self {
        x as f32
    }
    fn to_f64(self) -> Real {
        Real::from(self)
    }
}

/// An approximate-minimum-degree order of the slots of the block pattern `(ptr, row)` (the lower
/// triangle's off-diagonal blocks by column): per place the slot there, and per slot its place.
/// Ordering the slots rather than the scalar rows keeps each slot's three rows together.
fn minimum_degree_order(
    ptr: &[usize],
    row: &[usize],
) -> Result<(Vec<usize>, Vec<usize>), FaerError> {
    let n = ptr.len() - 1;
    let (mut slot_at, mut position) = (vec![0; n], vec![0; n]);
    let structure = SymbolicSparseColMatRef::new_checked(n, n, ptr, None, row);
    let mut scratch = MemBuffer::try_new(amd::order_scratch::<usize>(n, row.len()))?;
    amd::order(
        &mut slot_at,
        &mut position,
        structure,
        amd::Control::default(),
        MemStack::new(&mut scratch),
    )?;
    Ok((slot_at, position))
}
