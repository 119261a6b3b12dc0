//! Inverse design: from a target curve to patches (issue 4). The design
//! variables and their bounds, the objective, and the KSA → CMA-ES → verify
//! pipeline.

mod correction;
pub mod evaluation_cache;
pub mod fidelity;
mod incumbent;
pub mod limits;
pub mod objective;
pub mod pipeline;
mod polish;
mod refine;
pub mod report;
pub mod variables;

pub use fidelity::Fidelity;
pub use limits::AtLimit;
pub use objective::{ObjectiveOptions, TargetProfiles};
pub use pipeline::{
    DesignCheckpoint, DesignHooks, DesignOutcome, DesignProgress, DesignRequest, DesignRunError,
    FinalRefine, INITIAL_STEP, Metrics, Stage, Start, assess, design, design_resumable,
};
pub use refine::RefineSummary;
pub use report::DesignReport;
pub use variables::{DesignSpace, Freedom, VariableBounds};
