//! A generation of CMA-ES candidates, or the columns of a finite-difference
//! Jacobian, evaluated across a few scoped threads.
//!
//! Parallel loops do not nest: work already on one of [`map_in_threads`]'s
//! threads runs any inner loop (a solve's assembly) on that thread alone,
//! so a thread count is never multiplied by another.

use std::cell::Cell;
use std::ops::Range;

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

/// `f` of every item, in order, the items split into up to `threads`
/// contiguous chunks, one scoped thread each.
pub(crate) fn map_in_threads<U: Sync, T: Send>(
    items: &[U],
    threads: usize,
    f: &(dyn Fn(&U) -> T + Sync),
) -> Vec<T> {
    if threads.clamp(1, items.len().max(1)) == 1 {
        return items.iter().map(f).collect();
    }
    let chunks: Vec<&[U]> = (ranges(items.len(), threads).into_iter())
        .map(|range| &items[range])
        .collect();
    let mapped = run_marked(chunks, &|chunk| chunk.iter().map(f).collect::<Vec<T>>());
    mapped.into_iter().flatten().collect()
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
