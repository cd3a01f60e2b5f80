//! The two triangular solves with a supernodal Cholesky factor `L` (`L Lᵀ x = b`) in faer's
//! layout: each supernode a dense column-major block of its columns, its diagonal block on top
//! of the rows of its pattern. The supernodes are split once per symbolic analysis over the
//! elimination tree into two groups of whole subtrees and the common ancestors above them
//! ([`TreeSplit`]), so two threads can share a solve: the groups run side by side, the
//! ancestors alone. Each group's updates to the ancestors' rows are summed apart and added in a
//! fixed order, so the arithmetic, and the result, is the same on one thread or two.

use super::assembly::Precision;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;

/// Below this many factor entries a solve stays on one thread: handing a group to the other
/// thread costs more than it saves.
pub(super) const PARALLEL_ENTRIES: usize = 50_000;

/// The groups are balanced once the heavier holds at most this fraction of their entries.
pub(super) const BALANCE: f64 = 0.55;

/// Marks a column that is not an ancestor's in [`TreeSplit::top_index`].
const NOT_TOP: u32 = u32::MAX;

/// A factor's supernodes (by index in faer's symbolic analysis, which holds their structure)
/// split into two groups of subtrees and their common ancestors.
#[derive(Debug)]
pub(super) struct TreeSplit {
    /// The supernodes of each group, increasing (a node's descendants come before it).
    groups: [Vec<usize>; 2],
    /// The common ancestors, increasing.
    top: Vec<usize>,
    /// For every column, its place among the ancestors' columns, or [`NOT_TOP`].
    top_index: Vec<u32>,
    /// The ancestors' columns, increasing.
    top_columns: Vec<usize>,
}

/// A numeric factor for a split: its symbolic structure (the analysis the split was made
/// from), its values in faer's supernodal layout and the reciprocals of its diagonal
/// ([`inverse_diagonal`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Factor<'a, T> {
    pub(super) symbolic: &'a SymbolicSupernodalCholesky<usize>,
    pub(super) values: &'a [T],
    pub(super) inverse_diagonal: &'a [T],
}

/// Buffers of a solve, reused across solves.
#[derive(Debug, Default)]
pub(super) struct SolveScratch<T> {
    /// A copy of `x` for group 0, whose columns are disjoint from group 1's.
    copy: Vec<T>,
    /// Each group's sums of its updates to the ancestors' rows.
    sums: [Vec<T>; 2],
    /// Each thread's dense work vector (a supernode's rows).
    work: [Vec<T>; 2],
}

impl TreeSplit {
    /// The split of the supernodes of `symbolic`: starting from the roots, the heaviest subtree
    /// (by factor entries) is opened, its root going to the ancestors, until the subtrees can be
    /// dealt to two groups, heaviest first to the lighter, with neither holding more than 55 % of
    /// the groups' entries, or until the heaviest subtree is a single supernode.
    pub(super) fn new(symbolic: &SymbolicSupernodalCholesky<usize>) -> TreeSplit {
        let ns = symbolic.n_supernodes();
        let mut begin = symbolic.supernode_begin().to_vec();
        begin.push(symbolic.nrows());
        let mut row_ptr = Vec::with_capacity(ns + 1);
        let mut rows = Vec::new();
        row_ptr.push(0);
        for s in 0..ns {
            rows.extend_from_slice(symbolic.supernode(s).pattern());
            row_ptr.push(rows.len());
        }
        let val_ptr = symbolic.col_ptr_for_val().to_vec();
        let mut owner = vec![0; symbolic.nrows()];
        for s in 0..ns {
            owner[begin[s]..begin[s + 1]].fill(s);
        }
        // A supernode's parent holds its pattern's first row; children precede their parent.
        let mut children = vec![Vec::new(); ns];
        let mut roots = Vec::new();
        let mut weight: Vec<usize> = (0..ns).map(|s| val_ptr[s + 1] - val_ptr[s]).collect();
        for s in 0..ns {
            match rows[row_ptr[s]..row_ptr[s + 1]].iter().min() {
                Some(&r) => {
                    let p = owner[r];
                    children[p].push(s);
                    weight[p] += weight[s];
                }
                None => roots.push(s),
            }
        }
        let mut frontier = roots;
        let mut top = Vec::new();
        let bins = loop {
            let bins = deal(&frontier, &weight);
            let load = |b: &Vec<usize>| b.iter().map(|&s| weight[s]).sum::<usize>();
            let (a, b) = (load(&bins[0]), load(&bins[1]));
            if a.max(b) as f64 <= BALANCE * (a + b) as f64 {
                break bins;
            }
            let heaviest = bins[0][0];
            if children[heaviest].is_empty() {
                break bins;
            }
            frontier.retain(|&s| s != heaviest);
            frontier.extend_from_slice(&children[heaviest]);
            top.push(heaviest);
        };
        let groups = bins.map(|subtree_roots| {
            let mut nodes = Vec::new();
            let mut stack = subtree_roots;
            while let Some(s) = stack.pop() {
                nodes.push(s);
                stack.extend_from_slice(&children[s]);
            }
            nodes.sort_unstable();
            nodes
        });
        top.sort_unstable();
        let mut top_index = vec![NOT_TOP; symbolic.nrows()];
        let mut top_columns = Vec::new();
        for &s in &top {
            top_columns.extend(begin[s]..begin[s + 1]);
        }
        for (k, &c) in top_columns.iter().enumerate() {
            top_index[c] = k as u32;
        }
        TreeSplit {
            groups,
            top,
            top_index,
            top_columns,
        }
    }

