//! What a user chooses for a design run: the balloon and materials, the
//! fidelity, the seed, the search budget, the fabrication bounds, which
//! patch parameters may move, whether the balloon length is fixed, the
//! threads and the run's time limit. Everything else is expert tuning (`tuning.rs`), fixed by the
//! fidelity's preset (`presets.rs`).

use super::input::Smoothing;
use super::presets::Fidelity;
use super::variables::{Freedom, VariableBounds};
use crate::design::Design;
use crate::spread::Tolerances;

/// A user's choices for a design run.
#[derive(Debug, Clone, PartialEq)]
pub struct UserSettings {
    /// Balloon, patch material and pressure (its `patches` are ignored).
    pub base: Design,
    pub fidelity: Fidelity,
    pub seed: u64,
    /// Forward evaluations of the search; none: the preset's.
    pub budget: Option<usize>,
    /// Fabrication limits and search windows.
    pub bounds: VariableBounds,
    pub freedom: Freedom,
    /// Keep `base.balloon.length_mm`; otherwise the length is chosen so the
    /// inflated balloon is as long as the target.
    pub fix_length: bool,
    /// How the target is smoothed before the design (default: from the
    /// noise found on it).
    pub smoothing: Smoothing,
    /// Threads evaluating a search generation or a Jacobian's columns side
    /// by side, and assembling a solve that runs alone (the refine's trials,
    /// the verification): the same design for any count.
    pub threads: usize,
    /// The fabrication and operating tolerances the spread is reported at.
    pub tolerances: Tolerances,
    /// The run's wall time, seconds (none: no limit). Once it has passed,
    /// the stage under way stops at its next step with its best design so
    /// far, the later stages that would only improve or report on the
    /// design are skipped, and the outcome names both (`TimeLimited`); the
    /// design is verified whatever the limit.
    pub time_limit_s: Option<f64>,
}

impl Default for UserSettings {
    fn default() -> Self {
        UserSettings {
            base: Design::reference(vec![]),
            fidelity: Fidelity::default(),
            seed: 1,
            budget: None,
            bounds: VariableBounds::default(),
            freedom: Freedom::default(),
            fix_length: false,
            smoothing: Smoothing::Auto,
            threads: 1,
            tolerances: Tolerances::default(),
            time_limit_s: None,
        }
    }
}
