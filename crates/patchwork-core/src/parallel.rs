//! A generation of CMA-ES candidates, or the columns of a finite-difference
//! Jacobian, evaluated across a few scoped threads, each taking the next
//! item as it finishes one.
//!
//! Parallel loops do not nest: work already on one of [`map_in_threads`]'s
//! threads runs any inner loop (a solve's assembly) on that thread alone,
//! so a thread count is never multiplied by another.

use std::cell::Cell;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

thread_local! {
    /// Whether this thread is one of a parallel loop's.
    static IN_PARALLEL_LOOP: Cell<bool> = const { Cell::new(false) };
}

/// The cores this process may use (1 where the system cannot say): the
/// default thread count of every command, job and calibration.
pub fn available_cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Whether the caller runs on a thread of a parallel loop (an inner loop
/// should then not spawn threads of its own).
pub(crate) fn nested() -> bool {
    IN_PARALLEL_LOOP.with(Cell::get)
}

/// Runs `work` on a scoped thread marked as a parallel loop's.
pub(crate) fn spawn_marked<'scope, T: Send + 'scope>(
    scope: &'scope std::thread::Scope<'scope, '_>,
    work: impl FnOnce() -> T + Send + 'scope,
) -> std::thread::ScopedJoinHandle<'scope, T> {
    scope.spawn(move || {
        IN_PARALLEL_LOOP.with(|flag| flag.set(true));
        work()
    })
}

/// `0..count` in up to `threads` contiguous ranges of near-equal length
/// (at least one range, empty when `count` is 0).
pub(crate) fn ranges(count: usize, threads: usize) -> Vec<Range<usize>> {
    let size = count.div_ceil(threads.clamp(1, count.max(1))).max(1);
    let mut ranges: Vec<Range<usize>> = (0..count)
        .step_by(size)
        .map(|start| start..(start + size).min(count))
        .collect();
    if ranges.is_empty() {
        ranges.push(0..0);
    }
    ranges
}

/// `work` of every job, in order, each job on its own scoped thread marked
/// as a parallel loop's; a job's panic resumes on the caller.
pub(crate) fn run_marked<J: Send, T: Send>(jobs: Vec<J>, work: &(dyn Fn(J) -> T + Sync)) -> Vec<T> {
    std::thread::scope(|scope| {
        let handles: Vec<_> = (jobs.into_iter())
            .map(|job| spawn_marked(scope, move || work(job)))
            .collect();
        (handles.into_iter())
            .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    })
}

/// `f` of every item, in order, on up to `threads` scoped threads. Each
/// thread takes the next item left as it finishes one, so items of unequal
/// cost (the spread's solves of a patch moved round the tube take 7–15
/// Newton iterations, of a changed width 2–4) keep every thread busy to the
/// end, where contiguous chunks left one thread idle while the other
/// finished its costlier share. Where `f` is a
/// function of its item alone — every caller's, but the search's optional
/// warm starts (`Tuning::warm_starts`, from the best design any thread has
/// found so far) — which thread runs an item, and when, changes the wall
/// time, never the results.
pub(crate) fn map_in_threads<U: Sync, T: Send>(
    items: &[U],
    threads: usize,
    f: &(dyn Fn(&U) -> T + Sync),
) -> Vec<T> {
    let threads = threads.clamp(1, items.len().max(1));
    if threads == 1 {
        return items.iter().map(f).collect();
    }
    let next = AtomicUsize::new(0);
    let taken = run_marked(vec![(); threads], &|()| {
        let mut mapped = Vec::new();
        loop {
            let k = next.fetch_add(1, Ordering::Relaxed);
            let Some(item) = items.get(k) else {
                return mapped;
            };
            mapped.push((k, f(item)));
        }
    });
    // Each thread's results are in its items' order; merged by index.
    let mut results: Vec<(usize, T)> = taken.into_iter().flatten().collect();
    results.sort_unstable_by_key(|&(k, _)| k);
    results.into_iter().map(|(_, result)| result).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_keep_the_items_order_for_any_thread_count() {
        let items: Vec<u32> = (0..11).collect();
        for threads in [0, 1, 2, 3, 11, 40] {
            let squares = map_in_threads(&items, threads, &|i| i * i);
            assert_eq!(squares, items.iter().map(|i| i * i).collect::<Vec<_>>());
        }
    }

    /// The first item waits for all the others to be done: on two threads
    /// the second thread takes them all while the first is busy (contiguous
    /// chunks would have left items 1–5 behind the first, on its thread).
    #[test]
    fn an_idle_thread_takes_the_items_left() {
        let items: Vec<usize> = (0..11).collect();
        let done = AtomicUsize::new(0);
        let waited = map_in_threads(&items, 2, &|&i| {
            if i > 0 {
                done.fetch_add(1, Ordering::SeqCst);
                return true;
            }
            let started = std::time::Instant::now();
            while done.load(Ordering::SeqCst) < items.len() - 1 {
                if started.elapsed() > std::time::Duration::from_secs(20) {
                    return false;
                }
                std::thread::yield_now();
            }
            true
        });
        assert!(waited.iter().all(|&w| w), "{waited:?}");
    }

    #[test]
    fn ranges_cover_the_count_in_order() {
        for (count, threads) in [(0, 2), (1, 3), (7, 1), (7, 2), (7, 3), (10, 4), (3, 40)] {
            let ranges = ranges(count, threads);
            assert!(
                ranges.len() <= threads.max(1),
                "{count} in {threads}: {ranges:?}"
            );
            let joined: Vec<usize> = ranges.iter().cloned().flatten().collect();
            assert_eq!(joined, (0..count).collect::<Vec<_>>());
        }
    }

    #[test]
    fn only_the_threads_of_a_parallel_loop_are_marked_nested() {
        assert!(!nested());
        assert_eq!(map_in_threads(&[1, 2], 1, &|_| nested()), [false, false]);
        assert_eq!(map_in_threads(&[1, 2], 2, &|_| nested()), [true, true]);
        assert!(!nested());
    }
}
