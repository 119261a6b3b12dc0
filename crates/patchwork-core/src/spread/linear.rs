//! The linear spread: each source's change of the centreline at its
//! tolerance, source by source, each on its nominal state (`Models`: the
//! balloon's sources on one, the patches' on the same or a coarser one).
//! Every source is first linearised at its nominal state
//! (`fe::sensitivity`: one factorisation of the tangent, a substitution per
//! source); the large ones are then solved both ways, in rounds
//! (`rounds.rs`), and the balloon's sources that act as one together
//! (`balloon.rs`). The linearised response alone misjudges the large
//! sources: it overstates a patch's placement around the tube up to
//! sixfold and its angle up to twofold (the tube's soft twist answering a
//! first-order force that its geometric stiffening holds back), and
//! understates its placement along it by up to a third; a small source's
//! share of the sum in quadrature is small, and so is its error's. On
//! seven draft designs of the suite (`examples/spread_linearised.rs`,
//! docs/studies.md "The spread's solves"), 3 to 10 of 13 to 28 sources
//! were solved, the RMS spread came within 1.1 % of every source's solve
//! and the three largest contributors were the same. Each centreline is
//! compared with the nominal at equal fractions of length.
//!
//! A source solved both ways is read to second order (`change.rs`): its
//! odd part a and even part b give E|d|² = |a|² + 3|b|² for a normal error
//! of one tolerance, and a mean move b. One way only (one solve at
//! +tolerance) understates a sampled spread by the even part: on five
//! draft designs, 200 samples each, the sampled RMS was 1.01–1.26 times
//! the spread solved one way and 0.96–1.17 times this one
//! (`examples/spread_both_ways.rs`, docs/studies.md "The spread's
//! solves").
//!
//! With Dₖ = E|dₖ|² summed over the n samples of the centreline (after the
//! best rigid alignment onto the nominal), bₖ source k's mean move at each
//! sample, Tₖ and tₖ the same for the tip (in the clamp's frame):
//! - spread RMS = √((Σₖ Dₖ − Σₖ |bₖ|² + |Σₖ bₖ|²) / n) (independent
//!   sources, one σ each: their mean moves add as vectors);
//! - worst case ≤ Σₖ √(Dₖ / n) (every source at its tolerance the worst
//!   way: the triangle inequality's bound);
//! - tip: √(Σₖ Tₖ − Σₖ |tₖ|² + |Σₖ tₖ|²), and Σₖ √Tₖ at worst;
//! - the expected centreline's offset from the nominal: √(|Σₖ bₖ|² / n);
//! - expected shape error against the target: √(e₀² + spread²), e₀ the
//!   nominal's (which leaves out how the mean move lines up with e₀'s
//!   residuals).

use std::sync::atomic::AtomicBool;

use super::answer::{Contributor, Estimate, Spread};
use super::balloon::Joined;
use super::change::{Change, Nominal, SAMPLES};
use super::models::{Found, Models, OnModels};
use super::monte_carlo::monte_carlo;
use super::rounds::{Context, Job, Round};
use super::sources::Source;
use super::tolerances::Tolerances;
use crate::curve::{Curve, Point, shape_error};
use crate::design::Design;
use crate::fe::newton::PatternCache;
use crate::fe::{SimulateError, SimulateOptions, Simulation, simulate_with};
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
/// `options` on up to `threads` threads — the patches' sources on
/// `patch_model` where given (the design solved there from its state on
/// `options`); against `target` where given; with the Monte-Carlo `check`
/// where asked, on `options`.
pub fn linear_spread(
    design: &Design,
    target: Option<&Curve>,
    tolerances: &Tolerances,
    (options, patch_model): (&SimulateOptions, Option<&SimulateOptions>),
    threads: usize,
    check: Option<Check>,
) -> Result<Spread, SpreadError> {
    tolerances.validate().map_err(SpreadError::Tolerances)?;
    let patterns = PatternCache::default();
    let state = simulate_with(design, options, None, &patterns).map_err(SpreadError::Nominal)?;
    let against = Against::target(&state, target)?;
    let nominal = Nominal {
        design,
        simulation: &state,
        options,
        patterns: &patterns,
    };
    let patch_model = patch_model.filter(|_| Source::any_patch(design, tolerances));
    let coarse = patch_model.map(|model| simulate_with(design, model, Some(&state), &patterns));
    let coarse = coarse.transpose().map_err(SpreadError::Nominal)?;
    let models = Models::pair(nominal, coarse.as_ref().zip(patch_model));
    let mut spread = spread_of(&models, &against, tolerances, threads)?;
    spread.solves += 1 + usize::from(coarse.is_some());
    if let Some(Check { samples, seed }) = check {
        let never = AtomicBool::new(false);
        let draw = (samples, seed);
        let sampled = monte_carlo(&nominal, &spread, tolerances, draw, threads, &never);
        spread.solves += samples;
        spread.monte_carlo = Some(sampled);
    }
    Ok(spread)
}

/// The source of the wall and the modulus with the smaller tolerance read
/// from the other's change (`equivalent`: its index, the other's and the
/// ratio of their tolerances), unless they were found together.
fn read_equivalent(changes: &mut [Found], equivalent: Option<(usize, usize, f64)>) {
    let Some((k, from, s)) = equivalent else {
        return;
    };
    if let Some((change, estimate)) = &changes[from]
        && *estimate != Estimate::Combined
    {
        changes[k] = Some((change.scaled(s), Estimate::Equivalent));
    }
}

