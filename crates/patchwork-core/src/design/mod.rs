//! The design schema shared by the CLI, the API and files: balloons, patches.

mod patch;

pub use patch::Patch;
