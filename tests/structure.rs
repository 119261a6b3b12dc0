//! The binary's source reads as layers, as the core's does: no module
//! imports one that imports it back, no file passes 500 lines and no
//! function 80. The checkers are the core's
//! (`crates/patchwork-core/tests/structure/`).

#[path = "../crates/patchwork-core/tests/structure/mod.rs"]
mod structure;

use std::path::Path;

use structure::imports::{MAX_FILE_LINES, structure};
use structure::lengths::{MAX_FUNCTION_LINES, functions, rust_files};

#[test]
fn the_binary_has_no_import_cycles_and_no_file_over_500_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let (graph, cycles, long) = structure(&root);
    assert!(
        cycles.is_empty() && long.is_empty(),
        "import cycles:\n  {}\nfiles over {MAX_FILE_LINES} lines:\n  {}",
        cycles.join("\n  "),
        long.join("\n  ")
    );
    // The check sees real edges: the bench's report imports its measure.
    let [report, measure] = [["cli", "bench", "report"], ["cli", "bench", "measure"]]
        .map(|m| m.map(String::from).to_vec());
    assert!(
        graph.get(&report).is_some_and(|t| t.contains(&measure)),
        "{graph:?}"
    );
    // And a `crate::` path from the binary's root (main.rs).
    let [sqlite, job_state] = [
        vec!["service", "store", "sqlite"],
        vec!["service", "job_state"],
    ]
    .map(|m| m.into_iter().map(String::from).collect::<Vec<_>>());
    assert!(graph.get(&sqlite).is_some_and(|t| t.contains(&job_state)));
}

#[test]
fn no_function_in_the_binary_passes_80_lines() {
    let mut files = Vec::new();
    rust_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut files,
    );
    let mut long = Vec::new();
    let mut counted = 0;
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        for (name, line, lines) in functions(&text) {
            counted += 1;
            if lines > MAX_FUNCTION_LINES {
                long.push(format!("{}:{line} {name} ({lines} lines)", file.display()));
            }
        }
    }
    assert!(counted > 250, "only {counted} functions found");
    assert!(
        long.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines:\n  {}",
        long.join("\n  ")
    );
}

/// The service's layers: HTTP (handlers, request bodies, problem details)
/// → job spec → store → worker → core. What runs a job — the job spec, the
/// store, the worker and what they import — never reaches back into the
/// HTTP layer: a job is read as its spec, not as a request.
#[test]
fn a_job_runs_without_the_http_layer() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let (graph, _, _) = structure(&root);
    let module = |path: &str| path.split('/').map(String::from).collect::<Vec<_>>();
    let http = [
        "service/request",
        "service/problem",
        "service/jobs",
        "service/routes",
    ]
    .map(module);
    let starts: Vec<Vec<String>> = graph
        .keys()
        .filter(|m| {
            ["service/spec", "service/worker", "service/store"]
                .iter()
                .any(|layer| m.starts_with(&module(layer)))
        })
        .cloned()
        .collect();
    assert!(starts.len() >= 8, "{starts:?}");
    // Everything those modules reach, by import.
    let mut reached: Vec<Vec<String>> = starts.clone();
    let mut seen: std::collections::BTreeSet<Vec<String>> = starts.into_iter().collect();
    while let Some(m) = reached.pop() {
        for next in graph.get(&m).into_iter().flatten() {
            if seen.insert(next.clone()) {
                reached.push(next.clone());
            }
        }
    }
    let wrong: Vec<_> = http.iter().filter(|m| seen.contains(*m)).collect();
    assert!(wrong.is_empty(), "the job's way reaches {wrong:?}");
    assert!(seen.contains(&module("service/job_state")), "{seen:?}");
    // Nor does it use axum's types.
    for m in &seen {
        let file = root.join(m.join("/"));
        for path in [file.with_extension("rs"), file.join("mod.rs")] {
            if let Ok(text) = std::fs::read_to_string(&path) {
                assert!(!text.contains("axum::"), "{} uses axum", path.display());
            }
        }
    }
}
