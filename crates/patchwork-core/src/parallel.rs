//! A generation of CMA-ES candidates, or the columns of a finite-difference
//! Jacobian, evaluated across a few scoped threads.

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
            scope.spawn(move || {
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
}
