//! Calibration: the balloon's material (and the patches') fitted to what a
//! lab measured on its own balloons, by least squares on the FE model:
//! - the bare balloon inflated: its length (clamp to tip) and diameter at
//!   one or more pressures ([`Inflation`]);
//! - the bare balloon's pressure–volume curve ([`PressureVolume`]);
//! - balloons built from designs, their centrelines measured inflated
//!   ([`Built`]): the only data that tells the patch's stiffness.
//!
//! The parameters fitted are chosen by the user ([`Parameter`]: the
//! modulus, the law's stiffening, the compressibility, the patch's
//! modulus); the others keep the starting materials' values. The misfits
//! are relative (predicted / measured − 1; a built centreline's distances
//! over its length), so every kind of value weighs alike. The answer states
//! each parameter's 95 % interval (from the residuals' scatter, Student's
//! t with m − n degrees of freedom), every residual, and warns where the
//! data cannot tell two parameters apart (|correlation| > 0.95).

mod built;
mod data;
mod fit;
mod model;
mod parameters;
mod problem;
mod report;

use serde::{Deserialize, Serialize};

pub use data::{Built, Inflation, Measurements, PressureVolume};
pub use parameters::{Materials, Parameter};

use crate::design::Balloon;
use crate::material::Material;
use problem::Problem;

/// Why a calibration cannot be made.
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
}

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

/// Fits `fit` of the materials — the balloon's, from `balloon`, and the
/// patches', `patch` — to `data`. The bare balloon's measurements are of
/// `balloon`'s geometry; a built design keeps its own.
pub fn calibrate(
    balloon: &Balloon,
    patch: &Material,
    data: &Measurements,
    fit: &[Parameter],
) -> Result<Calibration, CalibrationError> {
    data.check()?;
    let start = Materials {
        balloon: balloon.material.clone(),
        patch: patch.clone(),
    };
    let problem = Problem::new(balloon, start, data, fit)?;
    let log_start = problem.log_start();
    let residuals = |log: &[f64]| problem.residuals(&problem.materials_at(log));
    let result =
        fit::levenberg_marquardt(log_start, &residuals).ok_or(CalibrationError::NoStart)?;
    Ok(report::report(&problem, &result))
}

#[cfg(test)]
mod tests;