    /// True when a solve with a factor of `symbolic` (the analysis this split was made from)
    /// shares its groups between two threads: on a thread of a pool that can help
    /// ([`crate::parallel::pool_thread_can_share`]), both groups holding supernodes and the
    /// factor at least `PARALLEL_ENTRIES` entries.
    pub(super) fn shares_solves(&self, symbolic: &SymbolicSupernodalCholesky<usize>) -> bool {
        symbolic.len_val() >= PARALLEL_ENTRIES
            && self.groups.iter().all(|g| !g.is_empty())
            && crate::parallel::pool_thread_can_share()
    }

    /// Solves `L Lᵀ x = b` in place (`x` holds `b` on entry) with `factor`; the two groups run
    /// on two threads when [`TreeSplit::shares_solves`], one after the other otherwise.
    pub(super) fn solve<T: Precision>(
        &self,
        factor: Factor<'_, T>,
        x: &mut [T],
        scratch: &mut SolveScratch<T>,
    ) {
        let zero = T::from_f64(0.0);
        let SolveScratch { copy, sums, work } = scratch;
        let [sums0, sums1] = sums;
        let [work0, work1] = work;
        let parallel = self.shares_solves(factor.symbolic);
        let both = |a: &mut (dyn FnMut() + Send), b: &mut (dyn FnMut() + Send)| {
            if parallel {
                rayon::join(a, b);
            } else {
                a();
                b();
            }
        };
        // Forward, L y = b: the groups, their sums to the ancestors' rows, the ancestors.
        for s in [&mut *sums0, &mut *sums1] {
            s.clear();
            s.resize(self.top_columns.len(), zero);
        }
        copy.clear();
        copy.extend_from_slice(x);
        {
            let x1 = &mut *x;
            both(
                &mut || {
                    self.substitute(
                        Pass::Forward,
                        &self.groups[0],
                        factor,
                        copy,
                        Some(sums0),
                        work0,
                    )
                },
                &mut || {
                    self.substitute(
                        Pass::Forward,
                        &self.groups[1],
                        factor,
                        x1,
                        Some(sums1),
                        work1,
                    )
                },
            );
        }
        self.take_first_group(factor.symbolic, copy, x);
        for (k, &c) in self.top_columns.iter().enumerate() {
            x[c] += sums0[k] + sums1[k];
        }
        self.substitute(Pass::Forward, &self.top, factor, x, None, work0);
        // Backward, Lᵀ x = y: the ancestors, then the groups.
        self.substitute(Pass::Backward, &self.top, factor, x, None, work0);
        copy.clear();
        copy.extend_from_slice(x);
        {
            let x1 = &mut *x;
            both(
                &mut || self.substitute(Pass::Backward, &self.groups[0], factor, copy, None, work0),
                &mut || self.substitute(Pass::Backward, &self.groups[1], factor, x1, None, work1),
            );
        }
        self.take_first_group(factor.symbolic, copy, x);
    }

    /// Copies the first group's columns from `from` (where that group was solved) into `x`.
    fn take_first_group<T: Precision>(
        &self,
        symbolic: &SymbolicSupernodalCholesky<usize>,
        from: &[T],
        x: &mut [T],
    ) {
        for &s in &self.groups[0] {
            let cols = columns(symbolic, s);
            x[cols.clone()].copy_from_slice(&from[cols]);
        }
    }

