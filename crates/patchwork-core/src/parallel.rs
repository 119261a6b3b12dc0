//! A generation of CMA-ES candidates, or the columns of a finite-difference
//! Jacobian, evaluated across a few scoped threads.
//!
//! Parallel loops do not nest: work already on one of [`map_in_threads`]'s
//! threads runs any inner loop (a solve's assembly) on that thread alone,
//! so a thread count is never multiplied by another.

use std::cell::Cell;

thread_local! {
    /// Whether this thread is one of a parallel loop's.
    static IN_PARALLEL_LOOP: Cell<bool> = const { Cell::new(false) };
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

/// `f` of every item, in order, the items split into up to `threads`
/// contiguous chunks, one scoped thread each.
pub(crate) fn map_in_threads<U: Sync, T: Send>(
    items: &[U],
    threads: usize,
    f: &(dyn Fn(&U) -> T + Sync),
) -> Vec<T> {
    let threads = threads.clamp(1, items.len().max(1));
    if threads == 1 {
        return items.iter().map(f).collect();
    }
    let chunk = items.len().div_ceil(threads);
    let mut results: Vec<Option<T>> = items.iter().map(|_| None).collect();
    std::thread::scope(|scope| {
        for (slot, work) in results.chunks_mut(chunk).zip(items.chunks(chunk)) {
            spawn_marked(scope, move || {
                for (r, item) in slot.iter_mut().zip(work) {
                    *r = Some(f(item));
                }
            });
        }
    });
    results
        .into_iter()
        .map(|r| r.expect("every chunk's thread fills its slots"))
        .collect()
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
    fn only_the_threads_of_a_parallel_loop_are_marked_nested() {
        assert!(!nested());
        assert_eq!(map_in_threads(&[1, 2], 1, &|_| nested()), [false, false]);
        assert_eq!(map_in_threads(&[1, 2], 2, &|_| nested()), [true, true]);
        assert!(!nested());
    }
}
