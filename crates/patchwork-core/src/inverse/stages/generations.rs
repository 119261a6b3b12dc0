//! How a run of the search's CMA-ES generations is counted and why it
//! stops: shared by the search (`search.rs`) and its rounds on the rod
//! (`rod_search.rs`).

use super::super::outcome::SearchEnd;

/// Why a run of generations stopped.
pub enum Pause {
    /// The search is over.
    Ended(SearchEnd),
    /// The round's evaluations are spent (on the rod: time to correct it).
    Round,
}

/// How the search's evaluations are counted.
#[derive(Clone, Copy)]
pub struct Units {
    /// Model evaluations that make one evaluation (on the rod,
    /// `ROD_EVALUATIONS`; on FE one).
    pub scale: usize,
    /// Evaluations the run spent outside the optimiser.
    pub before: usize,
    /// Evaluations after which the generations pause (none: never).
    pub pause_at: Option<usize>,
}
