//! The definiteness guard: a step is kept only if the tangent at its end
//! factorises with a shift not much larger than the step's own.
//!
//! A full Newton step from a state where K is positive definite (or nearly)
//! can land where K is strongly indefinite: from a carried or kinematic start
//! on the Hilbert scene, the first step moves a node at a patch end by
//! 1–24 mm, where a 0.5 mm element's wall then wrinkles, and Newton needs a
//! shift of 10²–10³ times the mean tangent entry for the next 5–12
//! iterations, creeping like gradient descent until the shift has decayed
//! (docs/studies.md). The guard accepts the line search's point only if K there
//! factorises with a shift up to a ceiling (ten times the shift the step was
//! taken with, at least [`GUARD_SHIFT`] times the mean tangent entry);
//! otherwise it halves the step, up to [`GUARD_HALVINGS`] times, keeping
//! only halved points whose energy is not above the start's. The
//! factorisation it makes at the accepted point is the next iteration's, so
//! a step that passes first time costs nothing extra. If no halving passes,
//! the line search's point stands (the shifted iterations then take over).

use super::super::tangent_factor::TangentFactor;
use super::outcome::SolveStats;
use super::potential::{Linearisation, Potential};
use super::shift::factor_with_shift;
use super::timing::timed;

/// The largest shift, relative to the mean tangent entry, that the guard
/// lets a step's end need after a step taken without one (after a shifted
/// step: ten times that shift).
const GUARD_SHIFT: f64 = 1e-3;

/// Halvings of a step the guard tries before it takes the line search's
/// step as it was.
const GUARD_HALVINGS: usize = 4;

/// The largest shift a step taken with `used` may need at its end; infinite
/// (anything goes) when the guard is off.
pub fn ceiling(guarding: bool, used: f64, stiffness: f64) -> f64 {
    if guarding {
        (10.0 * used).max(GUARD_SHIFT * stiffness)
    } else {
        f64::INFINITY
    }
}

/// A state the guard accepted, linearised; `factored_with` is the shift of
/// the factorisation of K + αI it left in the factor, or, if every shift up
/// to the ceiling failed there, the last one tried.
pub struct Guarded {
    pub u: Vec<f64>,
    pub here: Linearisation,
    pub factored_with: Result<f64, f64>,
}

/// The guard on the line search's point `next` from `u` (energy `energy`),
/// with `next`'s linearisation where the caller has it: shifts tried from
/// `shift` up to `ceiling`. `None` if `next` is outside the potential's
/// domain.
pub fn guard_definiteness(
    potential: &impl Potential,
    factor: &mut TangentFactor,
    (u, energy): (&[f64], f64),
    (next, linearised): (Vec<f64>, Option<Linearisation>),
    (shift, ceiling): (f64, f64),
    stats: &mut SolveStats,
) -> Option<Guarded> {
    // K at `point`, factorised with a shift up to the ceiling; `None` if the
    // point is outside the domain or its energy is above `cap` (judged before
    // the factorisation, which a refused point does not need).
    let mut test = |point: &[f64], known: Option<Linearisation>, cap: Option<f64>| {
        let linearised =
            known.or_else(|| timed(&mut stats.assembly_time, || potential.linearise(point)));
        let mut here = linearised.filter(|l| cap.is_none_or(|cap| l.potential <= cap))?;
        let (used, attempts) = timed(&mut stats.factor_time, || {
            factor_with_shift(factor, &mut here.values, shift, here.stiffness, ceiling)
        });
        stats.factorisations += attempts;
        Some((here, used))
    };
    // The line search accepted its own point (a full step by the energy of
    // its linearisation, a shorter one by `Potential::energy`, summed in
    // another order), so its energy is not judged again.
    let (here, used) = test(&next, linearised, None)?;
    if used.is_ok() || !ceiling.is_finite() {
        // Passed, or the guard is off: the point is taken as it is.
        return Some(Guarded {
            u: next,
            here,
            factored_with: used,
        });
    }
    let allowance = 1e-11 * energy.abs();
    for halving in 1..=GUARD_HALVINGS {
        let fraction = 0.5_f64.powi(halving as i32);
        let candidate: Vec<f64> = u
            .iter()
            .zip(&next)
            .map(|(a, b)| a + fraction * (b - a))
            .collect();
        // A halved point must not raise the energy.
        if let Some((halved, Ok(shifted))) = test(&candidate, None, Some(energy + allowance)) {
            return Some(Guarded {
                u: candidate,
                here: halved,
                factored_with: Ok(shifted),
            });
        }
    }
    // No halving passed: the line search's point stands.
    Some(Guarded {
        u: next,
        here,
        factored_with: used,
    })
}
