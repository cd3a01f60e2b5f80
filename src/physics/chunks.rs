//! The elements split by vertex windows, so a force sweep runs on every thread of the pool and
//! gives the same forces, bit for bit, whatever the number of threads.
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
use super::kernels::Window;
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

    /// Runs `work` on every chunk with the forces of its window, the even chunks then the odd
    /// ones, on the threads of the current rayon pool; `forces` holds one entry per slot.
    pub fn sweep(&self, forces: &mut [Vec3], work: &(impl Fn(&Chunk, Window) + Sync)) {
        let parallel = crate::parallel::pool_can_help();
        for phase in 0..2 {
            let count = (self.parts.len() + 1 - phase) / 2;
            self.run(phase, 0..count, forces, 0, work, parallel);
        }
    }

    /// Chunks `phase + 2 k` for `k` in `ks`, whose windows lie in `forces` (slots from `first`).
    fn run(
        &self,
        phase: usize,
        ks: Range<usize>,
        forces: &mut [Vec3],
        first: usize,
        work: &(impl Fn(&Chunk, Window) + Sync),
        parallel: bool,
    ) {
        if ks.len() == 1 {
            let chunk = &self.parts[phase + 2 * ks.start];
            let w = &chunk.window;
            let window = Window {
                forces: &mut forces[w.start - first..w.end - first],
                first: w.start,
            };
            work(chunk, window);
            return;
        }
        let (start, mid, end) = (ks.start, ks.start + ks.len() / 2, ks.end);
        let split = self.parts[phase + 2 * mid].window.start;
        let (left, right) = forces.split_at_mut(split - first);
        if parallel {
            rayon::join(
                || self.run(phase, start..mid, left, first, work, true),
                || self.run(phase, mid..end, right, split, work, true),
            );
        } else {
            self.run(phase, start..mid, left, first, work, false);
            self.run(phase, mid..end, right, split, work, false);
        }
    }
}
