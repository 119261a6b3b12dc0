//! Black-box tests of `patchwork serve` over real HTTP: each test starts the
//! binary on port 0 with a fresh SQLite file.

#[path = "../common/mod.rs"]
mod common;
mod support;

mod access;
mod bad_input;
mod lifecycle;
mod recovery;
mod schemathesis;
