//! A calibration's answer: the fitted parameters with their 95 % intervals,
//! every bare-balloon residual, each built design's shape error before and
//! after, and the warnings a user must read.

use super::answer::{BuiltFit, Calibration, Fitted, Residual};
use super::built::shape_error_percent;
use super::fit::{self, Fit};
use super::problem::{Predictions, Problem};

/// Correlations above this (in magnitude) are reported: the data then
/// cannot tell the two parameters apart.
const CORRELATED: f64 = 0.95;

pub fn report(problem: &Problem, result: &Fit) -> Calibration {
    let materials = problem.materials_at(&result.log_values);
    let predictions = problem.predict(&materials);
    let t = fit::t95(result.degrees_of_freedom);
    let parameters = problem
        .fit
        .iter()
        .enumerate()
        .map(|(i, &parameter)| {
            let log = result.log_values[i];
            Fitted {
                parameter,
                start: parameter.value(&problem.start).unwrap_or(f64::NAN),
                value: log.exp(),
                interval95: result
                    .log_sd
                    .as_ref()
                    .filter(|_| t.is_finite())
                    .map(|sd| [(log - t * sd[i]).exp(), (log + t * sd[i]).exp()]),
            }
        })
        .collect();
    let rms_percent = rms_percent(&result.residuals);
    let residuals = predictions
        .as_ref()
        .map_or_else(Vec::new, |p| bare_residuals(problem, p));
    Calibration {
        material: materials.balloon,
        patch_material: materials.patch,
        parameters,
        warnings: warnings(problem, result, rms_percent, &residuals),
        residuals,
        built: predictions
            .as_ref()
            .map_or_else(Vec::new, |p| built_fits(problem, result, p)),
        rms_percent,
        solves: problem.solves(result.evaluations),
    }
}

/// RMS of relative residuals, in %.
pub fn rms_percent(residuals: &[f64]) -> f64 {
    100.0 * (residuals.iter().map(|r| r * r).sum::<f64>() / residuals.len().max(1) as f64).sqrt()
}

fn bare_residuals(problem: &Problem, predictions: &Predictions) -> Vec<Residual> {
    let mut out = Vec::new();
    let mut push = |pressure_kpa, quantity, measured: Option<f64>, predicted: f64| {
        if let Some(measured) = measured {
            out.push(Residual {
                pressure_kpa,
                quantity,
                measured,
                predicted,
                percent: 100.0 * (predicted / measured - 1.0),
            });
        }
    };
    for d in &problem.data.inflation {
        let p = problem.bare_at(predictions, d.pressure_kpa);
        push(d.pressure_kpa, "length_mm", d.length_mm, p.length_mm);
        push(d.pressure_kpa, "diameter_mm", d.diameter_mm, p.diameter_mm);
    }
    for &i in &problem.pressure_volume.0 {
        let d = &problem.data.pressure_volume[i];
        let p = problem.bare_at(predictions, d.pressure_kpa);
        push(d.pressure_kpa, "volume_ml", Some(d.volume_ml), p.volume_ml);
    }
    out
}

fn built_fits(problem: &Problem, result: &Fit, predictions: &Predictions) -> Vec<BuiltFit> {
    problem
        .built
        .iter()
        .zip(&predictions.built)
        .enumerate()
        .map(|(index, (b, predicted))| {
            let range = problem.built_range(index);
            BuiltFit {
                index,
                measured_length_mm: b.length_mm(),
                predicted_length_mm: predicted.centreline.length(),
                measured_radius_mm: b.radius_mm,
                predicted_radius_mm: predicted.radius_mm,
                shape_error_start_percent: shape_error_percent(
                    result.start_residuals.get(range.clone()).unwrap_or(&[]),
                ),
                shape_error_percent: shape_error_percent(
                    result.residuals.get(range).unwrap_or(&[]),
                ),
            }
        })
        .collect()
}

/// A fit whose residuals' RMS is above this (%) does not describe the
/// data: the law, the parameters fitted or a measurement is wrong.
const POOR_FIT_PERCENT: f64 = 3.0;

/// What the user must read: a poor fit (`rms` %, with the bare
/// `residuals`), an exact one, P–V points left out, intervals from
/// centrelines, parameters the data cannot tell apart.
fn warnings(problem: &Problem, result: &Fit, rms: f64, residuals: &[Residual]) -> Vec<String> {
    let mut out = Vec::new();
    let fit = &problem.fit;
    if rms > POOR_FIT_PERCENT {
        let worst = residuals
            .iter()
            .max_by(|a, b| a.percent.abs().total_cmp(&b.percent.abs()))
            .map_or(String::new(), |r| {
                format!(
                    "; the largest misfit is {} at {} kPa ({:+.1} %)",
                    r.quantity, r.pressure_kpa, r.percent
                )
            });
        out.push(format!(
            "the model fits these data only to {rms:.1} % RMS{worst}: check the measurements, fit more parameters, or choose another law"
        ));
    }
    if result.degrees_of_freedom == 0 {
        out.push(
            "as many measured values as parameters: the fit is exact and has no intervals; measure more"
                .to_string(),
        );
    }
    let left_out = &problem.pressure_volume.1;
    if !left_out.is_empty() {
        let points: Vec<String> = left_out
            .iter()
            .map(|&i| {
                let d = &problem.data.pressure_volume[i];
                format!("{} kPa at {} mL", d.pressure_kpa, d.volume_ml)
            })
            .collect();
        out.push(format!(
            "{} pressure–volume point(s) not fitted: a larger volume holds the same pressure or less (past the peak, where a bulge forms and runs along the balloon): {}",
            left_out.len(),
            points.join("; ")
        ));
    }
    if !problem.built.is_empty() && result.log_sd.is_some() {
        out.push(format!(
            "the intervals count a built centreline's {} samples as independent; neighbouring samples' misfits are not, so the intervals are narrower than the data support",
            super::data::SAMPLES
        ));
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
