//! Reach tables kept on disk between runs of `patchwork`
//! (`patchwork_core::inverse::reach::memo`): a design's reach stage solves
//! 21 one-patch balloons of the scene (about two seconds), and every later
//! design of the same scene, bounds and model reads them back instead.
//!
//! The folder is `PATCHWORK_CACHE_DIR`, else `$XDG_CACHE_HOME/patchwork`,
//! else `~/.cache/patchwork`; `PATCHWORK_CACHE_DIR=` (empty) keeps tables in
//! memory only. One file per table, `reach-<hash>.json`, holding the table
//! and the whole key it was computed for, prefixed with this executable's
//! identity (its size and modification time): a table is read back only for
//! the same key from the same build, since another build's model may solve
//! differently. It is a cache: a folder that cannot be written, or a file
//! that cannot be read, only costs the solves.

use std::path::{Path, PathBuf};

use patchwork_core::inverse::reach::ReachTable;
use patchwork_core::inverse::reach::memo::{TableStore, keep_tables_in};
use serde::{Deserialize, Serialize};

/// What one file holds.
#[derive(Serialize, Deserialize)]
struct Stored {
    key: String,
    table: ReachTable,
}

/// Tables in files under one folder, for one build.
struct DiskStore {
    folder: PathBuf,
    build: String,
}

/// Keeps the reach tables of this process's design runs on disk, where
/// there is a folder for them.
pub fn install() {
    if let Some(folder) = folder() {
        let build = build_identity().unwrap_or_default();
        keep_tables_in(Box::new(DiskStore { folder, build }));
    }
}

fn folder() -> Option<PathBuf> {
    match std::env::var_os("PATCHWORK_CACHE_DIR") {
        Some(dir) if dir.is_empty() => None,
        Some(dir) => Some(PathBuf::from(dir)),
        None => std::env::var_os("XDG_CACHE_HOME")
            .filter(|d| !d.is_empty())
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| Path::new(&h).join(".cache")))
            .map(|cache| cache.join("patchwork")),
    }
}

/// This executable's size and modification time: another build, another
/// identity.
fn build_identity() -> Option<String> {
    let meta = std::fs::metadata(std::env::current_exe().ok()?).ok()?;
    let modified = meta.modified().ok()?;
    let since = modified.duration_since(std::time::UNIX_EPOCH).ok()?;
    Some(format!("{} {}", meta.len(), since.as_nanos()))
}

/// FNV-1a, 64 bits: a file name for a key (the key itself is checked on
/// reading, so a collision only misses the cache).
fn fnv1a(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |hash, byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

impl DiskStore {
    fn full_key(&self, key: &str) -> String {
        format!("patchwork {}\n{key}", self.build)
    }

    fn path(&self, full_key: &str) -> PathBuf {
        self.folder
            .join(format!("reach-{:016x}.json", fnv1a(full_key)))
    }
}

impl TableStore for DiskStore {
    fn load(&self, key: &str) -> Option<ReachTable> {
        let full = self.full_key(key);
        let text = std::fs::read_to_string(self.path(&full)).ok()?;
        let stored: Stored = serde_json::from_str(&text).ok()?;
        (stored.key == full).then_some(stored.table)
    }

    fn save(&self, key: &str, table: &ReachTable) {
        let key = self.full_key(key);
        let path = self.path(&key);
        let stored = Stored {
            key,
            table: table.clone(),
        };
        let Ok(text) = serde_json::to_string(&stored) else {
            return;
        };
        // Written beside, then renamed: a reader never sees half a file.
        let partial = path.with_extension(format!("{}.partial", std::process::id()));
        let written = std::fs::create_dir_all(&self.folder)
            .and_then(|()| std::fs::write(&partial, text))
            .and_then(|()| std::fs::rename(&partial, &path));
        if written.is_err() {
            let _ = std::fs::remove_file(&partial);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use patchwork_core::inverse::reach::PatchResponse;

    fn table(curvature: f64) -> ReachTable {
        ReachTable {
            patch_length_mm: 30.0,
            entries: vec![PatchResponse {
                width_mm: 1.0,
                theta_deg: 0.0,
                curvature_per_mm: curvature,
                torsion_per_mm: 0.0,
                peak_curvature_per_mm: curvature,
            }],
        }
    }

    #[test]
    fn a_table_is_read_back_for_its_key_and_build_only() {
        let dir = tempfile::tempdir().unwrap();
        let store = |build: &str| DiskStore {
            folder: dir.path().join("cache"),
            build: build.into(),
        };
        let this = store("1 2");
        assert!(this.load("scene a").is_none());
        this.save("scene a", &table(0.05));
        assert_eq!(this.load("scene a"), Some(table(0.05)));
        assert!(this.load("scene b").is_none());
        assert!(store("1 3").load("scene a").is_none());
        // A damaged file is a miss, not an error.
        let path = this.path(&this.full_key("scene a"));
        std::fs::write(&path, "{").unwrap();
        assert!(this.load("scene a").is_none());
    }

    #[test]
    fn a_folder_that_cannot_be_written_only_misses() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("not a folder");
        std::fs::write(&file, "").unwrap();
        let store = DiskStore {
            folder: file,
            build: String::new(),
        };
        store.save("scene", &table(0.1));
        assert!(store.load("scene").is_none());
    }
}
