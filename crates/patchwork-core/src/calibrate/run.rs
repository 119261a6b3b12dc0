//! A calibration from start to answer: the measurements checked, the
//! problem set up, Levenberg–Marquardt, the report. A caller that runs it
//! for someone else (the service) watches it: a progress report after each
//! iteration, and a flag that stops it.

use std::sync::atomic::{AtomicBool, Ordering};

use serde::Serialize;

use super::answer::Calibration;
use super::data::Measurements;
use super::error::CalibrationError;
use super::fit::{self, NoFit};
use super::parameters::{Materials, Parameter};
use super::problem::{Problem, check_fit};
use super::report;
use crate::design::Balloon;
use crate::material::Material;

/// Where a running calibration stands, after its start and each iteration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CalibrationProgress {
    /// Levenberg–Marquardt iterations done (0: the start).
    pub iteration: usize,
    /// FE solves taken so far.
    pub solves: usize,
    /// RMS of the relative residuals at the current values (%).
    pub rms_percent: f64,
    /// The current values of the parameters fitted, in the order asked.
    pub values: Vec<(Parameter, f64)>,
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
    calibrate_watched(
        balloon,
        patch,
        data,
        fit,
        &AtomicBool::new(false),
        &mut |_| {},
    )
}

/// Every check [`calibrate`] makes before its first solve: the data's
/// values, and `fit` against the data and the materials.
pub fn check(
    balloon: &Material,
    patch: &Material,
    data: &Measurements,
    fit: &[Parameter],
) -> Result<(), CalibrationError> {
    data.check()?;
    let start = Materials {
        balloon: balloon.clone(),
        patch: patch.clone(),
    };
    check_fit(&start, data, fit).map(|_| ())
}

/// [`calibrate`], reporting its progress to `progress` and stopping with
/// [`CalibrationError::Cancelled`] soon after `cancel` is set (at the next
/// residual evaluation: a few FE solves).
pub fn calibrate_watched(
    balloon: &Balloon,
    patch: &Material,
    data: &Measurements,
    fit: &[Parameter],
    cancel: &AtomicBool,
    progress: &mut dyn FnMut(&CalibrationProgress),
) -> Result<Calibration, CalibrationError> {
    data.check()?;
    let start = Materials {
        balloon: balloon.material.clone(),
        patch: patch.clone(),
    };
    let problem = Problem::new(balloon, start, data, fit)?;
    let log_start = problem.log_start();
    let stopped = || cancel.load(Ordering::Relaxed);
    let residuals = |log: &[f64]| {
        (!stopped())
            .then(|| problem.residuals(&problem.materials_at(log)))
            .flatten()
    };
    let mut iteration = 0;
    let mut watch = |log: &[f64], r: &[f64], evaluations: usize| {
        let materials = problem.materials_at(log);
        progress(&CalibrationProgress {
            iteration,
            solves: problem.solves(evaluations),
            rms_percent: report::rms_percent(r),
            values: fit
                .iter()
                .filter_map(|&p| Some((p, p.value(&materials)?)))
                .collect(),
        });
        iteration += 1;
        !stopped()
    };
    match fit::levenberg_marquardt(log_start, &residuals, &mut watch) {
        Ok(result) => Ok(report::report(&problem, &result)),
        Err(_) if stopped() => Err(CalibrationError::Cancelled),
        Err(NoFit::NoStart | NoFit::Stopped) => Err(CalibrationError::NoStart),
    }
}