/// The spread of a design whose nominal states are known (a design run's
/// verified simulation, and the patches' coarser one where it has it), on
/// up to `threads` threads.
pub fn spread_of(
    models: &Models,
    against: &Against,
    tolerances: &Tolerances,
    threads: usize,
) -> Result<Spread, SpreadError> {
    tolerances.validate().map_err(SpreadError::Tolerances)?;
    let on = OnModels::new(models).map_err(degenerate)?;
    let design = models.balloon.design;
    let sources = Source::all(design, tolerances);
    let moved: Vec<Design> = sources
        .iter()
        .map(|s| s.moved(design, s.tolerance(tolerances).0))
        .collect();
    let linearised = on.linearised(&sources, &moved, threads);
    let (mut changes, mut solves) = (linearised.changes, linearised.runs);
    let equivalent = Source::equivalent(&sources, tolerances);
    let mut joint = Joined::of(&sources, &linearised.fields);
    read_equivalent(&mut changes, equivalent);
    let context = Context {
        on: &on,
        sources: &sources,
        tolerances,
        moved: &moved,
        starts: &linearised.starts,
    };
    // The balloon's joined sources are solved in the first round whatever
    // their linearised size: theirs is the response least linear.
    while let Some(round) = Round::next(&changes, joint.take()) {
        let jobs = round.jobs(&sources);
        let done = map_in_threads(&jobs, threads, &|&job| context.solve(job));
        solves += jobs.iter().map(Job::solves).sum::<usize>();
        context
            .take(&round, done, &mut changes)
            .map_err(|(source, reason)| SpreadError::Moved {
                label: source.label(),
                reason,
            })?;
        read_equivalent(&mut changes, equivalent);
    }
    let changes: Vec<(Change, Estimate)> = (changes.into_iter())
        .map(|found| found.expect("every source found"))
        .collect();
    let together = Together::of(&changes);
    let contributors = contributors(sources, &changes, tolerances);
    Ok(summary(contributors, &together, against, solves))
}

/// Each source's share, the largest first.
fn contributors(
    sources: Vec<Source>,
    changes: &[(Change, Estimate)],
    tolerances: &Tolerances,
) -> Vec<Contributor> {
    let mut contributors: Vec<Contributor> = (sources.into_iter().zip(changes))
        .map(|(source, (change, estimate))| {
            let (tolerance, unit) = source.tolerance(tolerances);
            Contributor {
                source,
                label: source.label(),
                tolerance,
                unit: unit.into(),
                rms_mm: change.rms_mm(),
                tip_mm: change.tip_mm,
                shift_mm: rms_of(&change.shift),
                estimate: *estimate,
            }
        })
        .collect();
    contributors.sort_by(|a, b| b.rms_mm.total_cmp(&a.rms_mm));
    contributors
}

/// Every source's change together, at each sample and at the tip: the
/// expected squares added, and the mean moves added as vectors, so
/// E|Σₖ dₖ|² = Σₖ E|dₖ|² + |Σₖ bₖ|² − Σₖ |bₖ|² for independent sources
/// with means bₖ.
struct Together {
    band_sq: Vec<f64>,
    tip_sq: f64,
    mean_shift_mm: f64,
}

impl Together {
    fn of(changes: &[(Change, Estimate)]) -> Together {
        let mut band_sq = vec![0.0; SAMPLES];
        let mut shift = vec![Point::zeros(); SAMPLES];
        let (mut tip_sq, mut tip_shift) = (0.0, Point::zeros());
        for (change, _) in changes {
            for (sum, d) in band_sq.iter_mut().zip(&change.each_sq) {
                *sum += d;
            }
            for ((sum, total), b) in band_sq.iter_mut().zip(&mut shift).zip(&change.shift) {
                *sum -= b.norm_squared();
                *total += b;
            }
            tip_sq += change.tip_mm.powi(2) - change.tip_shift.norm_squared();
            tip_shift += change.tip_shift;
        }
        for (sum, b) in band_sq.iter_mut().zip(&shift) {
            *sum = (*sum + b.norm_squared()).max(0.0);
        }
        Together {
            band_sq,
            tip_sq: (tip_sq + tip_shift.norm_squared()).max(0.0),
            mean_shift_mm: rms_of(&shift),
        }
    }
}

/// The RMS over the samples of moves given at each (mm; 0 where none are).
fn rms_of(moves: &[Point]) -> f64 {
    (moves.iter().map(|b| b.norm_squared()).sum::<f64>() / SAMPLES as f64).sqrt()
}

/// The sources' shares added up, found with `solves` FE solves.
fn summary(
    contributors: Vec<Contributor>,
    together: &Together,
    against: &Against,
    solves: usize,
) -> Spread {
    let rms_mm = (together.band_sq.iter().sum::<f64>() / SAMPLES as f64).sqrt();
    let rms_percent = 100.0 * rms_mm / against.length_mm;
    let nominal_error = against.nominal_shape_error_percent;
    Spread {
        rms_mm,
        rms_percent,
        worst_mm: contributors.iter().map(|c| c.rms_mm).sum(),
        tip_rms_mm: together.tip_sq.sqrt(),
        tip_worst_mm: contributors.iter().map(|c| c.tip_mm).sum(),
        nominal_shape_error_percent: nominal_error,
        expected_shape_error_percent: nominal_error.map(|e| e.hypot(rms_percent)),
        mean_shift_mm: together.mean_shift_mm,
        solves,
        contributors,
        monte_carlo: None,
        band_mm: together.band_sq.iter().map(|d| d.sqrt()).collect(),
    }
}
