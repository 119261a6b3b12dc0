//! The linear spread: each source at its tolerance, its centreline by a
//! Newton solve warm-started from the nominal state, to a relative residual
//! of `SOURCE_TOLERANCE` (a secant: at these
//! tolerances the linearised response of `fe::sensitivity` overstates a
//! patch's placement around the tube two- to threefold, the tube's soft
//! twist answering a first-order force that its geometric stiffening
//! holds back); each centreline compared with the nominal at equal
//! fractions of length.
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

use std::sync::atomic::AtomicBool;

use super::answer::{Contributor, Spread};
use super::change::{Nominal, SAMPLES, change_of};
use super::monte_carlo::monte_carlo;
use super::sources::Source;
use super::tolerances::Tolerances;
use crate::curve::{Curve, shape_error};
use crate::design::Design;
use crate::fe::newton::PatternCache;
use crate::fe::{SimulateError, SimulateOptions, Simulation, simulate, simulate_with};
use crate::parallel::map_in_threads;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpreadError {
    #[error("tolerances: {0}")]
    Tolerances(String),
    #[error("the design does not inflate: {0}")]
    Nominal(SimulateError),
    #[error("{label} at its tolerance: {reason}")]
    Moved { label: String, reason: String },
}

/// What the spread is measured against: the length its percentages are of,
/// and the nominal design's shape error against the target, if any.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Against {
    pub length_mm: f64,
    pub nominal_shape_error_percent: Option<f64>,
}

impl Against {
    /// `target` (the nominal's shape error measured against it) or, without
    /// one, the nominal centreline's own length.
    pub fn target(nominal: &Simulation, target: Option<&Curve>) -> Result<Against, SpreadError> {
        let nominal_shape_error_percent = target
            .map(|t| shape_error(&nominal.centreline, t, SAMPLES))
            .transpose()
            .map_err(degenerate)?
            .map(|e| e.percent_of_length);
        Ok(Against {
            length_mm: target.map_or(nominal.centreline.length(), Curve::length),
            nominal_shape_error_percent,
        })
    }
}

fn degenerate(e: crate::CurveError) -> SpreadError {
    SpreadError::Nominal(SimulateError::Centreline(e.to_string()))
}

/// A Monte-Carlo check to run with the spread: its samples and seed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Check {
    pub samples: usize,
    pub seed: u64,
}

/// The spread of `design`'s centreline under `tolerances`, solved with
/// `options` on up to `threads` threads; against `target` where given; with
/// the Monte-Carlo `check` where asked.
pub fn linear_spread(
    design: &Design,
    target: Option<&Curve>,
    tolerances: &Tolerances,
    options: &SimulateOptions,
    threads: usize,
    check: Option<Check>,
) -> Result<Spread, SpreadError> {
    tolerances.validate().map_err(SpreadError::Tolerances)?;
    let nominal = simulate(design, options).map_err(SpreadError::Nominal)?;
    let against = Against::target(&nominal, target)?;
    let patterns = PatternCache::default();
    let nominal = Nominal {
        design,
        simulation: &nominal,
        options,
        patterns: &patterns,
    };
    let mut spread = spread_of(&nominal, &against, tolerances, threads)?;
    spread.solves += 1;
    if let Some(Check { samples, seed }) = check {
        let never = AtomicBool::new(false);
        let draw = (samples, seed);
        let sampled = monte_carlo(&nominal, &spread, tolerances, draw, threads, &never);
        spread.solves += samples;
        spread.monte_carlo = Some(sampled);
    }
    Ok(spread)
}

/// The spread of a design whose nominal state is known (a design run's
/// verified simulation), on up to `threads` threads.
pub fn spread_of(
    nominal: &Nominal,
    against: &Against,
    tolerances: &Tolerances,
    threads: usize,
) -> Result<Spread, SpreadError> {
    tolerances.validate().map_err(SpreadError::Tolerances)?;
    let samples = nominal
        .simulation
        .centreline
        .resample(SAMPLES)
        .map_err(degenerate)?;
    let sources = Source::all(nominal.design, tolerances);
    let moved: Vec<Design> = sources
        .iter()
        .map(|s| s.moved(nominal.design, s.tolerance(tolerances).0))
        .collect();
    let options = nominal.source_options();
    let changes = map_in_threads(&moved, threads, &|design| {
        simulate_with(design, &options, Some(nominal.simulation), nominal.patterns)
            .map_err(|e| e.to_string())
            .and_then(|moved| {
                change_of(&moved.centreline, &nominal.simulation.centreline, &samples)
            })
    });
    let mut contributors = Vec::with_capacity(sources.len());
    let mut band_sq = vec![0.0; SAMPLES];
    for (source, change) in sources.into_iter().zip(changes) {
        let change = change.map_err(|reason| SpreadError::Moved {
            label: source.label(),
            reason,
        })?;
        for (sum, d) in band_sq.iter_mut().zip(&change.each_sq) {
            *sum += d;
        }
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
    let mut spread = summary(contributors, against);
    spread.band_mm = band_sq.iter().map(|d| d.sqrt()).collect();
    Ok(spread)
}

/// The sources' shares added up.
fn summary(contributors: Vec<Contributor>, against: &Against) -> Spread {
    let rms_mm = contributors
        .iter()
        .map(|c| c.rms_mm.powi(2))
        .sum::<f64>()
        .sqrt();
    let rms_percent = 100.0 * rms_mm / against.length_mm;
    let nominal_error = against.nominal_shape_error_percent;
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
        solves: contributors.len(),
        contributors,
        monte_carlo: None,
        band_mm: Vec::new(),
    }
}
