//! Tables kept between design runs: the reach table (`reach::memo`) and
//! the rod table (`crate::rod`) of a scene.
//!
//! A table depends on the scene (the balloon but its length, the patch
//! material, the pressure), the bounds and the model it is solved on —
//! not on the target — and costs tens of one-patch solves. So a process
//! keeps the last [`KEEP`] complete tables of each kind it computed (the
//! service's jobs share them), and a caller may keep them longer through a
//! [`TableStore`] (the CLI's on disk). A table is found by its key: every
//! input it is computed from, written out exactly (`{:?}` of f64
//! round-trips), its first word naming its kind. A table that a cancel or
//! a time limit left incomplete is not kept.

use std::fmt::Debug;
use std::sync::{Mutex, OnceLock};
use std::time::Duration;

use serde::Serialize;
use serde::de::DeserializeOwned;

use super::variables::VariableBounds;
use crate::design::Design;
use crate::fe::SimulateOptions;
use crate::fe::newton::NewtonOptions;

/// Tables of each kind a process keeps in memory (the most recently used
/// first).
pub const KEEP: usize = 8;

/// Where tables are kept beyond the process, as JSON: a cache, so a failed
/// load or save only costs the table's solves.
pub trait TableStore: Send + Sync {
    /// The table stored under `key`, if any.
    fn load(&self, key: &str) -> Option<String>;
    /// Stores `table` under `key`.
    fn save(&self, key: &str, table: &str);
}

static STORE: OnceLock<Box<dyn TableStore>> = OnceLock::new();

/// Keeps tables in `store` too, for the rest of the process; false if a
/// store was already set.
pub fn keep_tables_in(store: Box<dyn TableStore>) -> bool {
    STORE.set(store).is_ok()
}

/// The key of a table of `kind` for `base`'s scene within `bounds` on
/// `model` over `grid`: the scene without its patches or length, the
/// bounds, the model (less its thread count and time limits, which do not
/// change a complete table) and the grid, written out.
pub fn scene_key(
    kind: &str,
    base: &Design,
    bounds: &VariableBounds,
    model: &SimulateOptions,
    grid: &impl Debug,
) -> String {
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
    format!("{kind}\n{scene:?}\n{bounds:?}\n{model:?}\n{grid:?}")
}

/// The tables of one kind a process keeps in memory.
pub struct Kept<T> {
    tables: Mutex<Vec<(String, T)>>,
}

impl<T: Clone + Serialize + DeserializeOwned> Kept<T> {
    pub const fn new() -> Kept<T> {
        Kept {
            tables: Mutex::new(Vec::new()),
        }
    }

    /// The table under `key`: kept in memory, else from the store, else
    /// `compute`d (and kept where complete).
    pub fn table_for<E>(
        &self,
        key: &str,
        compute: impl FnOnce() -> Result<T, E>,
        complete: impl Fn(&T) -> bool,
    ) -> Result<T, E> {
        if let Some(table) = self.kept(key) {
            return Ok(table);
        }
        let stored = STORE.get().and_then(|s| s.load(key));
        let stored = stored.and_then(|json| serde_json::from_str::<T>(&json).ok());
        if let Some(table) = stored.filter(&complete) {
            self.keep(key, &table);
            return Ok(table);
        }
        let table = compute()?;
        if complete(&table) {
            self.keep(key, &table);
            let json = serde_json::to_string(&table);
            if let (Some(store), Ok(json)) = (STORE.get(), json) {
                store.save(key, &json);
            }
        }
        Ok(table)
    }

    /// How many tables are kept in memory.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// Whether no table is kept in memory.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<(String, T)>> {
        self.tables
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// The table kept in memory under `key`, moved to the front.
    fn kept(&self, key: &str) -> Option<T> {
        let mut kept = self.lock();
        let at = kept.iter().position(|(k, _)| k == key)?;
        let entry = kept.remove(at);
        let table = entry.1.clone();
        kept.insert(0, entry);
        Some(table)
    }

    /// Keeps `table` in memory under `key`, dropping the least recently
    /// used beyond [`KEEP`].
    fn keep(&self, key: &str, table: &T) {
        let mut kept = self.lock();
        kept.retain(|(k, _)| k != key);
        kept.insert(0, (key.to_string(), table.clone()));
        kept.truncate(KEEP);
    }
}

impl<T: Clone + Serialize + DeserializeOwned> Default for Kept<T> {
    fn default() -> Self {
        Kept::new()
    }
}
