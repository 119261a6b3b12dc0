//! Tangent patterns built recently, for solves of meshes with the same
//! topology.

use std::sync::{Arc, Mutex};

use faer::sparse::Pair;

use super::super::tangent_factor::TangentPattern;

/// How many patterns a cache keeps: a search and a verification mesh per
/// running job, for a few jobs.
const CAPACITY: usize = 8;

/// Tangent patterns (ordering, permuted pattern, symbolic factorisation)
/// with the triplet positions each was built from, most recent last.
/// Candidates of a design search share their mesh's topology (graded zones
/// snap to a coarse grid), so most solves find theirs here instead of
/// redoing the ordering and the symbolic factorisation (13 % of a cold 2 mm
/// Hilbert solve). Keyed by the full triplet list, so a different mesh never
/// reuses a wrong pattern. Shared between threads; whoever runs a sequence
/// of solves owns one and passes it in.
#[derive(Default)]
pub struct PatternCache {
    recent: Mutex<Vec<Cached>>,
}

/// A pattern and the triplet positions it was built from.
type Cached = (Vec<Pair<usize, usize>>, Arc<TangentPattern>);

impl PatternCache {
    /// The pattern for `n` unknowns and these triplet positions: the cached
    /// one (moved to the most recent place), or a new one, stored.
    pub fn get_or_build(
        &self,
        n: usize,
        pairs: Vec<Pair<usize, usize>>,
    ) -> Result<Arc<TangentPattern>, String> {
        if let Some(pattern) = self.recent(&pairs) {
            return Ok(pattern);
        }
        let pattern = Arc::new(TangentPattern::new(n, &pairs)?);
        let mut recent = self.recent.lock().unwrap_or_else(|e| e.into_inner());
        if recent.len() == CAPACITY {
            recent.remove(0);
        }
        recent.push((pairs, Arc::clone(&pattern)));
        Ok(pattern)
    }

    /// Empties the cache, so that the next solve of every mesh pays its full
    /// setup (for benchmarks of a first solve).
    pub fn clear(&self) {
        self.recent
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
    }

    /// How many patterns the cache holds.
    pub fn len(&self) -> usize {
        self.recent.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn recent(&self, pairs: &[Pair<usize, usize>]) -> Option<Arc<TangentPattern>> {
        let mut recent = self.recent.lock().unwrap_or_else(|e| e.into_inner());
        let index = recent.iter().position(|(p, _)| p.as_slice() == pairs)?;
        let entry = recent.remove(index);
        let pattern = Arc::clone(&entry.1);
        recent.push(entry);
        Some(pattern)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diagonal(n: usize) -> Vec<Pair<usize, usize>> {
        (0..n).map(|i| Pair::new(i, i)).collect()
    }

    #[test]
    fn the_same_pattern_is_reused_and_the_oldest_goes_first() {
        let cache = PatternCache::default();
        let first = cache.get_or_build(2, diagonal(2)).unwrap();
        let again = cache.get_or_build(2, diagonal(2)).unwrap();
        assert!(Arc::ptr_eq(&first, &again));
        for n in 3..3 + CAPACITY {
            cache.get_or_build(n, diagonal(n)).unwrap();
        }
        assert_eq!(cache.len(), CAPACITY);
        // The 2 × 2 pattern was the oldest: it was dropped.
        let rebuilt = cache.get_or_build(2, diagonal(2)).unwrap();
        assert!(!Arc::ptr_eq(&first, &rebuilt));
        cache.clear();
        assert!(cache.is_empty());
    }
}
