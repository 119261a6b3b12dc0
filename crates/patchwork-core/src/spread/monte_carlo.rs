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
//! of N samples ([`relative_error`]); a ratio beyond `AGREEMENT` says the
//! response is not linear there and the sampled figure is the one to
//! trust.

use std::sync::atomic::{AtomicBool, Ordering};

use super::answer::{MonteCarlo, Spread};
use super::change::{Nominal, SAMPLES, change_of};
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
    let squares: Vec<f64> = (solved.iter())
        .map(|c| c.samples_sq() / SAMPLES as f64)
        .collect();
    let rms_mm = (squares.iter().sum::<f64>() / n).sqrt();
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
        ratio_sigma: ratio * relative_error(&squares),
        agrees: (ratio - 1.0).abs() <= AGREEMENT,
    }
}

/// The relative sampling error (one σ) of the RMS √m̄ of draws whose mean
/// squares are `squares` (mᵢ, one per draw): m̄'s standard error is s/√N,
/// s the draws' sample deviation, and to first order the RMS's relative
/// error is half m̄'s, s / (2 m̄ √N). For a normal-like change (mᵢ a scaled
/// χ², s ≈ √2 m̄) that is 1/√(2N); where a few draws in the tails move the
/// centreline much further than the rest, s and the error grow with them.
/// 1 (all of it) with fewer than two draws or none that moved.
pub fn relative_error(squares: &[f64]) -> f64 {
    let n = squares.len() as f64;
    let mean = squares.iter().sum::<f64>() / n;
    if squares.len() < 2 || mean <= 0.0 {
        return 1.0;
    }
    let variance = squares.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (n - 1.0);
    variance.sqrt() / (2.0 * mean * n.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Squares of standard normal draws (χ² with one degree of freedom,
    /// deviation √2): the error is 1/√(2N) within the draws' own sampling
    /// (5 % at N = 4000); one draw far in a tail widens it.
    #[test]
    fn the_sampling_error_follows_the_draws_spread() {
        let mut rng = SeededRng::new(3);
        let n = 4000;
        let mut squares: Vec<f64> = (0..n).map(|_| rng.normal().powi(2)).collect();
        let normal = relative_error(&squares);
        let expected = 1.0 / (2.0 * n as f64).sqrt();
        assert!(
            (normal / expected - 1.0).abs() < 0.05,
            "{normal} against {expected}"
        );
        squares[0] = 400.0;
        assert!(relative_error(&squares) > 1.5 * normal);
        assert_eq!(relative_error(&[2.0]), 1.0);
        assert_eq!(relative_error(&[0.0, 0.0]), 1.0);
    }
}
