//! Functions fit on a screen: none over 80 lines in the design pipeline
//! (`inverse/`), the finite elements (`fe/`, Newton's method included) and
//! the least-squares solver (`least_squares/`), tests included.

mod structure;

use std::path::Path;

use structure::lengths::{MAX_FUNCTION_LINES as MAX_LINES, functions, rust_files};

const CHECKED: [&str; 5] = ["inverse", "fe", "least_squares", "measure", "calibrate"];

#[test]
fn no_function_in_the_pipeline_fe_least_squares_or_measure_passes_80_lines() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut long = Vec::new();
    let mut counted = 0;
    let mut longest = (0, String::new());
    for dir in CHECKED {
        let mut files = Vec::new();
        rust_files(&src.join(dir), &mut files);
        assert!(!files.is_empty(), "{dir} has no sources");
        for file in files {
            let text = std::fs::read_to_string(&file).unwrap();
            for (name, line, lines) in functions(&text) {
                counted += 1;
                if lines > longest.0 {
                    longest = (lines, format!("{}:{line} {name}", file.display()));
                }
                if lines > MAX_LINES {
                    long.push(format!("{}:{line} {name} ({lines} lines)", file.display()));
                }
            }
        }
    }
    println!(
        "{counted} functions; the longest {} lines: {}",
        longest.0, longest.1
    );
    assert!(counted > 100, "only {counted} functions found");
    assert!(
        long.is_empty(),
        "functions over {MAX_LINES} lines:\n  {}",
        long.join("\n  ")
    );
}

#[test]
fn the_scanner_measures_bodies_and_ignores_braces_in_strings_and_comments() {
    let text = "fn a() {\n    let s = \"}}\"; // }\n    let c = '}';\n    let r = r#\"{\"#;\n}\n\
                pub(crate) fn b<'a>(x: &'a str) -> &'a str {\n    x\n}\n\
                fn declared();\n    pub fn c() { if true { } }\n";
    assert_eq!(
        functions(text),
        vec![
            ("a".to_string(), 1, 5),
            ("b".to_string(), 6, 3),
            ("c".to_string(), 10, 1)
        ]
    );
}
