//! Which springs and bending elements touch each vertex slot, so a per-element sum (forces, the
//! implicit system's product) can be gathered per vertex in parallel instead of scattered from
//! each element: no two threads write one slot, and each slot adds its terms in element order,
//! the order of the serial sweep over elements, so the result is the same bit for bit whatever
//! the thread count.

use super::{Bends, Springs};
use crate::math::Vec3;
use rayon::prelude::*;
use std::sync::Mutex;

/// Items per parallel task (a fixed size, so the split does not depend on the thread count).
pub const CHUNK: usize = 1024;

/// Below this many vertex slots the per-element sweeps stay serial (a parallel call costs tens
/// of microseconds; a sweep over a smaller cloth takes about as long).
pub const PARALLEL_MIN_SLOTS: usize = 2048;

/// True when sweeps over `slots` vertex slots run in parallel: from [`PARALLEL_MIN_SLOTS`] on,
/// with more than one thread in the pool.
pub fn parallel_for(slots: usize) -> bool {
    slots >= PARALLEL_MIN_SLOTS && rayon::current_num_threads() > 1
}

/// Compressed lists, per vertex slot, of the springs and bending elements touching it, each list
/// in increasing element index.
#[derive(Clone, Debug, Default)]
pub struct Incidence {
    spring_start: Vec<u32>,
    /// `j << 1 | role`, role 0 for the spring's first end `a`, 1 for its second `b`.
    spring_items: Vec<u32>,
    bend_start: Vec<u32>,
    /// `e << 2 | k`: element `e`, the slot being its `k`-th vertex.
    bend_items: Vec<u32>,
}

/// One spring at a slot: its index and whether the slot is its second end (the force there is
/// the opposite of the first end's).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpringEnd {
    /// Spring index.
    pub j: usize,
    /// True at the second end `b`.
    pub second: bool,
}

/// One bending element at a slot: its index and the slot's place `k` (0-3) in it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BendCorner {
    /// Element index.
    pub e: usize,
    /// Place of the slot among the element's four vertices.
    pub k: usize,
}

impl Incidence {
    /// Lists, for `slots` vertex slots, the springs and bending elements touching each. Reuses the
    /// buffers. Element counts must fit the packed indices (below 2^31 springs, 2^30 elements).
    pub fn rebuild(&mut self, slots: usize, springs: &Springs, bends: &Bends) {
        let ends = springs.a.iter().zip(&springs.b).enumerate();
        fill(
            &mut self.spring_start,
            &mut self.spring_items,
            slots,
            ends.flat_map(|(j, (&a, &b))| [(a, (j as u32) << 1), (b, (j as u32) << 1 | 1)]),
        );
        let corners = bends
            .v
            .iter()
            .enumerate()
            .flat_map(|(e, ids)| (0..4).map(move |k| (ids[k], (e as u32) << 2 | k as u32)));
        fill(&mut self.bend_start, &mut self.bend_items, slots, corners);
    }

    /// The springs at slot `i`, in increasing index.
    pub fn springs_at(&self, i: usize) -> impl Iterator<Item = SpringEnd> + '_ {
        let range = self.spring_start[i] as usize..self.spring_start[i + 1] as usize;
        self.spring_items[range].iter().map(|&item| SpringEnd {
            j: (item >> 1) as usize,
            second: item & 1 == 1,
        })
    }

    /// The bending elements at slot `i`, in increasing index.
    pub fn bends_at(&self, i: usize) -> impl Iterator<Item = BendCorner> + '_ {
        let range = self.bend_start[i] as usize..self.bend_start[i + 1] as usize;
        self.bend_items[range].iter().map(|&item| BendCorner {
            e: (item >> 2) as usize,
            k: (item & 3) as usize,
        })
    }
}

/// Counting sort of `(slot, item)` pairs into `start` (slots + 1 offsets) and `items`, each
/// slot's items in the order given.
fn fill(
    start: &mut Vec<u32>,
    items: &mut Vec<u32>,
    slots: usize,
    pairs: impl Iterator<Item = (u32, u32)> + Clone,
) {
    start.clear();
    start.resize(slots + 1, 0);
    for (slot, _) in pairs.clone() {
        start[slot as usize + 1] += 1;
    }
    for i in 0..slots {
        start[i + 1] += start[i];
    }
    items.clear();
    items.resize(start[slots] as usize, 0);
    let mut next: Vec<u32> = start[..slots].to_vec();
    for (slot, item) in pairs {
        let at = &mut next[slot as usize];
        items[*at as usize] = item;
        *at += 1;
    }
}

