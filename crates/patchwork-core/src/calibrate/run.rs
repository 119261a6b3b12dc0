//! A calibration from start to answer: the measurements checked, the
//! problem set up, Levenberg–Marquardt, the report.

use super::answer::Calibration;
use super::data::Measurements;
use super::error::CalibrationError;
use super::parameters::{Materials, Parameter};
use super::problem::Problem;
use super::{fit, report};
use crate::design::Balloon;
use crate::material::Material;

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
