//! The parallel pool of a study: `jobs` worker threads take items from a shared list, largest
//! first, each with its own progress bar; results keep the list's order.

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

/// Progress display of a study: one bar per running item, finished lines printed above them.
pub struct Progress {
    multi: MultiProgress,
    shown: bool,
}

impl Progress {
    /// Bars on stderr when `shown` (the caller checks it is a terminal), hidden otherwise.
    pub fn new(shown: bool) -> Progress {
        let target = if shown {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        Progress {
            multi: MultiProgress::with_draw_target(target),
            shown,
        }
    }

    /// The bars' owner (to add bars for other runs, such as the reference).
    pub fn multi(&self) -> &MultiProgress {
        &self.multi
    }

    /// Prints a line above the bars, or on stderr when the bars are hidden.
    pub fn println(&self, line: &str) {
        if self.shown {
            let _ = self.multi.println(line);
        } else {
            crate::note!("{line}");
        }
    }
}

/// Runs `work(item, bar)` for every item on `jobs` threads (at least one), starting with the
/// items of largest `size` (shortest makespan); each call gets a fresh bar labelled by
/// `label(item)`, cleared when it returns. Returns the results in the items' order; stops taking
/// new items after the first error and returns it, or once `stop` is set (Ctrl-C): the items
/// begun by then finish, the others have no result.
pub fn run_all<T: Sync, R: Send, E: Send>(
    items: &[T],
    jobs: usize,
    stop: Option<&AtomicBool>,
    progress: &Progress,
    size: impl Fn(&T) -> usize,
    label: impl Fn(&T) -> String + Sync,
    work: impl Fn(&T, ProgressBar) -> Result<R, E> + Sync,
) -> Result<Vec<R>, E> {
    let mut order: Vec<usize> = (0..items.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(size(&items[i])));
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<R>>> = Mutex::new((0..items.len()).map(|_| None).collect());
    let first_error: Mutex<Option<E>> = Mutex::new(None);
    let lock_poisoned = "a worker panicked while holding the pool's lock";
    std::thread::scope(|s| {
        for _ in 0..jobs.max(1).min(items.len()) {
            s.spawn(|| loop {
                let stopped = stop.is_some_and(|s| s.load(Ordering::SeqCst));
                if stopped || first_error.lock().expect(lock_poisoned).is_some() {
                    break;
                }
                let k = next.fetch_add(1, Ordering::SeqCst);
                let Some(&i) = order.get(k) else { break };
                let bar = crate::sim::labelled_bar(progress.multi(), &label(&items[i]));
                let result = work(&items[i], bar.clone());
                bar.finish_and_clear();
                match result {
                    Ok(r) => results.lock().expect(lock_poisoned)[i] = Some(r),
                    Err(e) => {
                        first_error.lock().expect(lock_poisoned).get_or_insert(e);
                    }
                }
            });
        }
    });
    if let Some(e) = first_error.into_inner().expect(lock_poisoned) {
        return Err(e);
    }
    Ok(results
        .into_inner()
        .expect(lock_poisoned)
        .into_iter()
        .flatten()
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_keep_the_list_order_and_the_first_error_stops_the_pool() {
        let progress = Progress::new(false);
        let items: Vec<usize> = (0..20).collect();
        let out: Result<Vec<usize>, ()> = run_all(
            &items,
            3,
            None,
            &progress,
            |&i| i,
            |i| i.to_string(),
            |&i, _| Ok(i * 2),
        );
        assert_eq!(out.unwrap(), (0..20).map(|i| i * 2).collect::<Vec<_>>());
        let out: Result<Vec<usize>, usize> = run_all(
            &items,
            2,
            None,
            &progress,
            |_| 0,
            |i| i.to_string(),
            |&i, _| if i == 5 { Err(i) } else { Ok(i) },
        );
        assert_eq!(out.unwrap_err(), 5);
    }

    /// After an interrupt no item starts: a study's runs not begun are not run.
    #[test]
    fn no_item_starts_once_stop_is_set() {
        let progress = Progress::new(false);
        let items: Vec<usize> = (0..20).collect();
        let stop = AtomicBool::new(false);
        let out: Result<Vec<usize>, ()> = run_all(
            &items,
            1,
            Some(&stop),
            &progress,
            |_| 0,
            |i| i.to_string(),
            |&i, _| {
                if i == 3 {
                    stop.store(true, Ordering::SeqCst);
                }
                Ok(i)
            },
        );
        assert_eq!(out.unwrap(), [0, 1, 2, 3]);
    }
}
