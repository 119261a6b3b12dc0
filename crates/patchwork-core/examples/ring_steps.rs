//! Newton's steps taken linearly against ring by ring
//! (`fe::newton::Steps`), on designs' solves: each design.json's design
//! solved cold on the spread's model (graded 1 mm); then each spread source
//! at its default tolerance and `PERTURBED` random moves of the design
//! (every patch's X, Y by up to ±`MOVE_MM`, Θ by up to ±`MOVE_DEG`,
//! seeded), warm-started from the nominal. The cold solves and the moves
//! are solved to the default residual (1e-9) both ways; the sources also to
//! a loose residual (`LOOSE`, 1e-5), with and without a bound on the last
//! iteration's move (`SOURCE_STEP_MM`). Per kind of solve and
//! rule: Newton iterations and time, and the largest distance of its
//! centreline from the linear 1e-9 solve's (same fractions of length).
//!
//! `cargo run --release -p patchwork-core --example ring_steps -- DESIGN.json…`

use std::time::Instant;

use patchwork_core::cmaes::SeededRng;
use patchwork_core::curve::Curve;
use patchwork_core::design::Design;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::newton::{PatternCache, Steps};
use patchwork_core::fe::{SimulateOptions, Simulation, simulate, simulate_with};
use patchwork_core::spread::{Source, Tolerances};

#[path = "common/design_json.rs"]
mod design_json;

const PERTURBED: usize = 6;
const MOVE_MM: f64 = 1.0;
const MOVE_DEG: f64 = 3.0;
/// The loose residual compared with 1e-9 (the spread's solves step ring
/// by ring to `spread::SOURCE_TOLERANCE`, 1e-7, their last move bounded).
const LOOSE: f64 = 1e-5;
/// The bound on the last iteration's largest move tried with the loose
/// residual (mm).
const SOURCE_STEP_MM: f64 = 1e-3;

fn options(steps: Steps, tolerance: f64, step_mm: f64) -> SimulateOptions {
    let mut o = SimulateOptions {
        mesh: MeshSpec::graded(1.0, 4.0),
        threads: 1,
        ..SimulateOptions::default()
    };
    o.newton.steps = steps;
    o.newton.tolerance = tolerance;
    o.newton.step_tolerance = step_mm;
    o
}

/// Largest distance between two centrelines at 200 equal fractions of length.
fn apart(a: &Curve, b: &Curve) -> f64 {
    let (a, b) = (a.resample(200).expect("a"), b.resample(200).expect("b"));
    (a.points().iter().zip(b.points()))
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

/// One rule's solves of one kind.
#[derive(Default, Clone)]
struct Tally {
    solves: usize,
    iterations: usize,
    seconds: f64,
    apart_mm: Vec<f64>,
    failed: usize,
}

impl Tally {
    fn add(&mut self, run: Option<(Simulation, f64)>, reference: &Curve) {
        self.solves += 1;
        match run {
            Some((sim, s)) => {
                self.iterations += sim.stats.iterations;
                self.seconds += s;
                self.apart_mm.push(apart(&sim.centreline, reference));
            }
            None => self.failed += 1,
        }
    }

    fn row(&mut self, kind: &str, rule: &str) {
        let n = self.solves as f64;
        self.apart_mm.sort_by(f64::total_cmp);
        let median = self.apart_mm.get(self.apart_mm.len() / 2).copied();
        let largest = self.apart_mm.last().copied();
        println!(
            "| {kind} | {rule} | {} | {:.1} | {:.2} | {:.1e} | {:.1e} | {} |",
            self.solves,
            self.iterations as f64 / n,
            self.seconds / n,
            median.unwrap_or(f64::NAN),
            largest.unwrap_or(f64::NAN),
            self.failed,
        );
    }
}

fn timed(run: impl FnOnce() -> Option<Simulation>) -> Option<(Simulation, f64)> {
    let started = Instant::now();
    run().map(|sim| (sim, started.elapsed().as_secs_f64()))
}

fn perturbed(design: &Design, rng: &mut SeededRng) -> Design {
    let mut d = design.clone();
    for p in &mut d.patches {
        p.x_mm += MOVE_MM * (2.0 * rng.uniform() - 1.0);
        p.y_mm += MOVE_MM * (2.0 * rng.uniform() - 1.0);
        p.theta_deg += MOVE_DEG * (2.0 * rng.uniform() - 1.0);
    }
    d
}

fn main() {
    let loose = format!("residual {LOOSE:e}");
    let bounded = format!("{loose}, last move ≤ {SOURCE_STEP_MM} mm");
    let rules: Vec<(String, SimulateOptions)> = vec![
        (
            "linear, 1e-9".into(),
            options(Steps::Linear, 1e-9, f64::INFINITY),
        ),
        (
            "rings, 1e-9".into(),
            options(Steps::Rings, 1e-9, f64::INFINITY),
        ),
        (
            format!("linear, {loose}"),
            options(Steps::Linear, LOOSE, f64::INFINITY),
        ),
        (
            format!("rings, {loose}"),
            options(Steps::Rings, LOOSE, f64::INFINITY),
        ),
        (
            format!("linear, {bounded}"),
            options(Steps::Linear, LOOSE, SOURCE_STEP_MM),
        ),
        (
            format!("rings, {bounded}"),
            options(Steps::Rings, LOOSE, SOURCE_STEP_MM),
        ),
    ];
    let tolerances = Tolerances::default();
    let mut cold = vec![Tally::default(); 2];
    let mut moves = vec![Tally::default(); 2];
    let mut sources = vec![Tally::default(); rules.len()];
    let mut rng = SeededRng::new(1);
    for path in std::env::args().skip(1) {
        let design = design_json::design_of(&path);
        let Some((start, s)) = timed(|| simulate(&design, &rules[0].1).ok()) else {
            eprintln!("{path}: the design does not inflate");
            continue;
        };
        cold[0].add(Some((start.clone(), s)), &start.centreline);
        cold[1].add(
            timed(|| simulate(&design, &rules[1].1).ok()),
            &start.centreline,
        );
        let patterns = PatternCache::default();
        let warm = |d: &Design, o: &SimulateOptions| {
            timed(|| simulate_with(d, o, Some(&start), &patterns).ok())
        };
        let kind = |moved: &Design, tallies: &mut [Tally]| {
            let Some((exact, s)) = warm(moved, &rules[0].1) else {
                tallies.iter_mut().for_each(|t| t.failed += 1);
                return;
            };
            let reference = exact.centreline.clone();
            tallies[0].add(Some((exact, s)), &reference);
            for (tally, (_, o)) in tallies.iter_mut().zip(&rules).skip(1) {
                tally.add(warm(moved, o), &reference);
            }
        };
        for source in Source::all(&design, &tolerances) {
            kind(
                &source.moved(&design, source.tolerance(&tolerances).0),
                &mut sources,
            );
        }
        for _ in 0..PERTURBED {
            kind(&perturbed(&design, &mut rng), &mut moves);
        }
        eprintln!("{path}: done");
    }
    println!(
        "| solves | rule | count | Newton iterations | s per solve | from linear 1e-9, median mm | largest mm | failed |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (tally, (rule, _)) in cold.iter_mut().zip(&rules) {
        tally.row("cold", rule);
    }
    for (tally, (rule, _)) in sources.iter_mut().zip(&rules) {
        tally.row("spread sources, warm", rule);
    }
    let moved = format!("moves ±{MOVE_MM} mm, ±{MOVE_DEG}°, warm");
    for (tally, (rule, _)) in moves.iter_mut().zip(&rules) {
        tally.row(&moved, rule);
    }
}
