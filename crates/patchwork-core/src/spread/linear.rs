//! The linear spread: the nominal design solved once, then each source at
//! its tolerance (in parallel, warm-started from the nominal state); each
//! centreline compared with the nominal at equal fractions of length.
//!
//! With dₖ the change of the centreline's samples at source k's tolerance
//! (after the best rigid alignment onto the nominal, n samples) and tₖ the
//! tip's move in the clamp's frame:
//! - spread RMS = √(Σₖ |dₖ|² / n) (independent sources, one σ each);
//! - worst case ≤ Σₖ |dₖ| / √n (every source at its tolerance the worst
//!   way: the triangle inequality's bound);
//! - tip: √(Σₖ |tₖ|²), and Σₖ |tₖ| at worst;
//! - expected shape error against the target: √(e₀² + spread²), e₀ the
//!   nominal's (the changes have mean zero to first order).

use super::answer::{Contributor, Spread};
use super::sources::Source;
use super::tolerances::Tolerances;
use crate::curve::{AlignedSamples, Curve, shape_error};
use crate::design::Design;
use crate::fe::{SimulateError, SimulateOptions, Simulation, simulate, simulate_from};
use crate::parallel::map_in_threads;

/// Samples of the centreline compared.
const SAMPLES: usize = 64;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpreadError {
    #[error("tolerances: {0}")]
    Tolerances(String),
    #[error("the design does not inflate: {0}")]
    Nominal(SimulateError),
    #[error("{label} at its tolerance: {reason}")]
    Moved { label: String, reason: String },
}

/// One source's change: the centreline's samples (mm, aligned) and the tip.
struct Change {
    samples_sq: f64,
    tip_mm: f64,
}

/// The spread of `design`'s centreline under `tolerances`, solved with
/// `options` on up to `threads` threads; against `target` where given.
pub fn linear_spread(
    design: &Design,
    target: Option<&Curve>,
    tolerances: &Tolerances,
    options: &SimulateOptions,
    threads: usize,
) -> Result<Spread, SpreadError> {
    tolerances.validate().map_err(SpreadError::Tolerances)?;
    let nominal = simulate(design, options).map_err(SpreadError::Nominal)?;
    let degenerate =
        |e: crate::CurveError| SpreadError::Nominal(SimulateError::Centreline(e.to_string()));
    let samples = nominal.centreline.resample(SAMPLES).map_err(degenerate)?;
    let sources = Source::all(design, tolerances);
    let changes = map_in_threads(&sources, threads, &|&source| {
        let (tolerance, _) = source.tolerance(tolerances);
        let moved = source.moved(design, tolerance);
        simulate_from(&moved, options, Some(&nominal))
            .map_err(|e| e.to_string())
            .and_then(|sim| change(&sim, &nominal, &samples))
            .map_err(|reason| SpreadError::Moved {
                label: source.label(),
                reason,
            })
    });
    let mut contributors = Vec::with_capacity(sources.len());
    for (source, change) in sources.into_iter().zip(changes) {
        let change = change?;
        let (tolerance, unit) = source.tolerance(tolerances);
        contributors.push(Contributor {
            source,
            label: source.label(),
            tolerance,
            unit: unit.into(),
            rms_mm: (change.samples_sq / SAMPLES as f64).sqrt(),
            tip_mm: change.tip_mm,
        });
    }
    contributors.sort_by(|a, b| b.rms_mm.total_cmp(&a.rms_mm));
    let nominal_error = target
        .map(|t| shape_error(&nominal.centreline, t, SAMPLES))
        .transpose()
        .map_err(degenerate)?
        .map(|e| e.percent_of_length);
    Ok(summary(contributors, nominal_error, target, &nominal))
}

/// The sources' shares added up.
fn summary(
    contributors: Vec<Contributor>,
    nominal_error: Option<f64>,
    target: Option<&Curve>,
    nominal: &Simulation,
) -> Spread {
    let rms_mm = contributors
        .iter()
        .map(|c| c.rms_mm.powi(2))
        .sum::<f64>()
        .sqrt();
    let length = target.map_or(nominal.centreline.length(), Curve::length);
    let rms_percent = 100.0 * rms_mm / length;
    Spread {
        rms_mm,
        rms_percent,
        worst_mm: contributors.iter().map(|c| c.rms_mm).sum(),
        tip_rms_mm: contributors
            .iter()
            .map(|c| c.tip_mm.powi(2))
            .sum::<f64>()
            .sqrt(),
        tip_worst_mm: contributors.iter().map(|c| c.tip_mm).sum(),
        nominal_shape_error_percent: nominal_error,
        expected_shape_error_percent: nominal_error.map(|e| e.hypot(rms_percent)),
        solves: contributors.len() + 1,
        contributors,
    }
}

/// How `sim` differs from `nominal`: Σ|dᵢ|² over the nominal's samples
/// after the best rigid alignment, and the tip's move unaligned.
fn change(sim: &Simulation, nominal: &Simulation, samples: &Curve) -> Result<Change, String> {
    let aligned = AlignedSamples::new(&sim.centreline, samples).map_err(|e| e.to_string())?;
    let samples_sq = aligned.residuals.iter().map(|r| r.norm_squared()).sum();
    let tip = |s: &Simulation| s.centreline.points().last().copied();
    let (Some(moved), Some(home)) = (tip(sim), tip(nominal)) else {
        return Err("no centreline".into());
    };
    Ok(Change {
        samples_sq,
        tip_mm: (moved - home).norm(),
    })
}
