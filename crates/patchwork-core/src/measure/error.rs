//! Why a comparison cannot be made.

use crate::curve::CurveError;

/// A measured centreline shorter or longer than the prediction by more
/// than this factor is refused: its units are likely wrong, or it is of
/// another balloon.
pub(super) const LENGTH_FACTOR_LIMIT: f64 = 2.0;

/// Why a comparison cannot be made; each names the input at fault.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CompareError {
    #[error("design: {0}")]
    Design(String),
    #[error("measured centreline: {0}")]
    Measured(#[from] CurveError),
    #[error(
        "measured centreline: {measured_mm:.1} mm long against the predicted {predicted_mm:.1} mm \
         — more than a factor of {LENGTH_FACTOR_LIMIT} apart; are its units right?"
    )]
    Length { measured_mm: f64, predicted_mm: f64 },
}
