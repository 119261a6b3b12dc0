//! Reach tables kept between design runs.
//!
//! A table depends on the scene (the balloon but its length, the patch
//! material, the pressure), the bounds and the verification model — not on
//! the target — and costs 21 solves on the verification mesh (about two
//! seconds on two cores, a fifth of a short `draft` design). So a process
//! keeps the last [`KEEP`] complete tables it computed (the service's jobs
//! share them), and a caller may keep them longer through a [`TableStore`]
//! (the CLI's on disk). A table is found by its [`key`]: every input it is
//! computed from, written out exactly (`{:?}` of f64 round-trips). A table
//! that a cancel or a time limit left incomplete is not kept.

use std::sync::{Mutex, OnceLock};
use std::time::Duration;

use crate::design::Design;
use crate::fe::newton::NewtonOptions;
use crate::fe::{SimulateError, SimulateOptions};

use super::super::variables::VariableBounds;
use super::table::ReachTable;

/// Tables a process keeps in memory (the most recently used first).
pub const KEEP: usize = 8;

/// Where tables are kept beyond the process: a cache, so a failed load or
/// save only costs the table's solves.
pub trait TableStore: Send + Sync {
    /// The table stored under `key`, if any.
    fn load(&self, key: &str) -> Option<ReachTable>;
    /// Stores `table` under `key`.
    fn save(&self, key: &str, table: &ReachTable);
}

static STORE: OnceLock<Box<dyn TableStore>> = OnceLock::new();
static KEPT: Mutex<Vec<(String, ReachTable)>> = Mutex::new(Vec::new());

/// Keeps tables in `store` too, for the rest of the process; false if a
/// store was already set.
pub fn keep_tables_in(store: Box<dyn TableStore>) -> bool {
    STORE.set(store).is_ok()
}

/// What a table for `base`'s scene within `bounds` on `model` is computed
/// from, written out: the scene without its patches or length, the bounds,
/// the model (less its thread count and time limits, which do not change a
/// complete table) and the grid.
pub fn key(base: &Design, bounds: &VariableBounds, model: &SimulateOptions) -> String {
    let mut scene = base.clone();
    scene.patches.clear();
    scene.balloon.length_mm = 0.0;
    let model = SimulateOptions {
        threads: 1,
        time_limit: None,
        newton: NewtonOptions {
            time_limit: Duration::ZERO,
            ..model.newton
        },
        ..*model
    };
    format!(
        "reach table 1\n{scene:?}\n{bounds:?}\n{model:?}\n{:?}",
        ReachTable::grid(bounds)
    )
}

/// The table under `key`: kept in memory, else from the store, else
/// `compute`d (and kept where complete).
pub fn table_for(
    key: &str,
    compute: impl FnOnce() -> Result<ReachTable, SimulateError>,
    complete: impl Fn(&ReachTable) -> bool,
) -> Result<ReachTable, SimulateError> {
    if let Some(table) = kept(key) {
        return Ok(table);
    }
    if let Some(table) = STORE.get().and_then(|s| s.load(key)).filter(&complete) {
        keep(key, &table);
        return Ok(table);
    }
    let table = compute()?;
    if complete(&table) {
        keep(key, &table);
        if let Some(store) = STORE.get() {
            store.save(key, &table);
        }
    }
    Ok(table)
}

/// The table kept in memory under `key`, moved to the front.
fn kept(key: &str) -> Option<ReachTable> {
    let mut kept = KEPT.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let at = kept.iter().position(|(k, _)| k == key)?;
    let entry = kept.remove(at);
    let table = entry.1.clone();
    kept.insert(0, entry);
    Some(table)
}

/// Keeps `table` in memory under `key`, dropping the least recently used
/// beyond [`KEEP`].
fn keep(key: &str, table: &ReachTable) {
    let mut kept = KEPT.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    kept.retain(|(k, _)| k != key);
    kept.insert(0, (key.to_string(), table.clone()));
    kept.truncate(KEEP);
}

#[cfg(test)]
#[path = "memo_tests.rs"]
mod tests;
