//! The solver on small analytic problems, where the answer is known.

use std::sync::atomic::{AtomicUsize, Ordering};

use super::super::SpaceMapped;
use super::step::damped_step_from_normal;
use super::*;
use nalgebra::DVector;

/// An analytic Jacobian of the point.
type JacobianFn = fn(&[f64]) -> DMatrix<f64>;

/// A problem given by its residual function of the point; the state is the
/// point itself. Counts its evaluations; `exact` supplies the analytic
/// Jacobian as the cheap one; `cancel_after` cancels after that many, and
/// its time is up after `time_after`.
struct Analytic<F> {
    r: F,
    jacobian: Option<JacobianFn>,
    solves: AtomicUsize,
    cancel_after: usize,
    time_after: usize,
}

impl<F: Fn(&[f64]) -> Vec<f64> + Sync> Analytic<F> {
    fn new(r: F) -> Self {
        Analytic {
            r,
            jacobian: None,
            solves: AtomicUsize::new(0),
            cancel_after: usize::MAX,
            time_after: usize::MAX,
        }
    }

    fn start(&self, u: &[f64]) -> Iterate<Vec<f64>> {
        Iterate::new(self, u.to_vec(), u.to_vec()).ok().unwrap()
    }
}

impl<F: Fn(&[f64]) -> Vec<f64> + Sync> Residuals for Analytic<F> {
    type State = Vec<f64>;

    fn residuals(&self, u: &Vec<f64>) -> Option<DVector<f64>> {
        Some(DVector::from_vec((self.r)(u)))
    }

    fn solve(&self, u: &[f64], _near: &Vec<f64>) -> Option<Vec<f64>> {
        self.solves.fetch_add(1, Ordering::Relaxed);
        Some(u.to_vec())
    }

    fn cheap_jacobian(&self, at: &Iterate<Vec<f64>>, _step: f64) -> Option<DMatrix<f64>> {
        self.jacobian.map(|j| j(&at.u))
    }

    fn cancelled(&self) -> bool {
        self.solves.load(Ordering::Relaxed) >= self.cancel_after
    }

    fn out_of_time(&self) -> bool {
        self.solves.load(Ordering::Relaxed) >= self.time_after
    }
}

fn run<F: Fn(&[f64]) -> Vec<f64> + Sync>(
    problem: &Analytic<F>,
    from: &[f64],
    budget: usize,
) -> Solution<Vec<f64>> {
    minimise(
        problem,
        problem.start(from),
        budget,
        None,
        &Settings::default(),
        &mut |_, _, _| {},
    )
    .unwrap()
}

/// y = a e^(−b t) sampled at t = 0, 0.5, …, 3 with a = 2.5, b = 0.7; the
/// cube maps to a ∈ [0, 4], b ∈ [0, 2], so the answer is u = (0.625, 0.35).
fn exponential(u: &[f64]) -> Vec<f64> {
    let (a, b) = (4.0 * u[0], 2.0 * u[1]);
    (0..7)
        .map(|i| {
            let t = 0.5 * i as f64;
            a * (-b * t).exp() - 2.5 * (-0.7 * t).exp()
        })
        .collect()
}

#[test]
fn fits_an_exponential_to_its_exact_parameters_by_forward_differences() {
    let problem = Analytic::new(exponential);
    let solution = run(&problem, &[0.5, 0.5], 200);
    let u = &solution.best.u;
    assert!(
        (u[0] - 0.625).abs() < 1e-6 && (u[1] - 0.35).abs() < 1e-6,
        "{u:?}"
    );
    assert!(solution.best.error < 1e-8, "{}", solution.best.error);
    let counts = solution.counts;
    assert!(counts.jacobians >= 1 && counts.differenced == counts.jacobians);
    // Every evaluation was counted, and the budget held.
    assert_eq!(counts.evaluations, problem.solves.load(Ordering::Relaxed));
    assert!(counts.evaluations <= 200);
}

#[test]
fn solves_rosenbrock_from_across_the_valley() {
    // r = (10 (y − x²), 1 − x), x, y ∈ [−2, 2]: the minimum |r| = 0 at
    // (1, 1), u = (0.75, 0.75), at the end of a curved valley.
    let problem = Analytic::new(|u: &[f64]| {
        let (x, y) = (4.0 * u[0] - 2.0, 4.0 * u[1] - 2.0);
        vec![10.0 * (y - x * x), 1.0 - x]
    });
    let solution = run(&problem, &[0.125, 0.5], 2000);
    let u = &solution.best.u;
    assert!(
        (u[0] - 0.75).abs() < 1e-5 && (u[1] - 0.75).abs() < 1e-5,
        "{u:?} after {:?}",
        solution.counts
    );
    assert!(solution.start_error > 10.0 && solution.best.error < 1e-5);
}

