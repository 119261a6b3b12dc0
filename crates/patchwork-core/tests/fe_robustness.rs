//! 200 random six-patch designs within the authors' bounds (fixed seed): every
//! one converges to a stable equilibrium with finite numbers — within the
//! fabrication bounds no design may fail to solve. The Newton iterations and
//! factorisations are printed.

use std::time::Duration;

use patchwork_core::cmaes::SeededRng;
use patchwork_core::design::{Design, Patch};
use patchwork_core::fe::newton::NewtonOptions;
use patchwork_core::fe::{SimulateOptions, simulate};

fn uniform(rng: &mut SeededRng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.uniform()
}

/// KSA seeds of the Hilbert reference curve (DESIGN.md), mm.
const SEED_Y: [f64; 6] = [43.3, 87.9, 128.2, 163.9, 204.8, 248.8];

/// Random designs solved.
const CASES: usize = 200;

#[test]
fn every_random_design_within_the_bounds_converges_to_a_stable_state() {
    let mut rng = SeededRng::new(20231121);
    let options = SimulateOptions {
        newton: NewtonOptions {
            time_limit: Duration::from_secs(20),
            ..NewtonOptions::default()
        },
        ..SimulateOptions::default()
    };
    let circumference = std::f64::consts::TAU * 3.18;
    let designs: Vec<Design> = (0..CASES)
        .map(|_| {
            let patches = SEED_Y
                .iter()
                .map(|&y| Patch {
                    x_mm: uniform(&mut rng, 0.0, circumference),
                    y_mm: y + uniform(&mut rng, -5.0, 5.0),
                    h_mm: uniform(&mut rng, 10.0, 30.0),
                    w_mm: uniform(&mut rng, 1.0, 3.0),
                    theta_deg: uniform(&mut rng, -45.0, 45.0),
                })
                .collect();
            Design::reference(patches)
        })
        .collect();
    let started = std::time::Instant::now();
    // The cases on every core (the test binary has no other test to run
    // beside it); each checked where it was solved.
    let threads = patchwork_core::available_cores().min(4);
    let solved: Vec<(usize, usize)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                let (designs, options) = (&designs, &options);
                scope.spawn(move || {
                    (t..CASES)
                        .step_by(threads)
                        .map(|case| checked(case, &designs[case], options))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        (workers.into_iter())
            .flat_map(|w| w.join().expect("a worker panicked: see its case above"))
            .collect()
    });
    let mut iterations: Vec<usize> = solved.iter().map(|s| s.0).collect();
    let factorisations: usize = solved.iter().map(|s| s.1).sum();
    iterations.sort_unstable();
    println!(
        "robustness: {CASES}/{CASES} converged and stable; Newton iterations median {} max {} total {}; {factorisations} factorisations; {:.1} s on {threads} threads",
        iterations.get(iterations.len() / 2).copied().unwrap_or(0),
        iterations.last().copied().unwrap_or(0),
        iterations.iter().sum::<usize>(),
        started.elapsed().as_secs_f64()
    );
}

/// Solves `design` (case `case`) and checks its state: converged, stable,
/// finite, inflated; its Newton iterations and factorisations.
fn checked(case: usize, design: &Design, options: &SimulateOptions) -> (usize, usize) {
    let sim = simulate(design, options).unwrap_or_else(|e| panic!("case {case}: {e}"));
    assert!(sim.stats.stable, "case {case}: not a stable state");
    assert!(
        sim.centreline
            .points()
            .iter()
            .all(|p| p.iter().all(|v| v.is_finite())),
        "case {case}: a centreline point is not finite"
    );
    assert!(
        sim.curvature
            .iter()
            .chain(&sim.torsion)
            .all(|v| v.is_finite()),
        "case {case}: κ or τ not finite"
    );
    assert!(
        sim.inflated_length_mm.is_finite() && sim.inflated_length_mm > 292.0,
        "case {case}: inflated {} mm",
        sim.inflated_length_mm
    );
    (sim.stats.iterations, sim.stats.factorisations)
}
