//! The Monte-Carlo check of the linear spread: `samples` designs, each with
//! every source drawn at once from N(0, tolerance²) (seeded), solved in full
//! from the nominal state in parallel (to the spread's `SOURCE_TOLERANCE`); their centrelines' RMS change from
//! the nominal (aligned, as the linear spread measures it) against the
//! linear estimate.
//!
//! To first order the expected Σ|d|²/n of a sample is Σₖ |dₖ|²/n, the
//! linear spread's square: the cross terms of independent sources vanish
//! in expectation. So the ratio of the sampled RMS to the linear one is 1
//! where the model is linear over the tolerances, up to the sampling error
//! of N samples (about 1/√(2N) relative, for normal-like changes); a ratio
//! beyond `AGREEMENT` says the response is not linear there and the
//! sampled figure is the one to trust.

use std::sync::atomic::{AtomicBool, Ordering};

use super::answer::{MonteCarlo, Spread};
use super::change::{Change, Nominal, SAMPLES, change_of};
use super::sources::Source;
use super::tolerances::Tolerances;
use crate::cmaes::SeededRng;
use crate::design::Design;
use crate::fe::simulate_with;
use crate::parallel::map_in_threads;

/// How far the sampled RMS may lie from the linear one (relative) for the
/// two to agree.
pub const AGREEMENT: f64 = 0.2;

/// Draws `samples` designs about `nominal` at `tolerances` (seed `seed`),
/// solves them on up to `threads` threads and compares them with `linear`.
/// Once `cancel` is set no further design is solved (the caller, which
/// set it, discards the answer).
pub fn monte_carlo(
    nominal: &Nominal,
    linear: &Spread,
    tolerances: &Tolerances,
    (samples, seed): (usize, u64),
    threads: usize,
    cancel: &AtomicBool,
) -> MonteCarlo {
    let sources = Source::all(nominal.design, tolerances);
    let mut rng = SeededRng::new(seed);
    let designs: Vec<Design> = (0..samples)
        .map(|_| {
            sources.iter().fold(nominal.design.clone(), |d, s| {
                s.moved(&d, s.tolerance(tolerances).0 * rng.normal())
            })
        })
        .collect();
    let reference = nominal.simulation.centreline.resample(SAMPLES).ok();
    let options = nominal.source_options();
    let changes = map_in_threads(&designs, threads, &|design| {
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        let reference = reference.as_ref()?;
        let moved =
            simulate_with(design, &options, Some(nominal.simulation), nominal.patterns).ok()?;
        change_of(&moved.centreline, &nominal.simulation.centreline, reference).ok()
    });
    let solved: Vec<_> = changes.into_iter().flatten().collect();
    let n = solved.len().max(1) as f64;
    let rms_mm = (solved.iter().map(Change::samples_sq).sum::<f64>() / (n * SAMPLES as f64)).sqrt();
    let tip_rms_mm = (solved.iter().map(|c| c.tip_mm.powi(2)).sum::<f64>() / n).sqrt();
    let ratio = match linear.rms_mm > 0.0 {
        true => rms_mm / linear.rms_mm,
        false => 1.0,
    };
    MonteCarlo {
        samples,
        seed,
        failed: samples - solved.len(),
        rms_mm,
        tip_rms_mm,
        ratio,
        ratio_sigma: ratio / (2.0 * n).sqrt(),
        agrees: (ratio - 1.0).abs() <= AGREEMENT,
    }
}
