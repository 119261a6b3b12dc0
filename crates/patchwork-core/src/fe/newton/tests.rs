//! Newton's pieces on small analytic potentials, where every number can be
//! worked out by hand.

use faer::sparse::Pair;

use super::guard::{ceiling, guard_definiteness};
use super::minimise::minimise;
use super::potential::{Linearisation, Potential};
use super::*;
use crate::fe::tangent_factor::TangentPattern;

/// Π(u) given by closures over n unknowns, its Hessian stored densely as the
/// lower triangle (row by row) followed by the n shift slots.
pub(super) struct Analytic {
    n: usize,
    energy: fn(&[f64]) -> f64,
    gradient: fn(&[f64]) -> Vec<f64>,
    /// The lower triangle of the Hessian, row by row.
    hessian: fn(&[f64]) -> Vec<f64>,
}

impl Analytic {
    /// Π = u₀² + 1.5 u₁²: K = diag(2, 3), positive definite.
    pub fn bowl() -> Analytic {
        Analytic {
            n: 2,
            energy: |u| u[0] * u[0] + 1.5 * u[1] * u[1],
            gradient: |u| vec![2.0 * u[0], 3.0 * u[1]],
            hessian: |_| vec![2.0, 0.0, 3.0],
        }
    }

    /// Π = ½ u₀² − ¼ u₁²: K = diag(1, −0.5), indefinite.
    pub fn saddle() -> Analytic {
        Analytic {
            n: 2,
            energy: |u| 0.5 * u[0] * u[0] - 0.25 * u[1] * u[1],
            gradient: |u| vec![u[0], -0.5 * u[1]],
            hessian: |_| vec![1.0, 0.0, -0.5],
        }
    }

    /// Π(u) = −cos u − 0.4 u: minima where sin u = 0.4 (u = 0.4115 + 2πk),
    /// Π'' = cos u, negative for π/2 < u < 3π/2. From u = −1.2 (Π'' =
    /// 0.36) the Newton step is +3.68, to u = 2.48 where Π'' = −0.79 yet the
    /// energy is lower (−0.20 against 0.12), so the line search takes it.
    pub fn cosine() -> Analytic {
        Analytic {
            n: 1,
            energy: |u| -u[0].cos() - 0.4 * u[0],
            gradient: |u| vec![u[0].sin() - 0.4],
            hessian: |u| vec![u[0].cos()],
        }
    }

    /// Π(u) = (u₀² − 1)² + u₁²: minima at u₀ = ±1, a saddle-like ridge
    /// (Π₀₀'' = 12u₀² − 4 < 0) for |u₀| < 0.577.
    fn double_well() -> Analytic {
        Analytic {
            n: 2,
            energy: |u| (u[0] * u[0] - 1.0).powi(2) + u[1] * u[1],
            gradient: |u| vec![4.0 * u[0] * (u[0] * u[0] - 1.0), 2.0 * u[1]],
            hessian: |u| vec![12.0 * u[0] * u[0] - 4.0, 0.0, 2.0],
        }
    }

    pub fn pattern(&self) -> TangentPattern {
        let mut pairs: Vec<Pair<usize, usize>> = (0..self.n)
            .flat_map(|i| (0..=i).map(move |j| Pair::new(i, j)))
            .collect();
        pairs.extend((0..self.n).map(|i| Pair::new(i, i)));
        TangentPattern::new(self.n, &pairs).unwrap()
    }

    fn solve(&self, from: &[f64], guard: bool) -> Result<(Vec<f64>, SolveStats), SolveError> {
        let pattern = self.pattern();
        let options = NewtonOptions {
            tolerance: 1e-12,
            definiteness_guard: guard,
            ..NewtonOptions::default()
        };
        minimise(self, &mut pattern.factor(), from.to_vec(), 1.0, &options)
    }
}

impl Potential for Analytic {
    fn dimension(&self) -> usize {
        self.n
    }

    fn linearise(&self, u: &[f64]) -> Option<Linearisation> {
        let mut values = (self.hessian)(u);
        values.extend(std::iter::repeat_n(0.0, self.n));
        Some(Linearisation::new(
            (self.energy)(u),
            (self.gradient)(u),
            values,
        ))
    }

    fn energy(&self, u: &[f64]) -> f64 {
        (self.energy)(u)
    }
}

#[test]
fn newton_converges_in_one_step_on_a_quadratic_bowl() {
    let (u, stats) = Analytic::bowl().solve(&[0.7, -1.3], true).unwrap();
    assert!(u.iter().all(|x| x.abs() < 1e-15), "{u:?}");
    assert_eq!(stats.iterations, 1);
    assert!(stats.stable);
}