    /// Substitutes `nodes` in `pass`: forward in increasing order (updates of an ancestor's row
    /// into `sums` when given), backward in decreasing order (`sums` unused). Compiled for AVX2
    /// when the CPU has it: the same operations in the same order either way, no fused
    /// multiply-add, so the same result.
    fn substitute<T: Precision>(
        &self,
        pass: Pass,
        nodes: &[usize],
        factor: Factor<'_, T>,
        x: &mut [T],
        sums: Option<&mut [T]>,
        work: &mut Vec<T>,
    ) {
        dispatch!(
            substitute_avx2,
            substitute_body::<T>(self, pass, nodes, factor, x, sums, work)
        )
    }

    /// Forward substitution of each of `nodes` in turn: its columns of `x` solved with its
    /// diagonal block, then its pattern's rows updated, those of an ancestor into `sums` when
    /// given (a group's nodes).
    #[inline(always)]
    fn forward_nodes_body<T: Precision>(
        &self,
        nodes: &[usize],
        factor: Factor<'_, T>,
        x: &mut [T],
        mut sums: Option<&mut [T]>,
        work: &mut Vec<T>,
    ) {
        let zero = T::from_f64(0.0);
        for &s in nodes {
            let (block, cols, pattern) = node(s, factor);
            let (nc, nr) = (cols.len(), cols.len() + pattern.len());
            work.clear();
            work.extend_from_slice(&x[cols.clone()]);
            work.resize(nr, zero);
            let (top, below) = work.split_at_mut(nc);
            for j in 0..nc {
                let column = &block[j * nr..j * nr + nc];
                let xj = top[j] * factor.inverse_diagonal[cols.start + j];
                top[j] = xj;
                for (w, &l) in top[j + 1..].iter_mut().zip(&column[j + 1..]) {
                    *w -= l * xj;
                }
            }
            for (j, &xj) in top.iter().enumerate() {
                let column = &block[j * nr + nc..(j + 1) * nr];
                for (w, &l) in below.iter_mut().zip(column) {
                    *w -= l * xj;
                }
            }
            x[cols].copy_from_slice(top);
            for (&r, &update) in pattern.iter().zip(below.iter()) {
                match (&mut sums, self.top_index[r]) {
                    (Some(sums), k) if k != NOT_TOP => sums[k as usize] += update,
                    _ => x[r] += update,
                }
            }
        }
    }

    /// Backward substitution of each of `nodes`, last first: its columns of `x` solved from its
    /// pattern's rows (already solved: they are its ancestors'), then with its diagonal block.
    #[inline(always)]
    fn backward_nodes_body<T: Precision>(
        &self,
        nodes: &[usize],
        factor: Factor<'_, T>,
        x: &mut [T],
        work: &mut Vec<T>,
    ) {
        for &s in nodes.iter().rev() {
            let (block, cols, pattern) = node(s, factor);
            let (nc, nr) = (cols.len(), cols.len() + pattern.len());
            work.clear();
            work.extend_from_slice(&x[cols.clone()]);
            work.extend(pattern.iter().map(|&r| x[r]));
            let (top, below) = work.split_at_mut(nc);
            for (j, t) in top.iter_mut().enumerate() {
                *t -= dot(&block[j * nr + nc..(j + 1) * nr], below);
            }
            for j in (0..nc).rev() {
                let column = &block[j * nr..j * nr + nc];
                top[j] = (top[j] - dot(&column[j + 1..], &top[j + 1..]))
                    * factor.inverse_diagonal[cols.start + j];
            }
            x[cols].copy_from_slice(top);
        }
    }
}

#[cfg(test)]
impl TreeSplit {
    /// Checks the split: every supernode is in one group or among the ancestors, exactly once; a
    /// group's node has its pattern's rows in its own group or among the ancestors, an
    /// ancestor's among the ancestors (what lets the groups run side by side, then the ancestors
    /// alone). Returns the factor entries of the two groups and of the ancestors.
    pub(super) fn check(
        &self,
        symbolic: &SymbolicSupernodalCholesky<usize>,
    ) -> Result<[usize; 3], String> {
        let ns = symbolic.n_supernodes();
        let begin = symbolic.supernode_begin();
        let offsets = symbolic.col_ptr_for_val();
        let mut place = vec![usize::MAX; ns];
        let lists = [&self.groups[0], &self.groups[1], &self.top];
        for (g, list) in lists.iter().enumerate() {
            for &s in list.iter() {
                if place[s] != usize::MAX {
                    return Err(format!("supernode {s} placed twice"));
                }
                place[s] = g;
            }
        }
        if let Some(s) = place.iter().position(|&g| g == usize::MAX) {
            return Err(format!("supernode {s} placed nowhere"));
        }
        let owner = |r: usize| begin.partition_point(|&b| b <= r) - 1;
        for s in 0..ns {
            for &r in symbolic.supernode(s).pattern() {
                let g = place[owner(r)];
                if g != place[s] && g != 2 {
                    return Err(format!("supernode {s} updates row {r} of group {g}"));
                }
            }
        }
        let entries =
            |list: &[usize]| -> usize { list.iter().map(|&s| offsets[s + 1] - offsets[s]).sum() };
        Ok(lists.map(|l| entries(l)))
    }
}

