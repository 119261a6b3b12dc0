//! CMA-ES against pycma's own behaviour, and the loop's guarantees.
//!
//! Reference figures: pycma 4.5.0 (`cma.CMAEvolutionStrategy(x0, σ0,
//! {'seed': s, 'ftarget': 1e-8})`, default options, seeds 1..=11), median
//! evaluations to f < 1e-8 in 10-D:
//!   sphere, x0 = 3·1, σ0 = 2:       1430  (11/11 reached)
//!   ellipsoid (cond 1e6), same:     4270  (11/11)
//!   Rosenbrock, x0 = 0, σ0 = 0.5:   4875  (10/11)
//! The issue asks for medians within 1.5× of these. pycma uses active CMA
//! (negative weights) by default; this implementation has positive weights only.

use std::sync::atomic::{AtomicBool, Ordering};

use patchwork_core::cmaes::{Bounds, Optimizer, Progress, RunOptions, Termination};

fn sphere(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum()
}

fn ellipsoid(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    x.iter()
        .enumerate()
        .map(|(i, v)| 10f64.powf(6.0 * i as f64 / (n - 1.0)) * v * v)
        .sum()
}

fn rosenbrock(x: &[f64]) -> f64 {
    x.windows(2)
        .map(|w| 100.0 * (w[1] - w[0] * w[0]).powi(2) + (1.0 - w[0]).powi(2))
        .sum()
}

fn median_evaluations(f: fn(&[f64]) -> f64, x0: f64, sigma0: f64) -> (f64, usize) {
    let mut evaluations = Vec::new();
    for seed in 1..=11 {
        let mut options = RunOptions::new(vec![x0; 10], sigma0, seed);
        options.target = Some(1e-8);
        options.max_evaluations = 100_000;
        let result = Optimizer::new(options).run(&f, &mut |_: &Progress| true);
        if result.termination == Termination::TargetReached {
            evaluations.push(result.evaluations as f64);
        }
    }
    let reached = evaluations.len();
    evaluations.sort_by(f64::total_cmp);
    (evaluations[reached / 2], reached)
}

#[test]
fn sphere_within_one_and_a_half_times_pycma() {
    let (median, reached) = median_evaluations(sphere, 3.0, 2.0);
    println!("sphere: median {median} evaluations ({reached}/11); pycma 1430");
    assert_eq!(reached, 11);
    assert!(median <= 1.5 * 1430.0);
}

#[test]
fn ellipsoid_within_one_and_a_half_times_pycma() {
    let (median, reached) = median_evaluations(ellipsoid, 3.0, 2.0);
    println!("ellipsoid: median {median} evaluations ({reached}/11); pycma 4270");
    assert_eq!(reached, 11);
    assert!(median <= 1.5 * 4270.0);
}

#[test]
fn rosenbrock_within_one_and_a_half_times_pycma() {
    let (median, reached) = median_evaluations(rosenbrock, 0.0, 0.5);
    println!("Rosenbrock: median {median} evaluations ({reached}/11); pycma 4875");
    assert!(reached >= 9);
    assert!(median <= 1.5 * 4875.0);
}

#[test]
fn bounded_points_are_never_evaluated_outside_the_box() {
    let violated = AtomicBool::new(false);
    let objective = |x: &[f64]| {
        if x.iter().any(|v| !(1.0..=2.0).contains(v)) {
            violated.store(true, Ordering::Relaxed);
        }
        // Optimum outside the box: the answer is on the lower bound.
        x.iter().map(|v| (v + 1.0).powi(2)).sum::<f64>()
    };
    let mut options = RunOptions::new(vec![1.5; 4], 1.0, 3);
    options.bounds = Some(Bounds::new(vec![1.0; 4], vec![2.0; 4]).unwrap());
    options.max_evaluations = 3000;
    let result = Optimizer::new(options).run(&objective, &mut |_: &Progress| true);
    assert!(!violated.load(Ordering::Relaxed));
    assert!(
        result.x.iter().all(|v| (v - 1.0).abs() < 1e-3),
        "{:?}",
        result.x
    );
}

#[test]
fn checkpoint_and_resume_reproduce_the_run_exactly() {
    let mut options = RunOptions::new(vec![3.0; 6], 2.0, 11);
    options.max_evaluations = 2000;
    let mut straight = Optimizer::new(options.clone());
    let expected = straight.run(&ellipsoid, &mut |_: &Progress| true);

    let mut first = Optimizer::new(options);
    for _ in 0..40 {
        first.step(&ellipsoid);
    }
    let checkpoint = serde_json::to_string(&first).unwrap();
    let mut resumed: Optimizer = serde_json::from_str(&checkpoint).unwrap();
    let result = resumed.run(&ellipsoid, &mut |_: &Progress| true);
    assert_eq!(result, expected);
}

#[test]
fn parallel_evaluation_gives_the_same_run_and_seeds_reproduce() {
    let run = |threads: usize, seed: u64| {
        let mut options = RunOptions::new(vec![0.0; 8], 0.5, seed);
        options.max_evaluations = 1500;
        options.threads = threads;
        Optimizer::new(options).run(&rosenbrock, &mut |_: &Progress| true)
    };
    assert_eq!(run(1, 5), run(3, 5));
    assert_ne!(run(1, 5).x, run(1, 6).x);
}

#[test]
fn ipop_restarts_double_the_population() {
    // Rastrigin: many local minima, tolerance stops trigger restarts.
    let rastrigin = |x: &[f64]| -> f64 {
        10.0 * x.len() as f64
            + x.iter()
                .map(|v| v * v - 10.0 * (std::f64::consts::TAU * v).cos())
                .sum::<f64>()
    };
    let mut options = RunOptions::new(vec![2.0; 5], 2.0, 1);
    options.max_restarts = 4;
    options.tol_fun = 1e-9;
    options.max_evaluations = 60_000;
    let mut optimizer = Optimizer::new(options);
    let first_lambda = optimizer.strategy.params.lambda;
    let result = optimizer.run(&rastrigin, &mut |_: &Progress| true);
    assert!(result.restarts >= 1, "{result:?}");
    assert_eq!(
        optimizer.strategy.params.lambda,
        first_lambda << result.restarts
    );
    assert!(result.fitness < rastrigin(&[2.0; 5]));
}

#[test]
fn observer_can_cancel() {
    let mut options = RunOptions::new(vec![3.0; 5], 1.0, 2);
    options.max_evaluations = 100_000;
    let mut seen = 0;
    let result = Optimizer::new(options).run(&sphere, &mut |p: &Progress| {
        seen += 1;
        p.generation < 5
    });
    assert_eq!(result.termination, Termination::Cancelled);
    assert_eq!(seen, 5);
}