/// Runs `per_item(i, &mut out[i])` for every index of `out` (vertex slots, springs, bending
/// elements): in parallel over fixed chunks of [`CHUNK`] when `parallel`, else in order. Each
/// item is computed alone, so the values are the same either way.
pub fn for_each_indexed<T: Send>(
    out: &mut [T],
    parallel: bool,
    per_item: impl Fn(usize, &mut T) + Sync,
) {
    if parallel {
        out.par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(c, chunk)| {
                for (k, o) in chunk.iter_mut().enumerate() {
                    per_item(c * CHUNK + k, o);
                }
            });
    } else {
        for (i, o) in out.iter_mut().enumerate() {
            per_item(i, o);
        }
    }
}

/// The elements at each slot plus reusable per-element buffers, to add per-element terms (the
/// force kernels') to per-slot sums in parallel: each element's terms computed once, then each
/// slot gathers those of its elements in element order, as the serial sweep adds them. The
/// buffers sit behind locks because forces are evaluated through `&self`; a clone gets empty
/// buffers (scratch, not state).
#[derive(Debug, Default)]
pub struct Gather {
    incidence: Incidence,
    /// The number of slots `incidence` lists; 0 when below [`PARALLEL_MIN_SLOTS`] (serial).
    slots: usize,
    spring_terms: Mutex<Vec<Vec3>>,
    bend_terms: Mutex<Vec<[Vec3; 4]>>,
}

impl Clone for Gather {
    fn clone(&self) -> Self {
        Gather {
            incidence: self.incidence.clone(),
            slots: self.slots,
            ..Gather::default()
        }
    }
}

impl Gather {
    /// Lists the elements of a model of `slots` vertex slots when it is large enough to gather
    /// in parallel; otherwise forgets any list (the sweeps stay serial).
    pub fn rebuild(&mut self, slots: usize, springs: &Springs, bends: &Bends) {
        if slots >= PARALLEL_MIN_SLOTS {
            self.incidence.rebuild(slots, springs, bends);
            self.slots = slots;
        } else {
            self.incidence = Incidence::default();
            self.slots = 0;
        }
    }

    /// True when sums over `slots` slots are gathered in parallel: the lists are for that many
    /// and there is more than one thread (on one, the serial sweep is the cheaper way to the
    /// same sums).
    pub fn covers(&self, slots: usize) -> bool {
        self.slots == slots && parallel_for(slots)
    }

    /// `f[a] += t_j`, `f[b] -= t_j` for every spring `j` with a term `t_j = term(j)` (`None`:
    /// none), gathered per slot in parallel. Requires [`Gather::covers`]`(f.len())`.
    pub fn add_spring_terms(&self, f: &mut [Vec3], term: impl Fn(usize) -> Option<Vec3> + Sync) {
        let mut terms = self.spring_terms.lock().unwrap_or_else(|e| e.into_inner());
        let count = self.incidence.spring_items.len() / 2;
        terms.resize(count, Vec3::zeros());
        for_each_indexed(&mut terms, true, |j, t| {
            *t = term(j).unwrap_or_else(Vec3::zeros)
        });
        let terms = &*terms;
        for_each_indexed(f, true, |i, fi| {
            for end in self.incidence.springs_at(i) {
                if end.second {
                    *fi -= terms[end.j];
                } else {
                    *fi += terms[end.j];
                }
            }
        });
    }

    /// `f[ids_e[k]] += t_e[k]` for every bending element `e` with terms `t_e = term(e)` (`None`:
    /// none), gathered per slot in parallel. Requires [`Gather::covers`]`(f.len())`.
    pub fn add_bend_terms(&self, f: &mut [Vec3], term: impl Fn(usize) -> Option<[Vec3; 4]> + Sync) {
        let mut terms = self.bend_terms.lock().unwrap_or_else(|e| e.into_inner());
        let count = self.incidence.bend_items.len() / 4;
        terms.resize(count, [Vec3::zeros(); 4]);
        for_each_indexed(&mut terms, true, |e, t| {
            *t = term(e).unwrap_or([Vec3::zeros(); 4])
        });
        let terms = &*terms;
        for_each_indexed(f, true, |i, fi| {
            for c in self.incidence.bends_at(i) {
                *fi += terms[c.e][c.k];
            }
        });
    }
}

#[cfg(test)]
#[path = "incidence_tests.rs"]
mod tests;
