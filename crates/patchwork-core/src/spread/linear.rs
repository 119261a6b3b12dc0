//! The linear spread: each source's change of the centreline at its
//! tolerance. Every source is first linearised at the nominal state
//! (`fe::sensitivity`: one factorisation of the tangent, a substitution per
//! source); those whose linearised change is at least [`SOLVED_FRACTION`]
//! of the largest change found are then solved — a Newton solve warm-started
//! from the nominal state, to a relative residual of `SOURCE_TOLERANCE` (a
//! secant) — and the largest is taken again from the solved, until every
//! source above the fraction is solved. The linearised response alone
//! misjudges the large sources: it overstates a patch's placement around
//! the tube up to sixfold and its angle up to twofold (the tube's soft
//! twist answering a first-order force that its geometric stiffening holds
//! back), and understates its placement along it by up to a third; a small
//! source's share of the sum in quadrature is small, and so is its error's.
//! On seven draft designs of the suite (`examples/spread_linearised.rs`,
//! docs/studies.md "The spread's solves"), 3 to 10 of 13 to 28 sources
//! were solved, the RMS spread came within 1.1 % of every source's solve
//! and the three largest contributors were the same. Each centreline is compared with the
//! nominal at equal fractions of length.
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

use super::answer::{Contributor, Estimate, Spread};
use super::change::{Change, Nominal, SAMPLES, change_of};
use super::monte_carlo::monte_carlo;
use super::sources::Source;
use super::tolerances::Tolerances;
use crate::curve::{Curve, shape_error};
use crate::design::Design;
use crate::fe::newton::PatternCache;
use crate::fe::sensitivity::linearised_centrelines;
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

/// A source whose linearised change is at least this fraction of the
/// largest change (RMS) is solved; a smaller one keeps its linearised change.
pub const SOLVED_FRACTION: f64 = 0.5;

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
    let (mut changes, linearised) = linearised_changes(nominal, &moved, &samples, threads);
    let mut solves = usize::from(linearised);
    while let Some(pending) = to_solve(&changes) {
        let solved = map_in_threads(&pending, threads, &|&k| {
            solved_change(nominal, &moved[k], &samples)
        });
        for (k, change) in pending.into_iter().zip(solved) {
            let change = change.map_err(|reason| SpreadError::Moved {
                label: sources[k].label(),
                reason,
            })?;
            changes[k] = Some((change, Estimate::Solved));
            solves += 1;
        }
    }
    let mut contributors = Vec::with_capacity(sources.len());
    let mut band_sq = vec![0.0; SAMPLES];
    for (source, found) in sources.into_iter().zip(changes) {
        let (change, estimate) = found.expect("every source found");
        for (sum, d) in band_sq.iter_mut().zip(&change.each_sq) {
            *sum += d;
        }
        let (tolerance, unit) = source.tolerance(tolerances);
        contributors.push(Contributor {
            source,
            label: source.label(),
            tolerance,
            unit: unit.into(),
            rms_mm: rms(&change),
            tip_mm: change.tip_mm,
            estimate,
        });
    }
    contributors.sort_by(|a, b| b.rms_mm.total_cmp(&a.rms_mm));
    let mut spread = summary(contributors, against, solves);
    spread.band_mm = band_sq.iter().map(|d| d.sqrt()).collect();
    Ok(spread)
}

/// A source's change found so far, and how.
type Found = Option<(Change, Estimate)>;

/// Each moved design's linearised change (none where it has none: the
/// nominal state unstable, or the change leaving a material's domain), and
/// whether the linearisation ran (a factorisation, counted as a solve).
fn linearised_changes(
    nominal: &Nominal,
    moved: &[Design],
    samples: &Curve,
    threads: usize,
) -> (Vec<Found>, bool) {
    let (design, simulation) = (nominal.design, nominal.simulation);
    let curves = linearised_centrelines(
        design,
        simulation,
        nominal.options,
        moved,
        threads,
        nominal.patterns,
    );
    let Some(curves) = curves.filter(|_| !moved.is_empty()) else {
        return (moved.iter().map(|_| None).collect(), false);
    };
    let changes = curves
        .into_iter()
        .map(|curve| {
            let change = change_of(&curve?, &simulation.centreline, samples).ok()?;
            Some((change, Estimate::Linearised))
        })
        .collect();
    (changes, true)
}

/// The sources to solve next: those without a change, and those linearised
/// at `SOLVED_FRACTION` of the largest change or more; none when no source
/// is left to solve.
fn to_solve(changes: &[Found]) -> Option<Vec<usize>> {
    let largest = changes
        .iter()
        .flatten()
        .map(|(c, _)| rms(c))
        .fold(0.0, f64::max);
    let pending: Vec<usize> = (0..changes.len())
        .filter(|&k| match &changes[k] {
            None => true,
            Some((c, Estimate::Linearised)) => rms(c) >= SOLVED_FRACTION * largest,
            Some((_, Estimate::Solved)) => false,
        })
        .collect();
    (!pending.is_empty()).then_some(pending)
}

/// `moved`'s change by a Newton solve warm-started from the nominal state.
fn solved_change(nominal: &Nominal, moved: &Design, samples: &Curve) -> Result<Change, String> {
    let options = nominal.source_options();
    simulate_with(moved, &options, Some(nominal.simulation), nominal.patterns)
        .map_err(|e| e.to_string())
        .and_then(|sim| change_of(&sim.centreline, &nominal.simulation.centreline, samples))
}

/// A change's RMS over the samples (mm).
fn rms(change: &Change) -> f64 {
    (change.samples_sq / SAMPLES as f64).sqrt()
}

/// The sources' shares added up, found with `solves` FE solves.
fn summary(contributors: Vec<Contributor>, against: &Against, solves: usize) -> Spread {
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
        solves,
        contributors,
        monte_carlo: None,
        band_mm: Vec::new(),
    }
}
