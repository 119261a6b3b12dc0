//! The linear spread: each source's change of the centreline at its
//! tolerance, source by source, each on its nominal state (`Models`: the
//! balloon's sources on one, the patches' on the same or a coarser one).
//! Every source is first linearised at its nominal state
//! (`fe::sensitivity`: one factorisation of the tangent, a substitution per
//! source); those whose linearised change is at least [`SOLVED_FRACTION`]
//! of the largest change found are then solved both ways — Newton solves
//! at +tolerance, warm-started from the nominal state (all but a patch's
//! X from their linearised state, `models::starts_linearised`), and at
//! −tolerance, started from the first solve less twice the linearised
//! change (`fe::second_order_start`; a patch's X from the nominal
//! reflected through the first solve ring by ring, `fe::reflected_start`),
//! each to a relative residual of `SOURCE_TOLERANCE` with its last move
//! under `SOURCE_STEP_MM` — and the largest is taken again from
//! the solved, until every source above the fraction is solved. The
//! balloon's sources that act as one — the wall and the modulus exactly,
//! the pressure where its linearised move lies along theirs — are solved
//! together instead, once one of them is due: two solves at the nodes of
//! a Gauss–Hermite rule on their joint variable, each source shown with
//! its share (`balloon.rs`). Where a node's solve fails they are solved
//! one by one, and of the wall and the modulus only the one with the
//! larger tolerance; the other reads its change (`Source::equivalent`,
//! `Change::scaled`). The
//! linearised response alone misjudges the large sources: it overstates a
//! patch's placement around the tube up to sixfold and its angle up to
//! twofold (the tube's soft twist answering a first-order force that its
//! geometric stiffening holds back), and understates its placement along
//! it by up to a third; a small source's share of the sum in quadrature is
//! small, and so is its error's. On seven draft designs of the suite
//! (`examples/spread_linearised.rs`, docs/studies.md "The spread's
//! solves"), 3 to 10 of 13 to 28 sources were solved, the RMS spread came
//! within 1.1 % of every source's solve and the three largest contributors
//! were the same. Each centreline is compared with the nominal at equal
//! fractions of length.
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
use super::balloon::{Joined, NODES, apportioned};
use super::change::{Change, Nominal, SAMPLES, offsets_of};
use super::models::{Found, Models, OnModels};
use super::monte_carlo::monte_carlo;
use super::sources::Source;
use super::tolerances::Tolerances;
use crate::curve::{Curve, Point, shape_error};
use crate::design::Design;
use crate::fe::newton::PatternCache;
use crate::fe::{
    SimulateError, SimulateOptions, Simulation, reflected_start, second_order_start, simulate_with,
};
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

/// A source whose linearised change is at least this fraction of the
/// largest change (RMS) is solved; a smaller one keeps its linearised change.
pub const SOLVED_FRACTION: f64 = 0.5;

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
    let mut joined = Joined::of(&sources, &linearised.fields);
    read_equivalent(&mut changes, equivalent);
    while let Some(mut pending) = to_solve(&changes) {
        if let Some(j) = joined.take_if(|j| pending.iter().any(|&k| j.has(k))) {
            pending.retain(|&k| !j.has(k));
            let (nominal, samples) = on.of(sources[j.members[0].0]);
            let found = j.change(
                nominal,
                (&sources, tolerances),
                &linearised.starts,
                samples,
                threads,
            );
            solves += 2 * NODES.len();
            // Where a node's solve fails, each source is solved on its own.
            if let Ok(change) = found {
                for (k, share) in j.shares() {
                    changes[k] = Some((apportioned(&change, share), Estimate::Combined));
                }
            }
        }
        // The balloon's sources first (where not found together): their
        // solves, on the finer model, take longest, and the threads then
        // share out the patches'.
        pending.sort_by_key(|&k| matches!(sources[k], Source::Patch { .. }));
        let solved = map_in_threads(&pending, threads, &|&k| {
            let other_way = sources[k].moved(design, -sources[k].tolerance(tolerances).0);
            let (nominal, samples) = on.of(sources[k]);
            let start = linearised.starts[k].as_deref();
            solved_change(nominal, (&moved[k], start), &other_way, samples)
        });
        for (k, found) in pending.into_iter().zip(solved) {
            let found = found.map_err(|reason| SpreadError::Moved {
                label: sources[k].label(),
                reason,
            })?;
            changes[k] = Some(found);
            // Both ways, the second solve counted where it failed too.
            solves += 2;
        }
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
                rms_mm: rms(change),
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
            Some((_, Estimate::Solved | Estimate::BothWays)) => false,
            Some((_, Estimate::Equivalent | Estimate::Combined)) => false,
        })
        .collect();
    (!pending.is_empty()).then_some(pending)
}

/// A source's change by Newton solves at `plus` (warm-started from
/// `plus_start`, its linearised positions, where given, else from the
/// nominal state) and at `other_way` (started from the first less twice
/// the linearised change where `plus_start` is given,
/// `fe::second_order_start`, else from the nominal reflected through the
/// first, `fe::reflected_start`). Where the second solve
/// fails the first one's change stands alone (`Solved`).
fn solved_change(
    nominal: &Nominal,
    (plus, plus_start): (&Design, Option<&[Point]>),
    other_way: &Design,
    samples: &Curve,
) -> Result<(Change, Estimate), String> {
    let options = nominal.source_options();
    let home = &nominal.simulation.centreline;
    let solve = |design: &Design, start: &Simulation| {
        simulate_with(design, &options, Some(start), nominal.patterns).map_err(|e| e.to_string())
    };
    let linearised = plus_start.map(|positions| Simulation {
        positions: positions.to_vec(),
        ..nominal.simulation.clone()
    });
    let plus_state = solve(plus, linearised.as_ref().unwrap_or(nominal.simulation))?;
    let plus_offsets = offsets_of(&plus_state.centreline, home, samples)?;
    // Where the linearisation answers closely, at second order from it;
    // else the nominal reflected ring by ring through the first solve.
    let second =
        plus_start.and_then(|lin| second_order_start(nominal.simulation, &plus_state, lin));
    let start = second.or_else(|| reflected_start(nominal.simulation, &plus_state));
    let minus = solve(other_way, start.as_ref().unwrap_or(nominal.simulation))
        .and_then(|state| offsets_of(&state.centreline, home, samples));
    Ok(match minus {
        Ok(minus) => (Change::both_ways(&plus_offsets, &minus), Estimate::BothWays),
        Err(_) => (Change::one_way(&plus_offsets), Estimate::Solved),
    })
}

/// A change's RMS over the samples (mm).
fn rms(change: &Change) -> f64 {
    (change.samples_sq() / SAMPLES as f64).sqrt()
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
