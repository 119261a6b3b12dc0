//! What the balloon can make within the bounds (`table.rs`, from the FE
//! model, kept between runs by `memo.rs`), and where a target asks for
//! more (`verdict.rs`).

mod helix;
mod measure;
pub mod memo;
mod table;
mod verdict;

pub use table::{PatchResponse, ReachTable};
pub use verdict::{OutOfReach, ReachReport, WindowLengths, judge};
