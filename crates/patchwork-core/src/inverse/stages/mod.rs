//! The stages of a design run, one small type each with its own budget.
//! The seed stage creates the run; every later stage implements
//! [`RunStage`]: it reads what it needs from the [`Run`] and leaves its
//! result there. A new stage is a new file here, a variant of
//! `plan::PlannedStage`, and a line in `Plan::with_tuning` where it goes.

mod final_refine;
mod layout;
mod length;
mod polish;
mod reach;
mod refine;
mod search;
mod seed;
mod verify;

pub use final_refine::FinalRefineStage;
pub use layout::Layout;
pub use length::LengthCorrection;
pub use polish::Polish;
pub use reach::Reach;
pub use refine::Refine;
pub use search::Search;
pub use seed::Seed;
pub use verify::Verify;

use super::errors::DesignRunError;
use super::run::{Context, Run};

/// One stage after the seed.
pub trait RunStage {
    fn run(&self, run: &mut Run<'_>, ctx: &mut Context<'_>) -> Result<(), DesignRunError>;
}
