//! The tables of a scene kept on disk between runs of `patchwork`
//! (`patchwork_core::inverse::memo`): a design's reach stage solves 21
//! one-patch balloons of the scene (about two seconds) and its rod stage
//! 72 (about five), and every later design of the same scene, bounds and
//! model reads them back instead.
//!
//! The folder is `PATCHWORK_CACHE_DIR`, else `$XDG_CACHE_HOME/patchwork`,
//! else `~/.cache/patchwork`; `PATCHWORK_CACHE_DIR=` (empty) keeps tables in
//! memory only. One file per table, `reach-<hash>.json` or `rod-<hash>.json`
//! (the first word of its key), holding the table
//! and the whole key it was computed for, prefixed with this executable's
//! identity (its size and modification time): a table is read back only for
//! the same key from the same build, since another build's model may solve
//! differently. It is a cache: a folder that cannot be written, or a file
//! that cannot be read, only costs the solves.

use std::path::{Path, PathBuf};

use patchwork_core::inverse::memo::{TableStore, keep_tables_in};
use serde::{Deserialize, Serialize};

/// What one file holds.
#[derive(Serialize, Deserialize)]
struct Stored {
    key: String,
    table: serde_json::Value,
}

/// Tables in files under one folder, for one build.
struct DiskStore {
    folder: PathBuf,
    build: String,
}

/// Keeps the tables of this process's design runs on disk, where
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

    /// The file of `key` (without the build), named by its first word.
    fn path(&self, key: &str) -> PathBuf {
        let kind = key.split_whitespace().next().unwrap_or("table");
        let kind: String = kind.chars().filter(char::is_ascii_alphanumeric).collect();
        let hash = fnv1a(&self.full_key(key));
        self.folder.join(format!("{kind}-{hash:016x}.json"))
    }
}

impl TableStore for DiskStore {
    fn load(&self, key: &str) -> Option<String> {
        let text = std::fs::read_to_string(self.path(key)).ok()?;
        let stored: Stored = serde_json::from_str(&text).ok()?;
        (stored.key == self.full_key(key)).then(|| stored.table.to_string())
    }

    fn save(&self, key: &str, table: &str) {
        let path = self.path(key);
        let Ok(table) = serde_json::from_str(table) else {
            return;
        };
        let stored = Stored {
            key: self.full_key(key),
            table,
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

    /// A table as JSON, its keys in the order serde_json writes them.
    fn table(curvature: f64) -> String {
        format!(r#"{{"entries":[{{"curvature_per_mm":{curvature:?}}}],"patch_length_mm":30.0}}"#)
    }

    #[test]
    fn a_table_is_read_back_for_its_key_and_build_only() {
        let dir = tempfile::tempdir().unwrap();
        let store = |build: &str| DiskStore {
            folder: dir.path().join("cache"),
            build: build.into(),
        };
        let this = store("1 2");
        assert!(this.load("reach scene a").is_none());
        this.save("reach scene a", &table(0.05));
        assert_eq!(this.load("reach scene a"), Some(table(0.05)));
        assert!(this.load("reach scene b").is_none());
        assert!(this.load("rod scene a").is_none());
        assert!(store("1 3").load("reach scene a").is_none());
        let path = this.path("reach scene a");
        assert!(
            path.file_name()
                .unwrap()
                .to_str()
                .unwrap()
                .starts_with("reach-")
        );
        // A damaged file is a miss, not an error.
        std::fs::write(&path, "{").unwrap();
        assert!(this.load("reach scene a").is_none());
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
