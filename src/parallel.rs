//! When work may be split over the rayon pool.
//!
//! The command runs on a thread of the global pool (`main.rs`); a study's runs and a reference's
//! two runs go on threads of their own while that pool thread waits for them. Work one of those
//! threads hands to the pool is taken by another pool thread: with one pool thread there is none,
//! and the work would wait forever (a study with `--jobs 2` on two cores gets a pool of one).
//! Every parallel split asks [`pool_can_help`] first and runs in line when it says no; the
//! results never depend on it.

/// True when the current rayon pool has more than one thread, so work handed to it from any
/// thread is taken up.
pub fn pool_can_help() -> bool {
    rayon::current_num_threads() > 1
}
