//! A cache of evaluated designs: the converged simulations of recent cold
//! solves, keyed by the exact design and model, shared by the design runs of
//! whoever owns it (the service keeps one for all its jobs).
//!
//! A cold solve is deterministic, so a cached simulation is bit for bit the
//! one a new solve would return: a hit changes no result, only the time.
//! Warm-started solves are neither stored nor served (their result depends on
//! the start, to the solver's tolerance). Failed solves are not stored either
//! (a time limit depends on the machine's load).
//!
//! What it is for: a design job run again — a script's retry, a re-submitted
//! request, the same curve at a higher polish budget — repeats the whole
//! search exactly (same seed, same candidates) and finds every simulation
//! here. Within one run CMA-ES practically never proposes the same candidate
//! twice, so a single run gains nothing (measured in docs/studies.md).

use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard};

use crate::design::Design;
use crate::fe::newton::PatternCache;
use crate::fe::{SimulateError, SimulateOptions, Simulation, simulate_with};

/// Mesh nodes the cache may hold in all, about 110 bytes each in a
/// simulation: some 55 MB — 300 draft-search simulations (3 mm) or 20 of
/// the `fine` preset's 0.5 mm verification.
const NODE_BUDGET: usize = 500_000;

/// Converged cold solves, least recently used dropped first.
#[derive(Default)]
pub struct EvaluationCache {
    entries: Mutex<Entries>,
    hits: AtomicUsize,
    misses: AtomicUsize,
}

#[derive(Default)]
struct Entries {
    map: HashMap<Key, Entry>,
    nodes: usize,
    clock: u64,
}

struct Entry {
    simulation: Simulation,
    last_used: u64,
}

/// A design and a model, written out: `{:?}` prints every f64 in its
/// shortest round-trip form, so equal keys are equal values.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct Key(String);

impl Key {
    /// The thread count is left out: every count solves alike.
    fn new(design: &Design, options: &SimulateOptions) -> Key {
        let options = SimulateOptions {
            threads: 1,
            ..*options
        };
        Key(format!("{design:?}|{options:?}"))
    }
}

/// Hits and misses of a cache since it was made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CacheCounts {
    pub hits: usize,
    pub misses: usize,
}

impl EvaluationCache {
    /// `design` solved on `options` from the cold start, served from the
    /// cache when this exact design was solved on this exact model before;
    /// a new solve uses `patterns`.
    pub fn simulate(
        &self,
        design: &Design,
        options: &SimulateOptions,
        patterns: &PatternCache,
    ) -> Result<Simulation, SimulateError> {
        let key = Key::new(design, options);
        if let Some(simulation) = self.lookup(&key) {
            self.hits.fetch_add(1, Ordering::Relaxed);
            return Ok(simulation);
        }
        self.misses.fetch_add(1, Ordering::Relaxed);
        let simulation = simulate_with(design, options, None, patterns)?;
        self.store(key, &simulation);
        Ok(simulation)
    }

    pub fn counts(&self) -> CacheCounts {
        CacheCounts {
            hits: self.hits.load(Ordering::Relaxed),
            misses: self.misses.load(Ordering::Relaxed),
        }
    }

    /// Empties the cache (the counts stay).
    pub fn clear(&self) {
        *self.lock() = Entries::default();
    }

    fn lock(&self) -> MutexGuard<'_, Entries> {
        self.entries.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn lookup(&self, key: &Key) -> Option<Simulation> {
        let mut entries = self.lock();
        entries.clock += 1;
        let clock = entries.clock;
        let entry = entries.map.get_mut(key)?;
        entry.last_used = clock;
        Some(entry.simulation.clone())
    }

    fn store(&self, key: Key, simulation: &Simulation) {
        let size = simulation.mesh.nodes.len();
        if size > NODE_BUDGET {
            return;
        }
        let mut entries = self.lock();
        while entries.nodes + size > NODE_BUDGET {
            let Some(oldest) = entries
                .map
                .iter()
                .min_by_key(|(_, e)| e.last_used)
                .map(|(k, _)| k.clone())
            else {
                break;
            };
            if let Some(e) = entries.map.remove(&oldest) {
                entries.nodes -= e.simulation.mesh.nodes.len();
            }
        }
        entries.clock += 1;
        let entry = Entry {
            simulation: simulation.clone(),
            last_used: entries.clock,
        };
        if let Some(old) = entries.map.insert(key, entry) {
            entries.nodes -= old.simulation.mesh.nodes.len();
        }
        entries.nodes += size;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::Patch;
    use crate::fe::mesh::MeshSpec;
    use crate::fe::simulate;

    #[test]
    fn a_hit_returns_the_same_simulation_a_changed_design_misses_and_clear_empties() {
        let mut design = Design::reference(vec![Patch {
            x_mm: 0.0,
            y_mm: 30.0,
            h_mm: 15.0,
            w_mm: 2.0,
            theta_deg: 10.0,
        }]);
        design.balloon.length_mm = 60.0;
        let options = SimulateOptions {
            mesh: MeshSpec::uniform(3.0),
            ..SimulateOptions::default()
        };
        let (cache, patterns) = (EvaluationCache::default(), PatternCache::default());
        let first = cache
            .simulate(&design, &options, &patterns)
            .expect("solves");
        let second = cache
            .simulate(&design, &options, &patterns)
            .expect("solves");
        assert_eq!(first.positions, second.positions);
        assert_eq!(first.curvature, second.curvature);
        // A fresh solve gives the same bits: the cache changes no result.
        assert_eq!(
            simulate(&design, &options).expect("solves").positions,
            first.positions
        );
        design.patches[0].theta_deg = 10.000001;
        cache
            .simulate(&design, &options, &patterns)
            .expect("solves");
        assert_eq!(cache.counts(), CacheCounts { hits: 1, misses: 2 });
        // Cleared, the cache no longer holds it.
        let key = Key::new(&design, &options);
        assert!(cache.lookup(&key).is_some());
        cache.clear();
        assert!(cache.lookup(&key).is_none());
    }
}
