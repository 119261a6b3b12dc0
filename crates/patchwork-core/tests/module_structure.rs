//! The core's source reads as layers: no module imports one that imports it
//! back (directly or around a longer loop), and no file passes 500 lines.
//!
//! The graph is built from the source text: every `use` tree and every
//! `crate::…`/`super::…` path in code (tests excluded: a file is read up to
//! its `#[cfg(test)]`), resolved to the file that defines the item. A
//! folder's `mod.rs` that only re-exports is looked through: a name it
//! re-exports with `pub use` resolves to the file that defines it.

mod structure;

use std::path::Path;

use structure::imports::{MAX_FILE_LINES, structure};

#[test]
fn the_core_has_no_import_cycles_and_no_file_over_500_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let (graph, cycles, long) = structure(&root);
    assert!(
        cycles.is_empty() && long.is_empty(),
        "import cycles:\n  {}\nfiles over {MAX_FILE_LINES} lines:\n  {}",
        cycles.join("\n  "),
        long.join("\n  ")
    );
    // The check sees real edges (a sanity check on the parser).
    let newton = vec!["fe".to_string(), "newton".to_string()];
    assert!(graph.values().any(|targets| targets.contains(&newton)));
}

/// The checker finds a loop through a re-export and a written-out path, and
/// ignores test modules.
#[test]
fn the_checker_finds_a_cycle_in_a_small_tree() {
    let root = std::env::temp_dir().join(format!("patchwork-structure-{}", std::process::id()));
    let dir = root.join("stages");
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, text: &str| std::fs::write(root.join(name), text).unwrap();
    write("lib.rs", "mod plan;\nmod stages;\nmod run;\n");
    write("plan.rs", "use crate::stages::Search;\n");
    write("stages/mod.rs", "mod search;\npub use search::Search;\n");
    write(
        "stages/search.rs",
        "use super::super::run::Run;\npub struct Search;\n#[cfg(test)]\nuse crate::plan::X;\n",
    );
    write(
        "run.rs",
        "pub struct Run;\nfn f() { let _ = crate::plan::Plan::new(); }\n",
    );
    let (_, cycles, long) = structure(&root);
    assert_eq!(
        cycles,
        vec!["plan → stages::search → run → plan".to_string()]
    );
    assert!(long.is_empty());
    // Without the written-out path there is no loop.
    write("run.rs", "pub struct Run;\n");
    let (graph, cycles, _) = structure(&root);
    assert!(cycles.is_empty(), "{cycles:?}");
    assert_eq!(graph.len(), 2, "{graph:?}");
    std::fs::remove_dir_all(&root).unwrap();
}
