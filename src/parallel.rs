//! When work may be split over the rayon pool.
//!
//! The command runs on a thread of the global pool (`main.rs`); a study's runs and a reference's
//! two runs go on threads of their own while that pool thread waits for them. Work one of those
//! threads hands to the pool is taken by another pool thread: with one pool thread there is none,
//! and the work would wait forever (a study with `--jobs 2` on two cores gets a pool of one).
//! Every parallel split asks [`pool_can_help`] first and runs in line when it says no; the
//! results never depend on it. [`with_partner_awake`] keeps another thread taking work through
//! a phase of many short splits.

use std::sync::atomic::{AtomicBool, Ordering};

/// True when the current rayon pool has more than one thread, so work handed to it from any
/// thread is taken up.
pub fn pool_can_help() -> bool {
    rayon::current_num_threads() > 1
}

/// True on a thread of a pool with another thread to share its work: what a split that waits
/// for its halves needs to gain anything (from a thread outside the pool, a study's run, a join
/// hands both halves to the pool).
pub fn pool_thread_can_share() -> bool {
    rayon::current_thread_index().is_some() && pool_can_help()
}

/// Sets its flag when dropped: the phase's end, by return or by unwinding (so a panicking phase
/// never leaves its partner spinning).
struct EndOfPhase<'a>(&'a AtomicBool);

impl Drop for EndOfPhase<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Release);
    }
}

/// Runs `phase` on the current thread while another thread of its pool takes the pool's work as
/// soon as it appears, until `phase` returns: for a phase of many short two-way splits (a thread
/// of rayon's pool that finds no work goes to sleep, and waking it for the next `rayon::join`
/// took about 40 us here, a good part of what a conjugate-gradient solve's triangular solves
/// share). Only where [`pool_thread_can_share`]; elsewhere it just runs `phase`. The price is
/// a core kept busy for the phase; what `phase` computes does not depend on it. Between looks
/// for work the partner yields its core to the operating system rather than spinning: as fast
/// on an idle machine, and on one where another process holds a core a 65x65 implicit run took
/// 2.85-2.95 s instead of 3.89-3.95 s (docs/performance.md, "The fastest peer").
///
/// The partner is a task queued before the phase's first split; rayon's thieves take a queue's
/// oldest task first, so the partner is taken before any split of the phase, and the phase never
/// runs it itself. So `phase` must not call `rayon::yield_now` or `rayon::yield_local` (which
/// could run the queued partner on this thread, spinning until a phase that cannot end).
pub fn with_partner_awake<R>(phase: impl FnOnce() -> R) -> R {
    if !pool_thread_can_share() {
        return phase();
    }
    let done = AtomicBool::new(false);
    rayon::in_place_scope(|scope| {
        scope.spawn(|_| {
            while !done.load(Ordering::Acquire) {
                if rayon::yield_now() != Some(rayon::Yield::Executed) {
                    std::thread::yield_now();
                }
            }
        });
        let _end = EndOfPhase(&done);
        phase()
    })
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::in_pool;

    /// Joins inside the phase run, the phase's value comes back, and the partners stop: on a
    /// pool of two threads and of one.
    #[test]
    fn a_phase_runs_its_joins_and_ends() {
        for threads in [1, 2] {
            let sum = in_pool(threads, || {
                with_partner_awake(|| {
                    (0..100)
                        .map(|k| {
                            let (a, b) = rayon::join(|| k, || 2 * k);
                            a + b
                        })
                        .sum::<i32>()
                })
            });
            assert_eq!(sum, 3 * 4950);
        }
    }

    /// A phase that panics ends its partners too: the panic reaches the caller, no hang.
    #[test]
    fn a_panicking_phase_ends_its_partners() {
        let caught = in_pool(2, || {
            std::panic::catch_unwind(|| with_partner_awake(|| -> i32 { panic!("in the phase") }))
        });
        assert!(caught.is_err());
    }
}