#[test]
fn a_shifted_newton_leaves_the_ridge_of_a_double_well_for_a_stable_minimum() {
    // At u₀ = 0.1 K is indefinite (Π₀₀'' = −3.88): the first steps need a
    // shift; the solve ends in a minimum u₀ = ±1, u₁ = 0, stable.
    let (u, stats) = Analytic::double_well().solve(&[0.1, 0.5], true).unwrap();
    assert!(
        (u[0].abs() - 1.0).abs() < 1e-9 && u[1].abs() < 1e-9,
        "{u:?}"
    );
    assert!(stats.stable);
    // More factorisations than iterations: the shift's failed attempts.
    assert!(stats.factorisations > stats.iterations, "{stats:?}");
}

#[test]
fn the_guard_halves_a_step_that_lands_where_the_tangent_is_indefinite() {
    let cosine = Analytic::cosine();
    let pattern = cosine.pattern();
    let mut factor = pattern.factor();
    let u = [-1.2];
    let here = cosine.linearise(&u).unwrap();
    let next = vec![-1.2 + (0.4 - (-1.2_f64).sin()) / (-1.2_f64).cos()];
    assert!((next[0] - 2.48).abs() < 0.01 && next[0].cos() < -0.75);
    let mut stats = SolveStats::default();
    // After an unshifted step the end may need a shift of at most 1e-3 of
    // the mean tangent entry; at 2.48 it needs 0.79: halved once, to
    // u = 0.64, where K = cos 0.64 = 0.80 factorises unshifted.
    let mut guard = |guarding: bool| {
        let limit = ceiling(guarding, 0.0, here.stiffness);
        let start = (&u[..], here.potential);
        guard_definiteness(
            &cosine,
            &mut factor,
            start,
            (next.clone(), None),
            (0.0, limit),
            &mut stats,
        )
        .unwrap()
    };
    let guarded = guard(true);
    assert!((guarded.u[0] - (-1.2 + 0.5 * (next[0] + 1.2))).abs() < 1e-15);
    assert_eq!(guarded.factored_with, Ok(0.0));
    assert!(guarded.here.potential < here.potential);
    // The guard off: the line search's point stands, with the shift it needs.
    let unguarded = guard(false);
    assert_eq!(unguarded.u, next);
    assert!(unguarded.factored_with.unwrap() > 0.79);
}

#[test]
fn guarded_or_not_newton_finds_the_cosines_minimum_the_guard_in_fewer_factorisations() {
    let cosine = Analytic::cosine();
    let minimum = 0.4_f64.asin();
    let (guarded, with) = cosine.solve(&[-1.2], true).unwrap();
    let (unguarded, without) = cosine.solve(&[-1.2], false).unwrap();
    assert!((guarded[0] - minimum).abs() < 1e-9, "{guarded:?}");
    assert!((unguarded[0] - minimum).abs() < 1e-9, "{unguarded:?}");
    assert!(with.stable && without.stable);
    println!("guarded {with:?}\nunguarded {without:?}");
    assert!(with.factorisations < without.factorisations);
}

#[test]
fn a_start_outside_the_domain_or_at_a_non_finite_gradient_is_refused() {
    let nan = Analytic {
        n: 1,
        energy: |u| u[0].ln(),
        gradient: |u| vec![1.0 / u[0]],
        hessian: |u| vec![-1.0 / (u[0] * u[0])],
    };
    assert_eq!(
        nan.solve(&[0.0], true).unwrap_err(),
        SolveError::InadmissibleStart
    );
}

#[test]
fn a_bound_on_the_last_move_holds_a_loose_solve_until_its_steps_are_small() {
    // The double well from u₀ = 2: Newton's iterates 1.4545, 1.1511,
    // 1.0253, 1.00093, 1.0000012 (|∇Π| ≈ 1e-5). Residual 1e-3 alone stops
    // there, 1.2e-6 from the minimum, after a move of 9.3e-4; a bound of
    // 1e-6 on the last move goes on until a step of about 1e-12 (two more).
    let well = Analytic::double_well();
    let pattern = well.pattern();
    let solve = |step_tolerance: f64| {
        let options = NewtonOptions {
            tolerance: 1e-3,
            step_tolerance,
            ..NewtonOptions::default()
        };
        minimise(&well, &mut pattern.factor(), vec![2.0, 0.0], 1.0, &options).unwrap()
    };
    let (loose, loose_stats) = solve(f64::INFINITY);
    let (bounded, bounded_stats) = solve(1e-6);
    assert!(
        ((loose[0] - 1.0).abs() - 1.235e-6).abs() < 1e-9,
        "{loose:?}"
    );
    assert!((bounded[0] - 1.0).abs() < 1e-12, "{bounded:?}");
    assert_eq!(loose_stats.iterations, 5);
    assert_eq!(bounded_stats.iterations, 7);
}
