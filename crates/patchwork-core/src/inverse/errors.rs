//! Why a design run or its settings failed.

use super::variables::VariableError;
use crate::curve::CurveError;
use crate::fe::SimulateError;
use crate::ksa::KsaError;

/// A setting out of range, found while resolving a plan: the field (as in
/// the settings: `budget`, `initial_step`, `objective.shape_weight`,
/// `bounds.h_min_mm`, `design.balloon.radius_mm`, …) and why. The CLI and
/// the API translate the field into their own names.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}: {reason}")]
pub struct SettingsError {
    pub field: String,
    pub reason: String,
}

impl SettingsError {
    pub fn new(field: impl Into<String>, reason: impl Into<String>) -> SettingsError {
        SettingsError {
            field: field.into(),
            reason: reason.into(),
        }
    }
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignRunError {
    #[error("{0}")]
    Ksa(KsaError),
    #[error("{0}")]
    Variables(VariableError),
    #[error(
        "the bare balloon has no stable inflated state at {pressure_kpa} kPa: no rising branch of its inflation curve reaches that pressure below a hoop stretch of 12, past any latex balloon's burst"
    )]
    NoTubeState { pressure_kpa: f64 },
    #[error("the seed design could not be simulated: {0}")]
    Seed(SimulateError),
    #[error("no patch of the bounds could be simulated for the reach table: {0}")]
    Reach(SimulateError),
    #[error("the best design failed verification on the fine mesh: {0}")]
    Verify(SimulateError),
    /// A stage found the run without what an earlier stage should have left
    /// (a plan the resolver does not build).
    #[error("malformed plan: {0}")]
    Plan(String),
    #[error("the target could not be prepared: {0}")]
    Input(CurveError),
    #[error("cancelled")]
    Cancelled,
}
