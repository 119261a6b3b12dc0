//! The source-structure checkers the structure tests share (the core's
//! `module_structure.rs` and `function_length.rs`, and the binary's
//! `tests/structure.rs`): the import graph and its cycles, and function
//! lengths. Each test uses part of them.
#![allow(dead_code)]

pub mod imports;
pub mod lengths;
