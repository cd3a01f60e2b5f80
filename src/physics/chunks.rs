//! The elements split by vertex windows, so a sweep over them (the forces; the implicit system's
//! build and product) runs on every thread of the pool and gives the same sums, bit for bit,
//! whatever the number of threads.
//!
//! Chunk `t` holds the springs and bending elements whose key (a spring's smaller slot, a bending
//! element's shared-edge smaller slot: the order the element arrays are sorted in) lies in slots
//! `[t W, (t + 1) W)`; its window is the range of slots they touch. The width `W` is at least
//! twice the widest element's slot span, so the windows of chunks `t` and `t + 2` never meet: the
//! even chunks run at once, each adding into its own window, then the odd ones. Every vertex thus
//! receives its chunks' sums in one fixed order, and one thread makes the same sums one chunk
//! after the other. With fewer than four chunks holding elements (or unsorted elements) there
//! are no chunks: the mesh is swept in one piece.

use super::elements::{Bends, Springs};
use crate::math::Vec3;
use std::ops::Range;

/// Narrowest chunk (vertex slots): a chunk's work must outweigh handing it to another thread.
const MIN_WIDTH: usize = 512;

/// Fewest chunks worth a parallel sweep: on 3 chunks (33x33) two threads were measured 18 %
/// slower than one at RK4's integrate stage, on 9 (65x65) 15 % faster (docs/performance.md).
const MIN_CHUNKS: usize = 4;

/// One chunk: its elements and the slots they touch.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Chunk {
    /// Indices into the spring arrays.
    pub springs: Range<usize>,
    /// Indices into the bending elements.
    pub bends: Range<usize>,
    /// The vertex slots the chunk's elements touch.
    pub window: Range<usize>,
}

/// The entries of the vertex slots `first..first + values.len()` of a per-slot array (forces by
/// default): a sweep of a chunk adds to them and touches no other slot.
pub(super) struct Window<'a, T = Vec3> {
    pub values: &'a mut [T],
    pub first: usize,
}

impl<'a, T> Window<'a, T> {
    /// Every slot of `values` (slots from 0).
    pub fn whole(values: &'a mut [T]) -> Self {
        Window { values, first: 0 }
    }

    /// The same window, borrowed again (for a second sweep over it).
    pub fn reborrow(&mut self) -> Window<'_, T> {
        Window {
            values: &mut *self.values,
            first: self.first,
        }
    }
}

/// Which of a chunk's ranges indexes an array: its springs or its bending elements (an array
/// by slots is a [`Window`]).
#[derive(Clone, Copy, Debug)]
pub(super) enum Indexed {
    Springs,
    Bends,
}

impl Indexed {
    fn range(self, chunk: &Chunk) -> &Range<usize> {
        match self {
            Indexed::Springs => &chunk.springs,
            Indexed::Bends => &chunk.bends,
        }
    }
}

/// The part `first..first + values.len()` of an array indexed by springs or bending elements,
/// for the chunks whose ranges lie in it.
pub(super) struct Part<'a, T> {
    pub values: &'a mut [T],
    pub first: usize,
    pub by: Indexed,
}

impl<'a, T> Part<'a, T> {
    /// The whole of `values`, indexed `by`.
    pub fn whole(values: &'a mut [T], by: Indexed) -> Self {
        Part {
            values,
            first: 0,
            by,
        }
    }
}

/// What a chunked sweep hands each chunk: parts of arrays that split where a chunk's ranges
/// start (the chunks' ranges are in order and the windows of chunks `t` and `t + 2` apart).
pub(super) trait Parts: Send + Sized {
    /// The parts before chunk `at`'s ranges and from them on; `at`'s ranges start inside the
    /// parts (panics otherwise).
    fn split_before(self, at: &Chunk) -> (Self, Self);
    /// Only chunk `chunk`'s ranges, which lie inside the parts (panics otherwise).
    fn narrow(self, chunk: &Chunk) -> Self;
}

impl<T: Send> Parts for Window<'_, T> {
    fn split_before(self, at: &Chunk) -> (Self, Self) {
        let [(left, first), (right, split)] = cut(self.values, self.first, at.window.start);
        (
            Window {
                values: left,
                first,
            },
            Window {
                values: right,
                first: split,
            },
        )
    }

    fn narrow(self, chunk: &Chunk) -> Self {
        let w = &chunk.window;
        Window {
            values: keep(self.values, self.first, w),
            first: w.start,
        }
    }
}

impl<T: Send> Parts for Part<'_, T> {
    fn split_before(self, at: &Chunk) -> (Self, Self) {
        let by = self.by;
        let [(left, first), (right, split)] = cut(self.values, self.first, by.range(at).start);
        let left = Part {
            values: left,
            first,
            by,
        };
        let right = Part {
            values: right,
            first: split,
            by,
        };
        (left, right)
    }

    fn narrow(self, chunk: &Chunk) -> Self {
        let r = self.by.range(chunk);
        Part {
            values: keep(self.values, self.first, r),
            first: r.start,
            by: self.by,
        }
    }
}

/// The entries of `values` (indices from `first`) before index `at` and from it on, each with
/// its first index.
fn cut<T>(values: &mut [T], first: usize, at: usize) -> [(&mut [T], usize); 2] {
    let (left, right) = values.split_at_mut(at - first);
    [(left, first), (right, at)]
}

/// The entries `range` of `values` (indices from `first`).
fn keep<'a, T>(values: &'a mut [T], first: usize, range: &Range<usize>) -> &'a mut [T] {
    &mut values[range.start - first..range.end - first]
}

/// Parts a sweep may not use (`None`: no array, as the bending terms when bending is off).
impl<P: Parts> Parts for Option<P> {
    fn split_before(self, at: &Chunk) -> (Self, Self) {
        match self {
            Some(parts) => {
                let (left, right) = parts.split_before(at);
                (Some(left), Some(right))
            }
            None => (None, None),
        }
    }

