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