#[test]
fn a_cheap_jacobian_replaces_forward_differences_and_costs_one_evaluation() {
    let mut problem = Analytic::new(exponential);
    problem.jacobian = Some(|u: &[f64]| {
        let (a, b) = (4.0 * u[0], 2.0 * u[1]);
        DMatrix::from_fn(7, 2, |i, j| {
            let t = 0.5 * i as f64;
            match j {
                0 => 4.0 * (-b * t).exp(),
                _ => -2.0 * a * t * (-b * t).exp(),
            }
        })
    });
    let solution = run(&problem, &[0.5, 0.5], 200);
    assert!((solution.best.u[0] - 0.625).abs() < 1e-6);
    let counts = solution.counts;
    assert_eq!(counts.differenced, 0);
    // Cheap Jacobians cost no solve but count one evaluation each.
    assert_eq!(
        counts.evaluations,
        problem.solves.load(Ordering::Relaxed) + counts.jacobians
    );
}

#[test]
fn no_budget_is_overspent_and_a_budget_too_small_for_a_jacobian_moves_nothing() {
    for budget in 0..12 {
        let problem = Analytic::new(exponential);
        let solution = run(&problem, &[0.5, 0.5], budget);
        assert!(solution.counts.evaluations <= budget, "budget {budget}");
        // Forward differences in two variables and a step need three.
        if budget < 3 {
            assert_eq!(solution.best.u, vec![0.5, 0.5], "budget {budget}");
            assert_eq!(solution.counts.jacobians, 0);
        } else {
            assert!(
                solution.best.error < solution.start_error,
                "budget {budget}"
            );
        }
    }
}

#[test]
fn a_minimum_outside_the_cube_ends_on_its_face() {
    // r = (u₀ − 2, u₁ − 0.3): the best point in the cube is (1, 0.3), where
    // |r| = 1. The run stops once a step gains less than 1e-3 of |r|, so u₁
    // is as close as that gain resolves: within 1 % of |r|'s scale.
    let problem = Analytic::new(|u: &[f64]| vec![u[0] - 2.0, u[1] - 0.3]);
    let solution = run(&problem, &[0.2, 0.9], 100);
    assert_eq!(solution.best.u[0], 1.0);
    assert!(
        (solution.best.u[1] - 0.3).abs() < 0.05,
        "{:?}",
        solution.best.u
    );
    assert!(solution.best.error - 1.0 < 1e-3, "{}", solution.best.error);
    assert!(
        solution.counts.evaluations < 100,
        "stopped before the budget"
    );
}

#[test]
fn a_cancelled_run_says_so() {
    let mut problem = Analytic::new(exponential);
    problem.cancel_after = 5;
    let result = minimise(
        &problem,
        problem.start(&[0.5, 0.5]),
        200,
        None,
        &Settings::default(),
        &mut |_, _, _| {},
    );
    assert!(matches!(result, Err(Cancelled)));
}

#[test]
fn out_of_time_it_stops_before_the_next_solve_with_its_best_so_far() {
    let unlimited = run(&Analytic::new(exponential), &[0.5, 0.5], 200);
    let mut problem = Analytic::new(exponential);
    problem.time_after = 6;
    let solution = run(&problem, &[0.5, 0.5], 200);
    // Six solves: the Jacobian's two differences and four trials, no more.
    assert_eq!(problem.solves.load(Ordering::Relaxed), 6);
    assert_eq!(solution.counts.evaluations, 6);
    let start = problem.start(&[0.5, 0.5]).error;
    assert!(
        solution.best.error < start,
        "{} {start}",
        solution.best.error
    );
    assert!(
        solution.best.error > unlimited.best.error,
        "{} {}",
        solution.best.error,
        unlimited.best.error
    );
    // Out of time from the start: the start itself, no solve.
    problem.solves.store(0, Ordering::Relaxed);
    problem.time_after = 0;
    let solution = run(&problem, &[0.5, 0.5], 200);
    assert_eq!(problem.solves.load(Ordering::Relaxed), 0);
    assert_eq!(solution.best.u, vec![0.5, 0.5]);
}