    fn narrow(self, chunk: &Chunk) -> Self {
        self.map(|parts| parts.narrow(chunk))
    }
}

impl<A: Parts, B: Parts> Parts for (A, B) {
    fn split_before(self, at: &Chunk) -> (Self, Self) {
        let (a, b) = (self.0.split_before(at), self.1.split_before(at));
        ((a.0, b.0), (a.1, b.1))
    }

    fn narrow(self, chunk: &Chunk) -> Self {
        (self.0.narrow(chunk), self.1.narrow(chunk))
    }
}

/// The two phases of a chunked sweep: the even chunks, then the odd ones. A sweep runs both, in
/// the order of [`Phase::BOTH`], each with its parts made afresh (a phase takes them by value).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Phase {
    Even,
    Odd,
}

impl Phase {
    /// Both phases, in the order a sweep runs them.
    pub const BOTH: [Phase; 2] = [Phase::Even, Phase::Odd];
}

/// The chunks of a mesh's elements; empty when the mesh is swept in one piece.
#[derive(Clone, Debug, Default)]
pub(super) struct Chunks {
    parts: Vec<Chunk>,
}

impl Chunks {
    /// The chunks of these elements over `slots` vertex slots.
    pub fn build(springs: &Springs, bends: &Bends, slots: usize) -> Self {
        let spring_key = |j: usize| springs.a[j] as usize;
        let bend_key = |j: usize| bends.v[j][2].min(bends.v[j][3]) as usize;
        let sorted = (1..springs.len()).all(|j| spring_key(j - 1) <= spring_key(j))
            && (1..bends.len()).all(|j| bend_key(j - 1) <= bend_key(j));
        let spring_span = (0..springs.len()).map(|j| springs.a[j].abs_diff(springs.b[j]));
        let bend_span = bends
            .v
            .iter()
            .map(|e| e.iter().max().unwrap() - e.iter().min().unwrap());
        let span = spring_span.chain(bend_span).max().unwrap_or(0) as usize;
        let width = MIN_WIDTH.max(2 * span);
        let count = slots.div_ceil(width);
        if !sorted || count < MIN_CHUNKS {
            return Chunks::default();
        }
        let (mut next_spring, mut next_bend) = (0, 0);
        let parts = (0..count)
            .map(|t| {
                let end = (t + 1) * width;
                let s = next_spring
                    ..next_spring
                        + (next_spring..springs.len())
                            .take_while(|&j| spring_key(j) < end)
                            .count();
                let b = next_bend
                    ..next_bend
                        + (next_bend..bends.len())
                            .take_while(|&j| bend_key(j) < end)
                            .count();
                (next_spring, next_bend) = (s.end, b.end);
                let touched = s
                    .clone()
                    .flat_map(|j| [springs.a[j], springs.b[j]])
                    .chain(b.clone().flat_map(|j| bends.v[j]));
                let (lo, hi) = touched.fold((usize::MAX, 0), |(lo, hi), i| {
                    (lo.min(i as usize), hi.max(i as usize + 1))
                });
                let window = if lo < hi {
                    lo..hi
                } else {
                    (t * width).min(slots)..(t * width).min(slots)
                };
                Chunk {
                    springs: s,
                    bends: b,
                    window,
                }
            })
            .collect::<Vec<_>>();
        // A model over a few elements of a large mesh (`ForceModel::around`) is swept in one piece.
        let busy = parts
            .iter()
            .filter(|c| !c.springs.is_empty() || !c.bends.is_empty());
        if busy.count() < MIN_CHUNKS {
            return Chunks::default();
        }
        let apart = (2..parts.len()).all(|t| parts[t - 2].window.end <= parts[t].window.start);
        debug_assert!(apart, "chunk windows t and t + 2 overlap");
        if apart {
            Chunks { parts }
        } else {
            Chunks::default()
        }
    }

    /// The chunks, in slot order.
    #[cfg(test)]
    pub fn parts(&self) -> &[Chunk] {
        &self.parts
    }

    /// True when the mesh is swept in one piece.
    pub fn is_empty(&self) -> bool {
        self.parts.is_empty()
    }

    /// Runs `work` on the chunks of `phase` with their parts of `parts` (arrays whose ranges
    /// cover every chunk's), on the threads of the current rayon pool.
    pub fn sweep_phase<P: Parts>(
        &self,
        phase: Phase,
        parts: P,
        work: &(impl Fn(&Chunk, P) + Sync),
    ) {
        let parallel = crate::parallel::pool_can_help();
        let phase = phase as usize;
        let count = (self.parts.len() + 1 - phase) / 2;
        if count > 0 {
            self.run(phase, 0..count, parts, work, parallel);
        }
    }

    /// Chunks `phase + 2 k` for `k` in `ks`, whose ranges lie in `parts`.
    fn run<P: Parts>(
        &self,
        phase: usize,
        ks: Range<usize>,
        parts: P,
        work: &(impl Fn(&Chunk, P) + Sync),
        parallel: bool,
    ) {
        if ks.len() == 1 {
            let chunk = &self.parts[phase + 2 * ks.start];
            work(chunk, parts.narrow(chunk));
            return;
        }
        let (start, mid, end) = (ks.start, ks.start + ks.len() / 2, ks.end);
        let (left, right) = parts.split_before(&self.parts[phase + 2 * mid]);
        if parallel {
            rayon::join(
                || self.run(phase, start..mid, left, work, true),
                || self.run(phase, mid..end, right, work, true),
            );
        } else {
            self.run(phase, start..mid, left, work, false);
            self.run(phase, mid..end, right, work, false);
        }
    }
}
