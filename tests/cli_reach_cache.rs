//! `patchwork design` keeps its reach table on disk: a second design of the
//! same scene reads it back instead of solving the 21 one-patch balloons
//! (a mark put in the kept file shows in its reach); another scene solves
//! and keeps its own.

mod common;
use std::process::Command;

use common::cli::{json, temp_dir};
use serde_json::Value;

/// `patchwork design` of `curve` at draft with a tiny budget, no refine and
/// no spread, its tables kept in `cache`, at `pressure_kpa`.
fn design(cache: &std::path::Path, curve: &std::path::Path, pressure_kpa: &str) -> Value {
    let out = cache.with_file_name(format!("design-{pressure_kpa}"));
    let output = Command::new(env!("CARGO_BIN_EXE_patchwork"))
        .args(["design", &curve.to_string_lossy(), "--out"])
        .arg(&out)
        .args([
            "--fidelity",
            "draft",
            "--budget",
            "3",
            "--json",
            "--seed",
            "1",
        ])
        .arg("--options")
        .arg(format!(r#"{{"pressure_kpa": {pressure_kpa}}}"#))
        .args(["--tuning", r#"{"refine_budget": 0, "spread": false}"#])
        .env("PATCHWORK_CACHE_DIR", cache)
        .output()
        .expect("binary runs");
    json(&output)
}

/// The kept tables' files.
fn tables(cache: &std::path::Path) -> Vec<std::path::PathBuf> {
    let entries = std::fs::read_dir(cache).map(|d| d.flatten().map(|e| e.path()));
    let reach = |p: &std::path::PathBuf| p.to_string_lossy().contains("reach-");
    entries.map_or(Vec::new(), |paths| paths.filter(reach).collect())
}

#[test]
fn a_second_design_of_a_scene_reads_its_reach_table_back() {
    let scratch = temp_dir("reach-cache");
    let cache = scratch.path().join("cache");
    let curve = scratch.path().join("hook.csv");
    let preset = Command::new(env!("CARGO_BIN_EXE_patchwork"))
        .args(["preset", "hook"])
        .output()
        .expect("binary runs");
    assert!(preset.status.success());
    std::fs::write(&curve, &preset.stdout).unwrap();

    let first = design(&cache, &curve, "20");
    let files = tables(&cache);
    assert_eq!(files.len(), 1);
    // The kept table, marked: a design that reads it back reports the mark.
    let mut stored: Value =
        serde_json::from_str(&std::fs::read_to_string(&files[0]).unwrap()).unwrap();
    assert_eq!(stored["table"], first["reach"]["table"]);
    stored["table"]["entries"][0]["torsion_per_mm"] = 0.125.into();
    std::fs::write(&files[0], stored.to_string()).unwrap();
    let second = design(&cache, &curve, "20");
    assert_eq!(second["reach"]["table"], stored["table"]);

    // Another pressure is another scene: its table is solved and kept too.
    let other = design(&cache, &curve, "19");
    assert_ne!(other["reach"]["table"], first["reach"]["table"]);
    assert_eq!(tables(&cache).len(), 2);
}
