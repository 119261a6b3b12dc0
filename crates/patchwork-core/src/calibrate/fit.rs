//! Levenberg–Marquardt on the logarithms of the parameters (so they stay
//! positive and their steps are relative), the Jacobian by forward
//! differences (its columns in parallel); then the parameters' covariance σ² (JᵀJ)⁻¹ with
//! σ² = RSS / (m − n), their 95 % intervals from Student's t, and their
//! correlations.
//!
//! The damping follows the step's gain ratio after an accepted step
//! (Nielsen's rule, as the design refine's solver) and grows fourfold after
//! a refused one. The fit stops where going on changes nothing a
//! measurement could see: an accepted step that lowers |r|² by less than
//! [`MIN_GAIN`] of it, or a step that would move no parameter by more than
//! [`MIN_STEP`] (relative; not evaluated).

use nalgebra::{DMatrix, DVector};

use crate::least_squares::levenberg_marquardt::{damping_factor, gain_ratio};
use crate::parallel::map_in_threads;

/// The residuals at a point; none where the model has no answer.
pub type ResidualFn<'a> = dyn Fn(&[f64]) -> Option<Vec<f64>> + Sync + 'a;

/// Relative step of the forward differences (in log space).
const STEP: f64 = 1e-3;
const MAX_ITERATIONS: usize = 30;
/// A step that lowers |r|² by less than this fraction of it ends the fit:
/// the parameters then move by far less than their intervals' width.
const MIN_GAIN: f64 = 1e-6;
/// A step (in the logarithms) that moves every parameter by less than this
/// ends the fit: 0.001 %, below what the FE solves resolve.
const MIN_STEP: f64 = 1e-5;

/// A least-squares fit of `n` log-parameters.
pub struct Fit {
    pub log_values: Vec<f64>,
    pub residuals: Vec<f64>,
    /// The residuals at the start.
    pub start_residuals: Vec<f64>,
    /// Standard deviations of the log-parameters; none without more data
    /// than parameters.
    pub log_sd: Option<Vec<f64>>,
    pub correlation: Option<DMatrix<f64>>,
    pub degrees_of_freedom: usize,
    pub evaluations: usize,
}

/// Called after the start, before each iteration and at the end (unless no
/// evaluation came since the last call) with the point, its residuals and
/// the evaluations so far; answers whether to go on.
pub type StepFn<'a> = dyn FnMut(&[f64], &[f64], usize) -> bool + 'a;

/// Why a fit has no answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoFit {
    /// The model has no answer at the start.
    NoStart,
    /// `watch` said stop.
    Stopped,
}

/// Minimises |r(x)|² from `start`; `r` answers none where the model has no
/// answer (a step there is refused). `watch` sees every iteration and
/// can stop the fit.
pub fn levenberg_marquardt(
    start: Vec<f64>,
    r: &ResidualFn,
    watch: &mut StepFn,
) -> Result<Fit, NoFit> {
    let mut x = start;
    let mut rx = r(&x).ok_or(NoFit::NoStart)?;
    let start_residuals = rx.clone();
    let mut evaluations = 1;
    let mut damping = 1e-3;
    let norm = |v: &[f64]| v.iter().map(|e| e * e).sum::<f64>().sqrt();
    let mut error = norm(&rx);
    let mut jacobian = jacobian_at(&x, &rx, r, &mut evaluations).ok_or(NoFit::NoStart)?;
    let mut reported = evaluations;
    for _ in 0..MAX_ITERATIONS {
        if !watch(&x, &rx, evaluations) {
            return Err(NoFit::Stopped);
        }
        reported = evaluations;
        let residual = DVector::from_column_slice(&rx);
        let jtj = jacobian.transpose() * &jacobian;
        let mut a = jtj.clone();
        for i in 0..x.len() {
            a[(i, i)] += damping * jtj[(i, i)].max(1e-12);
        }
        let g = jacobian.transpose() * &residual;
        let Some(step) = a.lu().solve(&(-g)).filter(|s| s.amax() >= MIN_STEP) else {
            break;
        };
        let trial: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
        evaluations += 1;
        match r(&trial).map(|rt| (norm(&rt), rt)) {
            Some((trial_error, rt)) if trial_error < error => {
                let predicted = (&jacobian * &step + residual).norm();
                let ratio = gain_ratio(error, trial_error, predicted);
                let gain = error * error - trial_error * trial_error;
                (x, rx, error) = (trial, rt, trial_error);
                damping = (damping * damping_factor(ratio)).max(1e-9);
                if gain < MIN_GAIN * error * error {
                    break;
                }
                match jacobian_at(&x, &rx, r, &mut evaluations) {
                    Some(j) => jacobian = j,
                    None => break,
                }
            }
            _ => {
                damping *= 4.0;
                if damping > 1e8 {
                    break;
                }
            }
        }
    }
    // The answer, unless the last report was of it already.
    if evaluations > reported && !watch(&x, &rx, evaluations) {
        return Err(NoFit::Stopped);
    }
    let mut fit = statistics(x, rx, &jacobian, evaluations);
    fit.start_residuals = start_residuals;
    Ok(fit)
}

fn jacobian_at(
    x: &[f64],
    rx: &[f64],
    r: &ResidualFn,
    evaluations: &mut usize,
) -> Option<DMatrix<f64>> {
    let threads = crate::available_cores();
    let columns: Vec<usize> = (0..x.len()).collect();
    let found = map_in_threads(&columns, threads, &|&k| {
        // Forward, or backward where the model has no answer forward (the
        // balloon past its limit point).
        let mut tries = 0;
        let column = [STEP, -STEP].into_iter().find_map(|h| {
            let mut xk = x.to_vec();
            xk[k] += h;
            tries += 1;
            r(&xk).map(|rk| (h, rk))
        });
        (column, tries)
    });
    let mut j = DMatrix::zeros(rx.len(), x.len());
    for (k, (column, tries)) in found.into_iter().enumerate() {
        *evaluations += tries;
        let (h, rk) = column?;
        for i in 0..rx.len() {
            j[(i, k)] = (rk[i] - rx[i]) / h;
        }
    }
    Some(j)
}

fn statistics(x: Vec<f64>, rx: Vec<f64>, j: &DMatrix<f64>, evaluations: usize) -> Fit {
    let (m, n) = (rx.len(), x.len());
    let dof = m.saturating_sub(n);
    let rss: f64 = rx.iter().map(|e| e * e).sum();
    let covariance = (dof > 0)
        .then(|| (j.transpose() * j).try_inverse())
        .flatten()
        .map(|inverse| inverse * (rss / dof as f64));
    let log_sd = covariance.as_ref().map(|c| {
        (0..n)
            .map(|i| c[(i, i)].max(0.0).sqrt())
            .collect::<Vec<f64>>()
    });
    let correlation = covariance.as_ref().map(|c| {
        DMatrix::from_fn(n, n, |a, b| {
            c[(a, b)] / (c[(a, a)] * c[(b, b)]).sqrt().max(1e-300)
        })
    });
    Fit {
        log_values: x,
        residuals: rx,
        start_residuals: Vec::new(),
        log_sd,
        correlation,
        degrees_of_freedom: dof,
        evaluations,
    }
}

/// Student's t two-sided 95 % quantile for `dof` degrees of freedom.
pub fn t95(dof: usize) -> f64 {
    const TABLE: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160,
        2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056,
        2.052, 2.048, 2.045, 2.042,
    ];
    match dof {
        0 => f64::INFINITY,
        1..=30 => TABLE[dof - 1],
        _ => 1.96,
    }
}
