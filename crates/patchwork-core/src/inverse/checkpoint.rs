//! The executor's state between stages, as a checkpoint: enough to resume a
//! run where it stopped (a service killed mid-run resumes from its last
//! checkpoint, not from scratch).

use serde::{Deserialize, Serialize};

use crate::cmaes::Optimizer;
use crate::design::{Design, Patch};

/// The state of a design run once its seed is known, and again after every
/// search generation. The stages after the search are not checkpointed: a
/// resumed run repeats them from the search's last state, which gives the
/// same design as an uninterrupted run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignCheckpoint {
    /// Balloon, materials and pressure, with the balloon length chosen.
    pub base: Design,
    /// KSA seed on that balloon.
    pub seed_patches: Vec<Patch>,
    pub seed_objective: f64,
    /// The search's state; `None` before its first generation.
    pub optimizer: Option<Optimizer>,
    /// Best design so far on the search model.
    pub best_objective: f64,
    pub best_patches: Vec<Patch>,
    /// Forward evaluations spent, the seed's included.
    pub evaluations: usize,
    /// `evaluations` when the best design last improved (the seed: 1).
    #[serde(default)]
    pub improved_at: usize,
    /// Wall time spent on the run so far, over every process that ran it.
    pub elapsed_s: f64,
    /// A search on the rod (tuning `rod_search`): where its rod was last
    /// corrected and the best corrected design; none on FE and before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rod: Option<RodRounds>,
}

/// The state of a search on the rod between its corrections (see
/// `stages/rod_search.rs`), so that a resumed search corrects where the
/// interrupted one did.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RodRounds {
    /// The design the rod was last corrected at (solved on the
    /// verification model).
    pub corrected_at: Vec<Patch>,
    /// Evaluations at which the next correction is due.
    pub next_at: usize,
    /// The best design by its corrected score so far, and that score.
    pub kept_objective: f64,
    pub kept_patches: Vec<Patch>,
}

impl DesignCheckpoint {
    /// The best design so far.
    pub fn best_design(&self) -> Design {
        Design {
            patches: self.best_patches.clone(),
            ..self.base.clone()
        }
    }
}
