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
