//! Why a calibration cannot be made.

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CalibrationError {
    #[error("nothing measured: give inflations, a pressure–volume curve or a built design")]
    Empty,
    #[error(
        "{measured} measured values cannot determine {parameters} parameters; measure more pressures or both length and diameter"
    )]
    TooFewData { measured: usize, parameters: usize },
    #[error("{kind} {index}: {reason}")]
    Datum {
        kind: &'static str,
        index: usize,
        reason: String,
    },
    #[error("the material has no parameter `{0}` to fit")]
    NoSuchParameter(&'static str),
    #[error(
        "patch_modulus needs a built design's measured centreline: the bare balloon has no patches"
    )]
    PatchWithoutBuilt,
    #[error(
        "every pressure–volume point lies where the pressure is held again at a larger volume (past the peak): the model, pressure-controlled, cannot be fitted to them"
    )]
    NoRisingPressureVolume,
    #[error(
        "the model cannot inflate the balloon at every pressure given from this material (no stable state): check the pressures and the starting material"
    )]
    NoStart,
    #[error("the calibration was stopped before it finished")]
    Cancelled,
}
