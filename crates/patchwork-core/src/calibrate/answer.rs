//! What a calibration answers: the fitted parameters with their 95 %
//! intervals, the residuals, each built design's fit, the warnings.

use serde::{Deserialize, Serialize};

use super::parameters::Parameter;
use crate::material::Material;

/// One fitted parameter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fitted {
    pub parameter: Parameter,
    pub start: f64,
    pub value: f64,
    /// The 95 % interval; absent without more measured values than
    /// parameters.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interval95: Option<[f64; 2]>,
}

/// One measured value of the bare balloon against the calibrated model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Residual {
    pub pressure_kpa: f64,
    /// `length_mm`, `diameter_mm` or `volume_ml`.
    pub quantity: &'static str,
    pub measured: f64,
    pub predicted: f64,
    pub percent: f64,
}

/// A built design's measured centreline against the model, before and
/// after the calibration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BuiltFit {
    /// Its place in the data's `built` (from 0).
    pub index: usize,
    /// The measured centreline's length, its noise smoothed away (mm).
    pub measured_length_mm: f64,
    pub predicted_length_mm: f64,
    /// The tube's median radius, measured (when given) and by the
    /// calibrated model (mm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_radius_mm: Option<f64>,
    pub predicted_radius_mm: f64,
    /// The model's centreline against the measured one (RMS after the best
    /// rigid alignment, % of the measured length), from the starting
    /// materials and from the calibrated ones.
    pub shape_error_start_percent: f64,
    pub shape_error_percent: f64,
}

/// What a calibration found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Calibration {
    /// The calibrated balloon material, as `design --options` takes it.
    pub material: Material,
    /// The calibrated patch material.
    pub patch_material: Material,
    pub parameters: Vec<Fitted>,
    pub residuals: Vec<Residual>,
    pub built: Vec<BuiltFit>,
    /// RMS of the relative residuals (%).
    pub rms_percent: f64,
    pub warnings: Vec<String>,
    /// FE solves taken (each pressure and each built design counts; a
    /// built design's starting state too).
    pub solves: usize,
}
