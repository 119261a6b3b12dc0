//! When a fit stops: the resolution, the target, and a fresh Jacobian's
//! small gain (a stall the model foresaw, or an overshoot it did not).

use super::super::step::damped_step;
use super::*;

/// Steps that lower |r| by less than the resolution count as stalled: the
/// fit ends sooner, its error within a few resolutions of the exact fit's
/// (the last accepted steps each lowered it by less); an enormous
/// resolution ends it at the fresh Jacobian's first accepted step.
#[test]
fn steps_below_the_resolution_end_the_fit_sooner() {
    let fit = |resolution: f64| {
        let problem = Analytic::new(exponential);
        let settings = Settings {
            resolution,
            ..Settings::default()
        };
        let start = problem.start(&[0.5, 0.5]);
        minimise(&problem, start, 200, None, &settings, &mut |_, _, _| {}).unwrap()
    };
    let (exact, resolved, coarse) = (fit(0.0), fit(1e-3), fit(1e9));
    assert!(resolved.counts.evaluations < exact.counts.evaluations);
    assert!(resolved.best.error < 5e-3, "{}", resolved.best.error);
    assert_eq!(coarse.counts.iterations, 1);
    assert!(coarse.best.error < coarse.start_error);
}

/// A target ends the fit at the first iterate at or below it, with no
/// fresh Jacobian to confirm it; a start already there takes no
/// evaluation at all.
#[test]
fn a_target_ends_the_fit_once_met() {
    let fit = |target: f64, from: [f64; 2]| {
        let problem = Analytic::new(exponential);
        let settings = Settings {
            target,
            ..Settings::default()
        };
        let start = problem.start(&from);
        minimise(&problem, start, 200, None, &settings, &mut |_, _, _| {}).unwrap()
    };
    let exact = fit(0.0, [0.5, 0.5]);
    let target = 0.1 * exact.start_error;
    let met = fit(target, [0.5, 0.5]);
    assert!(met.best.error <= target, "{} > {target}", met.best.error);
    assert!(
        exact.best.error < 0.01 * met.best.error,
        "{}",
        exact.best.error
    );
    assert!(met.counts.evaluations < exact.counts.evaluations);
    let already = fit(2.0 * exact.start_error, [0.5, 0.5]);
    assert_eq!(already.counts.evaluations, 0);
    assert_eq!(already.best.error, already.start_error);
}

/// r = 2 (x − 0.5) on [0, 1]: its minimum at x = 0.5.
fn line(u: &[f64]) -> Vec<f64> {
    vec![2.0 * (u[0] - 0.5)]
}

/// A slope for `line` that underestimates the true 2, as a linearised
/// response can: from x = 0.7 at the first damping (0.01) its step reaches
/// x = 0.30015, where |r| = 0.3997.
fn shallow(_: &[f64]) -> DMatrix<f64> {
    DMatrix::from_element(1, 1, 0.4 / (0.39985 * 1.01))
}

/// `line` from x = 0.7 with `shallow` as the cheap Jacobian: the fresh
/// Jacobian's first step overshoots the minimum and lands where |r| is
/// barely lower (0.4 → 0.3997, a gain below `min_gain` and `resolution`,
/// where the model promised a fall to under 0.01). That is an overshoot,
/// not a stall: the fit goes on and reaches the minimum.
#[test]
fn a_fresh_jacobians_overshooting_step_is_not_taken_for_a_stall() {
    let mut problem = Analytic::new(line);
    problem.jacobian = Some(shallow);
    let start = problem.start(&[0.7]);
    let step = damped_step(&shallow(&[0.7]), &start, 0.01).unwrap();
    let first = line(&step.u)[0].abs();
    assert!((first - 0.3997).abs() < 1e-9, "{first}");
    assert!(step.predicted < 0.01, "{}", step.predicted);
    let settings = Settings {
        resolution: 0.002,
        ..Settings::default()
    };
    let fit = minimise(&problem, start, 50, None, &settings, &mut |_, _, _| {}).unwrap();
    assert!(fit.counts.iterations > 1, "{:?}", fit.counts);
    assert!(
        fit.best.error < 0.01,
        "{} after {:?}",
        fit.best.error,
        fit.counts
    );
}

/// A small gain the model foresaw still ends a fresh Jacobian's steps:
/// near the minimum of `line`, where the exact slope promises less than
/// the resolution, the fit takes one step and stops.
#[test]
fn a_small_gain_the_model_foresaw_ends_the_fit() {
    let mut problem = Analytic::new(line);
    problem.jacobian = Some(|_: &[f64]| DMatrix::from_element(1, 1, 2.0));
    let settings = Settings {
        resolution: 0.002,
        ..Settings::default()
    };
    let start = problem.start(&[0.5005]);
    let fit = minimise(&problem, start, 50, None, &settings, &mut |_, _, _| {}).unwrap();
    assert_eq!(fit.counts.iterations, 1, "{:?}", fit.counts);
    assert_eq!(fit.counts.jacobians, 1, "{:?}", fit.counts);
}