#[test]
fn a_handed_in_jacobian_of_the_wrong_shape_is_replaced_by_a_fresh_one() {
    let problem = Analytic::new(exponential);
    let mut heard = Vec::new();
    let solution = minimise(
        &problem,
        problem.start(&[0.5, 0.5]),
        200,
        Some(DMatrix::zeros(3, 2)),
        &Settings::default(),
        &mut |iterations, evaluations, _| heard.push((iterations, evaluations)),
    )
    .unwrap();
    assert!(solution.counts.jacobians >= 1);
    // The first report is the fresh Jacobian's, before any step.
    assert_eq!(heard[0], (0, 2));
    assert!(heard.windows(2).all(|w| w[0].1 < w[1].1));
}

#[test]
fn space_mapping_minimises_the_offset_residuals() {
    // r_c(u) = u − (0.4, 0.6), offset d = (0.1, −0.2): the mapped problem's
    // zero is u = (0.3, 0.8), where r_c = −d.
    let coarse = Analytic::new(|u: &[f64]| vec![u[0] - 0.4, u[1] - 0.6]);
    let offset = DVector::from_vec(vec![0.1, -0.2]);
    let mapped = SpaceMapped {
        inner: &coarse,
        offset: &offset,
    };
    let start = Iterate::new(&mapped, vec![0.5, 0.5], vec![0.5, 0.5])
        .ok()
        .unwrap();
    let solution = minimise(
        &mapped,
        start,
        100,
        None,
        &Settings::default(),
        &mut |_, _, _| {},
    )
    .unwrap();
    let u = &solution.best.u;
    assert!(
        (u[0] - 0.3).abs() < 1e-9 && (u[1] - 0.8).abs() < 1e-9,
        "{u:?}"
    );
}

#[test]
fn damped_step_solves_a_linear_least_squares_problem_when_undamped() {
    // r(u) = J u − b with J = [[2, 0], [0, 1], [1, 1]]: the undamped step
    // from u = 0 lands on the least-squares solution (JᵀJ)⁻¹ Jᵀ b.
    let j = DMatrix::from_row_slice(3, 2, &[2.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
    let b = DVector::from_vec(vec![0.8, 0.3, 0.5]);
    let normal = j.transpose() * &j;
    let next =
        damped_step_from_normal(&normal, &(j.transpose() * -&b), 0.0, 1e-12, &[0.0, 0.0]).unwrap();
    let exact = (j.transpose() * &j).try_inverse().unwrap() * j.transpose() * &b;
    assert!((next[0] - exact[0]).abs() < 1e-12 && (next[1] - exact[1]).abs() < 1e-12);
}

#[test]
fn damped_step_stays_in_the_unit_cube_and_shrinks_with_damping() {
    let normal = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 1.0]);
    let gradient = DVector::from_vec(vec![-5.0, 0.1]);
    let u = [0.5, 0.5];
    let wild = damped_step_from_normal(&normal, &gradient, 0.0, 1e-12, &u).unwrap();
    assert_eq!(wild[0], 1.0, "clamped at the upper bound");
    let damped = damped_step_from_normal(&normal, &gradient, 1e3, 1e-12, &u).unwrap();
    assert!((damped[0] - 0.5).abs() < 0.01 && damped[0] > 0.5);
    // A step that only pushes against a bound already reached moves nothing.
    assert!(damped_step_from_normal(&normal, &gradient, 0.0, 1e-12, &[1.0, 0.5]).is_some());
    let pinned = DVector::from_vec(vec![-5.0, 0.0]);
    assert!(damped_step_from_normal(&normal, &pinned, 0.0, 1e-12, &[1.0, 0.5]).is_none());
}

/// r(u) = J u − b with J = [[1, 1], [0, 1], [1, 0]], b = (2, 0.5, 2): from
/// u = (1, 0.5) the unconstrained step (5/6, −1/6) pushes u₀ past its upper
/// bound. Held there, the best u₁ is the least-squares fit of J's second
/// column to b − J's first: (1 + 0.5) / 2 = 0.75, where |r|² = 1.125 (1.25
/// at the start). Clamping the unconstrained step instead lands on
/// (1, 1/3), where |r|² = 1.47: no descent at all.
fn against_a_bound(u: &[f64]) -> Vec<f64> {
    vec![u[0] + u[1] - 2.0, u[1] - 0.5, u[0] - 2.0]
}

