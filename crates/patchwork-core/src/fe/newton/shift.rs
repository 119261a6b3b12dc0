//! The Levenberg shift: where K is not positive definite (compressed,
//! wrinkling regions, or far from equilibrium) Cholesky fails, which doubles
//! as an inertia test, and the step is taken with K + αI instead, α grown
//! until the factorisation succeeds and decayed over the next iterations.
//! K + αI positive definite makes −(K + αI)⁻¹∇Π a descent direction.

use super::super::tangent_factor::TangentFactor;

/// The first shift tried, relative to the mean tangent entry, when K itself
/// is not positive definite. Over the 200 random designs of the robustness
/// test, 200 of 207 such searches ended at 1e3 and none below 1e-3; starting
/// at 1e-8 spent four attempts on shifts that never work (factorisations
/// 12 009 → 11 187, Newton iterations 8 104 → 8 073, the worst case 80 → 61).
const FIRST_SHIFT: f64 = 1e-4;

/// A decayed shift below this (relative to the mean tangent entry) becomes
/// zero: plain Newton is tried again. The default of
/// `NewtonOptions::shift_floor`.
pub const SMALLEST_SHIFT: f64 = 1e-6;

/// Shifts tried before a factorisation is given up.
const MAX_SHIFT_ATTEMPTS: usize = 40;

/// Factors K + αI, growing α from `start` (tenfold, from [`FIRST_SHIFT`]
/// times `stiffness` if `start` is zero) until the factorisation succeeds or
/// α would pass `ceiling`; returns the α used (or the last one tried, as the
/// error) and the number of attempts. The last `n` triplets of `values` are
/// the diagonal shift slots.
pub fn factor_with_shift(
    factor: &mut TangentFactor,
    values: &mut [f64],
    start: f64,
    stiffness: f64,
    ceiling: f64,
) -> (Result<f64, f64>, usize) {
    let shift_slots = values.len() - factor.dimension();
    let mut shift = start;
    let mut tried = start;
    for attempt in 0..MAX_SHIFT_ATTEMPTS {
        if shift > ceiling {
            return (Err(tried), attempt);
        }
        values[shift_slots..].fill(shift);
        if factor.factorise(values) {
            return (Ok(shift), attempt + 1);
        }
        tried = shift;
        shift = if shift == 0.0 {
            FIRST_SHIFT * stiffness
        } else {
            shift * 10.0
        };
    }
    (Err(tried), MAX_SHIFT_ATTEMPTS)
}

/// The shift the next iteration starts from after a step taken with `used`:
/// a tenth of it, or zero (plain Newton) once that is below `floor` times
/// `stiffness`.
pub fn decayed(used: f64, stiffness: f64, floor: f64) -> f64 {
    if used / 10.0 > floor * stiffness {
        used / 10.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::Analytic;
    use super::*;
    use crate::fe::newton::potential::Potential;

    /// `potential`'s tangent at the origin factorised with shifts up to
    /// `ceiling`: the shift used (or the last tried), the attempts, and the
    /// stiffness scale.
    fn shift_at_origin(potential: &Analytic, ceiling: f64) -> (Result<f64, f64>, usize, f64) {
        let pattern = potential.pattern();
        let mut factor = pattern.factor();
        let mut here = potential.linearise(&[0.0, 0.0]).unwrap();
        let stiffness = here.stiffness;
        let (used, attempts) =
            factor_with_shift(&mut factor, &mut here.values, 0.0, stiffness, ceiling);
        (used, attempts, stiffness)
    }

    #[test]
    fn a_positive_definite_tangent_factorises_without_shift() {
        let (used, attempts, _) = shift_at_origin(&Analytic::bowl(), f64::INFINITY);
        assert_eq!((used, attempts), (Ok(0.0), 1));
    }

    #[test]
    fn an_indefinite_tangent_gets_the_first_shift_that_makes_it_definite() {
        // K = diag(1, −0.5): K + αI is positive definite for α > 0.5. The
        // stored triplets are K's lower triangle (1, 0, −0.5) and two shift
        // slots, mean magnitude 0.3, so the shifts tried are 0, 3e-5, 3e-4,
        // …, 0.3, and the seventh, 3, is the first above 0.5.
        let (used, attempts, stiffness) = shift_at_origin(&Analytic::saddle(), f64::INFINITY);
        assert!((stiffness - 0.3).abs() < 1e-15);
        let used = used.unwrap();
        assert!((used - 3.0).abs() < 1e-12, "{used}");
        assert_eq!(attempts, 7);
        // Under a ceiling below 0.5 every allowed shift fails: the last tried.
        let (capped, attempts, _) = shift_at_origin(&Analytic::saddle(), 0.1);
        assert!((capped.unwrap_err() - 0.03).abs() < 1e-12);
        assert_eq!(attempts, 5);
    }

    #[test]
    fn the_shift_decays_tenfold_then_to_zero() {
        assert_eq!(decayed(1.0, 1.0, SMALLEST_SHIFT), 0.1);
        assert_eq!(decayed(5e-6, 1.0, SMALLEST_SHIFT), 0.0);
        assert!((decayed(5e-6, 1.0, 1e-10) - 5e-7).abs() < 1e-18);
        assert_eq!(decayed(0.0, 1.0, SMALLEST_SHIFT), 0.0);
    }
}