/// The columns of supernode `s` of `symbolic`.
#[inline(always)]
fn columns(symbolic: &SymbolicSupernodalCholesky<usize>, s: usize) -> std::ops::Range<usize> {
    symbolic.supernode_begin()[s]..symbolic.supernode_end()[s]
}

/// Supernode `s`'s block of `factor`'s values, its columns and its pattern.
#[inline(always)]
fn node<T>(s: usize, factor: Factor<'_, T>) -> (&[T], std::ops::Range<usize>, &[usize]) {
    let offsets = factor.symbolic.col_ptr_for_val();
    (
        &factor.values[offsets[s]..offsets[s + 1]],
        columns(factor.symbolic, s),
        factor.symbolic.supernode(s).pattern(),
    )
}

/// The reciprocals of the diagonal of a factor of `symbolic` with `values` (faer's supernodal
/// layout), one per column, into `inverse`: the solves multiply by them, a division's latency
/// being most of a column's cost on the substitutions' critical path.
pub(super) fn inverse_diagonal<T: Precision>(
    symbolic: &SymbolicSupernodalCholesky<usize>,
    values: &[T],
    inverse: &mut Vec<T>,
) {
    inverse.clear();
    let one = T::from_f64(1.0);
    let factor = Factor {
        symbolic,
        values,
        inverse_diagonal: &[],
    };
    for s in 0..symbolic.n_supernodes() {
        let (block, cols, pattern) = node(s, factor);
        let nr = cols.len() + pattern.len();
        inverse.extend((0..cols.len()).map(|j| one / block[j * nr + j]));
    }
}

/// Which substitution: `L y = b` or `Lᵀ x = y`.
#[derive(Clone, Copy, Debug)]
enum Pass {
    Forward,
    Backward,
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn substitute_avx2<T: Precision>(
    split: &TreeSplit,
    pass: Pass,
    nodes: &[usize],
    factor: Factor<'_, T>,
    x: &mut [T],
    sums: Option<&mut [T]>,
    work: &mut Vec<T>,
) {
    substitute_body::<T>(split, pass, nodes, factor, x, sums, work)
}

#[inline(always)]
fn substitute_body<T: Precision>(
    split: &TreeSplit,
    pass: Pass,
    nodes: &[usize],
    factor: Factor<'_, T>,
    x: &mut [T],
    sums: Option<&mut [T]>,
    work: &mut Vec<T>,
) {
    match pass {
        Pass::Forward => split.forward_nodes_body(nodes, factor, x, sums, work),
        Pass::Backward => split.backward_nodes_body(nodes, factor, x, work),
    }
}

/// The subtrees rooted at `roots` dealt heaviest first (ties by index) to the lighter of two
/// groups (ties to the first); each group's roots in that order.
fn deal(roots: &[usize], weight: &[usize]) -> [Vec<usize>; 2] {
    let mut order = roots.to_vec();
    order.sort_unstable_by_key(|&s| (std::cmp::Reverse(weight[s]), s));
    let mut bins: [Vec<usize>; 2] = [Vec::new(), Vec::new()];
    let mut load = [0usize; 2];
    for s in order {
        let g = usize::from(load[1] < load[0]);
        bins[g].push(s);
        load[g] += weight[s];
    }
    bins
}

/// `a · b` summed in eight interleaved partial sums (so the loop vectorises), added pairwise.
#[inline(always)]
fn dot<T: Precision>(a: &[T], b: &[T]) -> T {
    let zero = T::from_f64(0.0);
    let mut part = [zero; 8];
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: T = a8
        .remainder()
        .iter()
        .zip(b8.remainder())
        .fold(zero, |acc, (&p, &q)| acc + p * q);
    for (p, q) in a8.zip(b8) {
        for k in 0..8 {
            part[k] += p[k] * q[k];
        }
    }
    ((part[0] + part[1]) + (part[2] + part[3])) + ((part[4] + part[5]) + (part[6] + part[7])) + tail
}
