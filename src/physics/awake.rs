//! Keeping the pool's other threads awake through a phase of many short parallel sections.
//!
//! A thread of rayon's pool that finds no work goes to sleep, and waking it for the next
//! `rayon::join` takes tens of microseconds (about 40 us measured on this machine), as long as a
//! good part of what the join shares: a conjugate-gradient solve hands each of its triangular
//! solves' halves to the other thread every 0.1-0.2 ms. Through such a phase every other thread
//! of the pool runs a task that keeps taking the pool's pending work (`rayon::yield_now`) until
//! the phase ends, so a join inside it is picked up at once. The price is the other cores kept
//! busy for the phase.

use std::sync::atomic::{AtomicBool, Ordering};

/// Sets its flag when dropped: the phase's end, by return or by unwinding (so a panicking phase
/// never leaves its partners spinning).
struct EndOfPhase<'a>(&'a AtomicBool);

impl Drop for EndOfPhase<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Release);
    }
}

/// Runs `phase` on the current thread while every other thread of the current pool takes the
/// pool's work as soon as it appears, until `phase` returns. On a pool of one thread it just
/// runs `phase`. What `phase` computes does not depend on it.
pub(crate) fn with_pool_awake<R>(phase: impl FnOnce() -> R) -> R {
    let others = rayon::current_num_threads().saturating_sub(1);
    if others == 0 {
        return phase();
    }
    let done = AtomicBool::new(false);
    rayon::in_place_scope(|scope| {
        for _ in 0..others {
            scope.spawn(|_| {
                while !done.load(Ordering::Acquire) {
                    if rayon::yield_now() != Some(rayon::Yield::Executed) {
                        std::hint::spin_loop();
                    }
                }
            });
        }
        let _end = EndOfPhase(&done);
        phase()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Joins inside the phase run, the phase's value comes back, and the partners stop: on a
    /// pool of two threads and of one.
    #[test]
    fn a_phase_runs_its_joins_and_ends() {
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let sum = pool.install(|| {
                with_pool_awake(|| {
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
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let caught = pool.install(|| {
            std::panic::catch_unwind(|| with_pool_awake(|| -> i32 { panic!("in the phase") }))
        });
        assert!(caught.is_err());
    }
}
