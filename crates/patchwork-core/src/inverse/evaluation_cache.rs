//! A cache of evaluated designs: the converged simulations of recent cold
//! solves, keyed by the exact design and model, shared by every design run in
//! the process (the service's jobs included).
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
//! twice, so a single run gains nothing (measured in BENCHMARKS.md).

use std::collections::HashMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::design::Design;
use crate::fe::{SimulateError, SimulateOptions, Simulation, simulate};

/// Mesh nodes the cache may hold in all, about 110 bytes each in a
/// simulation: some 55 MB — 300 draft-search simulations (3 mm) or 20 of
/// the `fine` preset's 0.5 mm verification.
const NODE_BUDGET: usize = 500_000;

struct Entry {
    simulation: Simulation,
    last_used: u64,
}

#[derive(Default)]
struct Cache {
    entries: HashMap<String, Entry>,
    nodes: usize,
    clock: u64,
}

static CACHE: Mutex<Option<Cache>> = Mutex::new(None);
static HITS: AtomicUsize = AtomicUsize::new(0);
static MISSES: AtomicUsize = AtomicUsize::new(0);

/// Hits and misses since the process started.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CacheCounts {
    pub hits: usize,
    pub misses: usize,
}

/// [`simulate`] from the cold start, served from the cache when this exact
/// design was solved on this exact model before.
pub fn simulate_cached(
    design: &Design,
    options: &SimulateOptions,
) -> Result<Simulation, SimulateError> {
    // `{:?}` prints every f64 in its shortest round-trip form: equal keys
    // are equal values.
    let key = format!("{design:?}|{options:?}");
    if let Some(simulation) = lookup(&key) {
        HITS.fetch_add(1, Ordering::Relaxed);
        return Ok(simulation);
    }
    MISSES.fetch_add(1, Ordering::Relaxed);
    let simulation = simulate(design, options)?;
    store(key, &simulation);
    Ok(simulation)
}

/// Counts of cache hits and misses.
pub fn counts() -> CacheCounts {
    CacheCounts {
        hits: HITS.load(Ordering::Relaxed),
        misses: MISSES.load(Ordering::Relaxed),
    }
}

/// Empties the cache (the counts stay): a benchmark that times runs as a
/// fresh process would see them calls this before each run — otherwise two
/// settings sharing a search (draft and fine) would time the second one's
/// search as all hits.
pub fn clear() {
    *lock() = None;
}

fn lock() -> std::sync::MutexGuard<'static, Option<Cache>> {
    CACHE.lock().unwrap_or_else(|e| e.into_inner())
}

fn lookup(key: &str) -> Option<Simulation> {
    let mut guard = lock();
    let cache = guard.as_mut()?;
    cache.clock += 1;
    let clock = cache.clock;
    let entry = cache.entries.get_mut(key)?;
    entry.last_used = clock;
    Some(entry.simulation.clone())
}

fn store(key: String, simulation: &Simulation) {
    let size = simulation.mesh.nodes.len();
    if size > NODE_BUDGET {
        return;
    }
    let mut guard = lock();
    let cache = guard.get_or_insert_with(Cache::default);
    while cache.nodes + size > NODE_BUDGET {
        let Some(oldest) = cache
            .entries
            .iter()
            .min_by_key(|(_, e)| e.last_used)
            .map(|(k, _)| k.clone())
        else {
            break;
        };
        if let Some(e) = cache.entries.remove(&oldest) {
            cache.nodes -= e.simulation.mesh.nodes.len();
        }
    }
    cache.clock += 1;
    let entry = Entry {
        simulation: simulation.clone(),
        last_used: cache.clock,
    };
    if let Some(old) = cache.entries.insert(key, entry) {
        cache.nodes -= old.simulation.mesh.nodes.len();
    }
    cache.nodes += size;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::Patch;
    use crate::fe::mesh::MeshSpec;

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
        let before = counts();
        let first = simulate_cached(&design, &options).expect("solves");
        let second = simulate_cached(&design, &options).expect("solves");
        assert_eq!(first.positions, second.positions);
        assert_eq!(first.curvature, second.curvature);
        // A fresh solve gives the same bits: the cache changes no result.
        assert_eq!(
            simulate(&design, &options).expect("solves").positions,
            first.positions
        );
        design.patches[0].theta_deg = 10.000001;
        simulate_cached(&design, &options).expect("solves");
        let after = counts();
        // Other tests may run in parallel: at least our own counts.
        assert!(after.hits > before.hits);
        assert!(after.misses >= before.misses + 2);
        // Cleared, the cache no longer holds it.
        let key = format!("{design:?}|{options:?}");
        assert!(lookup(&key).is_some());
        clear();
        assert!(lookup(&key).is_none());
    }
}
