//! Calibration: the balloon's material fitted to what a lab measured on its
//! own bare balloons inflated — the length (clamp to tip) and the diameter
//! at one or more pressures — by least squares on the FE model.
//!
//! The parameters fitted are chosen by the user ([`Parameter`]: the
//! modulus, the law's stiffening, the compressibility); the others keep the
//! starting material's values. The misfits are relative (predicted /
//! measured − 1), so lengths and diameters weigh alike. The answer states
//! each parameter's 95 % interval (from the residuals' scatter, Student's
//! t with m − n degrees of freedom), every residual, and warns where the
//! data cannot tell two parameters apart (|correlation| > 0.95).

mod fit;
mod model;
mod parameters;

use serde::{Deserialize, Serialize};

pub use parameters::Parameter;

use crate::design::Balloon;
use crate::material::Material;

/// Correlations above this (in magnitude) are reported: the data then
/// cannot tell the two parameters apart.
const CORRELATED: f64 = 0.95;

/// The bare balloon measured at one pressure: its length from the clamp to
/// the tip, its diameter across the middle (mid-wall), or both (mm).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Inflation {
    pub pressure_kpa: f64,
    pub length_mm: Option<f64>,
    pub diameter_mm: Option<f64>,
}

/// Why a calibration cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CalibrationError {
    #[error(
        "{measured} measured values cannot determine {parameters} parameters; measure more pressures or both length and diameter"
    )]
    TooFewData { measured: usize, parameters: usize },
    #[error("inflation {index}: {reason}")]
    Datum { index: usize, reason: String },
    #[error("the material has no parameter `{0}` to fit")]
    NoSuchParameter(&'static str),
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

/// One measured value against the calibrated model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Residual {
    pub pressure_kpa: f64,
    /// `length_mm` or `diameter_mm`.
    pub quantity: &'static str,
    pub measured: f64,
    pub predicted: f64,
    pub percent: f64,
}

/// What a calibration found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Calibration {
    /// The calibrated material, as `design --options` takes it.
    pub material: Material,
    pub parameters: Vec<Fitted>,
    pub residuals: Vec<Residual>,
    /// RMS of the relative residuals (%).
    pub rms_percent: f64,
    pub warnings: Vec<String>,
    /// FE solves of the whole bare balloon taken (each pressure counts).
    pub solves: usize,
}

/// Fits `fit` of `balloon.material` to `data`.
pub fn calibrate(
    balloon: &Balloon,
    data: &[Inflation],
    fit: &[Parameter],
) -> Result<Calibration, CalibrationError> {
    check(data)?;
    let measured = data
        .iter()
        .map(|d| usize::from(d.length_mm.is_some()) + usize::from(d.diameter_mm.is_some()))
        .sum::<usize>();
    if measured < fit.len() {
        return Err(CalibrationError::TooFewData {
            measured,
            parameters: fit.len(),
        });
    }
    let start: Vec<f64> = fit
        .iter()
        .map(|p| {
            p.get(&balloon.material)
                .ok_or(CalibrationError::NoSuchParameter(p.name()))
        })
        .collect::<Result<_, _>>()?;
    let material_at = |log: &[f64]| {
        fit.iter()
            .zip(log)
            .fold(balloon.material.clone(), |m, (p, v)| p.set(&m, v.exp()))
    };
    let with = |log: &[f64]| Balloon {
        material: material_at(log),
        ..balloon.clone()
    };
    let residuals = |log: &[f64]| {
        let b = with(log);
        b.material.validate().ok()?;
        model::predict(&b, data).map(|p| model::residuals(data, &p))
    };
    let log_start: Vec<f64> = start.iter().map(|v| v.ln()).collect();
    let result =
        fit::levenberg_marquardt(log_start, &residuals).ok_or(CalibrationError::NoStart)?;
    let material = material_at(&result.log_values);
    let predicted =
        model::predict(&with(&result.log_values), data).ok_or(CalibrationError::NoStart)?;
    Ok(report(fit, &start, &result, material, data, &predicted))
}

fn check(data: &[Inflation]) -> Result<(), CalibrationError> {
    for (index, d) in data.iter().enumerate() {
        let bad = |reason: &str| CalibrationError::Datum {
            index,
            reason: reason.into(),
        };
        if !(d.pressure_kpa.is_finite() && d.pressure_kpa > 0.0 && d.pressure_kpa <= 1000.0) {
            return Err(bad("pressure_kpa must be above 0 and at most 1000"));
        }
        for value in [d.length_mm, d.diameter_mm].into_iter().flatten() {
            if !(value.is_finite() && value > 0.0 && value < 1e5) {
                return Err(bad("lengths and diameters must be positive (mm)"));
            }
        }
        if d.length_mm.is_none() && d.diameter_mm.is_none() {
            return Err(bad("measures neither the length nor the diameter"));
        }
    }
    Ok(())
}

fn report(
    fit: &[Parameter],
    start: &[f64],
    result: &fit::Fit,
    material: Material,
    data: &[Inflation],
    predicted: &[model::Predicted],
) -> Calibration {
    let t = fit::t95(result.degrees_of_freedom);
    let parameters = fit
        .iter()
        .enumerate()
        .map(|(i, &parameter)| {
            let log = result.log_values[i];
            Fitted {
                parameter,
                start: start[i],
                value: log.exp(),
                interval95: result
                    .log_sd
                    .as_ref()
                    .filter(|_| t.is_finite())
                    .map(|sd| [(log - t * sd[i]).exp(), (log + t * sd[i]).exp()]),
            }
        })
        .collect();
    let mut residuals = Vec::new();
    for (d, p) in data.iter().zip(predicted) {
        let mut push = |quantity, measured: Option<f64>, predicted: f64| {
            if let Some(measured) = measured {
                residuals.push(Residual {
                    pressure_kpa: d.pressure_kpa,
                    quantity,
                    measured,
                    predicted,
                    percent: 100.0 * (predicted / measured - 1.0),
                });
            }
        };
        push("length_mm", d.length_mm, p.length_mm);
        push("diameter_mm", d.diameter_mm, p.diameter_mm);
    }
    let rms = (result.residuals.iter().map(|r| r * r).sum::<f64>()
        / result.residuals.len().max(1) as f64)
        .sqrt();
    Calibration {
        material,
        parameters,
        residuals,
        rms_percent: 100.0 * rms,
        warnings: warnings(fit, result),
        solves: result.evaluations * data.len(),
    }
}

fn warnings(fit: &[Parameter], result: &fit::Fit) -> Vec<String> {
    let mut out = Vec::new();
    if result.degrees_of_freedom == 0 {
        out.push(
            "as many measured values as parameters: the fit is exact and has no intervals; measure more"
                .to_string(),
        );
    }
    if let Some(c) = &result.correlation {
        for a in 0..fit.len() {
            for b in a + 1..fit.len() {
                if c[(a, b)].abs() > CORRELATED {
                    out.push(format!(
                        "the data cannot tell {} and {} apart (correlation {:.3}): measure more pressures, or fix one",
                        fit[a].name(),
                        fit[b].name(),
                        c[(a, b)]
                    ));
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests;