#[test]
fn a_variable_pushed_against_its_bound_is_held_there_and_the_rest_solved_without_it() {
    let j = DMatrix::from_row_slice(3, 2, &[1.0, 1.0, 0.0, 1.0, 1.0, 0.0]);
    let u = [1.0, 0.5];
    let r = DVector::from_vec(against_a_bound(&u));
    let next = damped_step_from_normal(&(j.transpose() * &j), &(j.transpose() * r), 0.0, 1e-12, &u)
        .unwrap();
    assert_eq!(next[0], 1.0);
    assert!((next[1] - 0.75).abs() < 1e-12, "{next:?}");
}

/// The same problem solved from inside the cube: the answer on the bound is
/// reached exactly, and no solve is spent on a step the linear model
/// expects to raise |r| (the exact Jacobian's model is the problem itself,
/// so every solve is accepted).
#[test]
fn an_answer_on_a_bound_is_reached_without_wasted_solves() {
    let mut problem = Analytic::new(against_a_bound);
    problem.jacobian = Some(|_| DMatrix::from_row_slice(3, 2, &[1.0, 1.0, 0.0, 1.0, 1.0, 0.0]));
    let solution = run(&problem, &[0.9, 0.2], 50);
    let u = &solution.best.u;
    assert!(u[0] == 1.0 && (u[1] - 0.75).abs() < 1e-6, "{u:?}");
    let counts = solution.counts;
    let steps = counts.evaluations - counts.jacobians;
    assert_eq!(steps, counts.iterations, "every step accepted: {counts:?}");
}

/// Nielsen's damping rule: a step the linear model predicted exactly lowers
/// the damping threefold, a half-right one keeps it, one that barely paid
/// doubles it; a model that predicted no fall counts as exact.
#[test]
fn the_damping_follows_how_well_the_model_predicted_the_step() {
    // |r| 2 → 1 as predicted: ρ = 1.
    assert!((damping_factor(gain_ratio(2.0, 1.0, 1.0)) - 1.0 / 3.0).abs() < 1e-12);
    // |r|² fell by 1.5 of a predicted 3: ρ = 0.5.
    let half = gain_ratio(2.0, 2.5_f64.sqrt(), 1.0);
    assert!((half - 0.5).abs() < 1e-12 && (damping_factor(half) - 1.0).abs() < 1e-12);
    assert!((damping_factor(gain_ratio(2.0, 2.0 - 1e-9, 1.0)) - 2.0).abs() < 1e-6);
    assert_eq!(gain_ratio(1.0, 0.5, 1.0), 1.0);
}

/// Rosenbrock's valley with its analytic Jacobian as the cheap one, run
/// with `secant_ratio`: the counts.
fn rosenbrock_with_cheap_jacobians(secant_ratio: f64) -> (Counts, usize, f64) {
    let mut problem = Analytic::new(|u: &[f64]| {
        let (x, y) = (4.0 * u[0] - 2.0, 4.0 * u[1] - 2.0);
        vec![10.0 * (y - x * x), 1.0 - x]
    });
    problem.jacobian = Some(|u: &[f64]| {
        let x = 4.0 * u[0] - 2.0;
        DMatrix::from_row_slice(2, 2, &[-80.0 * x, 40.0, -4.0, 0.0])
    });
    let settings = Settings {
        secant_ratio,
        ..Settings::default()
    };
    let start = problem.start(&[0.125, 0.5]);
    let solution = minimise(&problem, start, 2000, None, &settings, &mut |_, _, _| {}).unwrap();
    let solves = problem.solves.load(Ordering::Relaxed);
    (solution.counts, solves, solution.best.error)
}

/// A secant step that the linear model predicted badly refreshes a cheap
/// Jacobian: along Rosenbrock's curved valley the secant drifts, and fresh
/// Jacobians there reach the minimum in fewer trial solves than keeping
/// each secant until its steps stall.
#[test]
fn a_badly_predicted_secant_step_refreshes_a_cheap_jacobian() {
    let kept = rosenbrock_with_cheap_jacobians(f64::NEG_INFINITY);
    let refreshed = rosenbrock_with_cheap_jacobians(SECANT_RATIO);
    println!("kept {kept:?}, refreshed {refreshed:?}");
    assert!(
        kept.2 < 1e-5 && refreshed.2 < 1e-5,
        "{kept:?} {refreshed:?}"
    );
    assert!(
        refreshed.0.jacobians > kept.0.jacobians,
        "{kept:?} {refreshed:?}"
    );
    assert!(refreshed.1 < kept.1, "{kept:?} {refreshed:?}");
}

mod stops;
