//! The stages of a design run, one small type each with its own budget.
//! The seed stage creates the run; every later stage has a `run` that
//! reads what it needs from the run (`run.rs`) and leaves its result there.
//!
//! A new stage is: a file here with its type and `run`; a variant of
//! [`Stage`](super::Stage) holding it, with its [`StageName`](super::StageName)
//! in `Stage::name` and its call in `Stage::run` (the compiler asks for both);
//! and a line in `plan::stages` where the plan takes it. The executor
//! announces it by its name.

mod final_refine;
mod generations;
mod layout;
mod length;
mod polish;
mod reach;
mod refine;
mod robust;
mod rod_model;
mod rod_search;
mod search;
mod seed;
mod spread;
mod verify;

pub use final_refine::FinalRefine;
pub use layout::{Layout, MAX_LAYOUTS};
pub use length::Length;
pub use polish::Polish;
pub use reach::Reach;
pub use refine::Refine;
pub use robust::{MAX_SOURCES, RobustStage};
pub(super) use rod_model::RodModel;
pub use search::Search;
pub use seed::Seed;
pub(super) use seed::seed_tube_radius;
pub use spread::SpreadStage;
pub use verify::Verify;
