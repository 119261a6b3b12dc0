//! The design of a design.json (what `patchwork design` writes), for the
//! studies that take design runs' results as their input.

use patchwork_core::design::Design;

/// The design held in the design.json at `path`.
pub fn design_of(path: &str) -> Design {
    let text = std::fs::read_to_string(path).expect("readable");
    let value: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    serde_json::from_value(value["design"].clone()).expect("a design")
}
