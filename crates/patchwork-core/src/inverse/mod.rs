//! Inverse design: from a target curve to patches. A run is a [`Plan`] of
//! stages (`plan.rs`), resolved from the user's settings (`settings.rs`)
//! and a preset (`presets.rs`, a data table) with expert overrides
//! (`tuning.rs`), and run by the executor (`executor.rs`):
//!
//! ```text
//! seed → reach → search → polish → verify → length → refine (± correction)
//!      → layout → final refine
//! ```
//!
//! Each stage is a small type in `stages/`, a [`Stage`] of the plan, known
//! everywhere by its [`StageName`]; the executor announces each as it
//! begins (`Observer::stage`). A user's time limit (`deadline.rs`) stops
//! the stage under way at its next step and skips the later ones but the
//! verification. The numerical pieces they use:
//! the design variables and their bounds (`variables.rs`), the objective
//! (`objective.rs`), CMA-ES's incumbent (`incumbent.rs`), the
//! Levenberg–Marquardt refine (`refine.rs`) and its correction by a finer
//! model (`correction.rs`).

mod assess;
mod caches;
mod checkpoint;
pub mod clearing;
mod correction;
mod deadline;
mod errors;
mod evaluation_cache;
mod executor;
mod incumbent;
pub mod input;
pub mod layout;
pub mod limits;
pub mod memo;
pub mod objective;
mod outcome;
mod plan;
pub mod planar;
mod presets;
pub mod reach;
mod refine;
pub mod report;
mod run;
mod settings;
pub mod shortfall;
mod stages;
mod tuning;
pub mod variables;

pub use assess::assess;
pub use caches::Caches;
pub use checkpoint::{DesignCheckpoint, RodRounds};
pub use deadline::Deadline;
pub use errors::{DesignRunError, SettingsError};
pub use evaluation_cache::{CacheCounts, EvaluationCache};
pub use executor::{design, design_resumable};
pub use input::{InputReport, Smoothing};
pub use limits::AtLimit;
pub use objective::{ObjectiveOptions, TargetProfiles};
pub use outcome::{
    AsGiven, DesignOutcome, DesignProgress, Expected, Metrics, Profiles, RefineSummary,
    RobustSummary, SearchEnd, SearchStop, StageName, StageTime, TimeLimited,
};
pub use plan::{MAX_TIME_LIMIT_S, Plan, Stage};
pub use presets::{Fidelity, PRESETS, PresetRow};
pub use report::DesignReport;
pub use run::Observer;
pub use settings::UserSettings;
pub use tuning::{
    FinalRefineSettings, INITIAL_STEP, ROD_EVALUATIONS, Start, Tuning, TuningOverrides,
};
pub use variables::{DesignSpace, Freedom, VariableBounds};
