//! Issue 4's seeding evidence: KSA-seeded against unseeded CMA-ES on the
//! Hilbert reference curve — evaluations to reach the same objective.
//!
//! Both runs use the `draft` search model, the same balloon (length from
//! mechanics), the same objective and the same number of patches (KSA's six).
//! Seeded: CMA-ES starts from KSA's patches in windows around them (the
//! method). Unseeded (`Start::Even`): the six patches spread evenly along the
//! balloon, mid-range sizes, X = 0, Θ = 0, each free over the whole balloon.
//! Prints, per run, the best search objective against evaluations and the
//! evaluations each start needs to reach the KSA seed's own objective and the
//! seeded runs' median final objective.
//!
//! `cargo run --release -p patchwork-core --example seeding -- [budget] [runs]`
//! (defaults 400 and 3; about ten minutes on two cores).

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use patchwork_core::curve::ReferenceCurve;
use patchwork_core::inverse::{
    DesignProgress, Fidelity, Plan, StageName, Start, TuningOverrides, UserSettings, design,
};

/// One run's best objective after each generation, and its outcome.
struct Run {
    start_objective: f64,
    trajectory: Vec<(usize, f64)>,
    shape_error_percent: f64,
    wall_s: f64,
}

impl Run {
    /// Evaluations until the best objective first reached `target`.
    fn evaluations_to(&self, target: f64) -> Option<usize> {
        if self.start_objective <= target {
            return Some(1);
        }
        self.trajectory
            .iter()
            .find(|(_, best)| *best <= target)
            .map(|(evaluations, _)| *evaluations)
    }

    fn best(&self) -> f64 {
        self.trajectory
            .last()
            .map_or(self.start_objective, |(_, best)| *best)
    }
}

fn run(start: Start, budget: usize, seed: u64) -> Run {
    let target = ReferenceCurve::Hilbert.curve();
    let settings = UserSettings {
        fidelity: Fidelity::Draft,
        budget: Some(budget),
        threads: 2,
        seed,
        ..UserSettings::default()
    };
    let overrides = TuningOverrides {
        start: Some(start),
        ..TuningOverrides::default()
    };
    let plan = Plan::resolve(settings, &overrides).expect("valid settings");
    let mut trajectory = Vec::new();
    let mut observer = |p: &DesignProgress| {
        if p.stage == StageName::Search {
            trajectory.push((p.evaluations, p.best_objective));
        }
    };
    let cancel = AtomicBool::new(false);
    let started = Instant::now();
    let outcome = design(&target, &plan, &cancel, &mut observer).expect("the Hilbert design runs");
    Run {
        start_objective: outcome.seed_objective,
        trajectory,
        shape_error_percent: outcome.metrics.shape_error_percent,
        wall_s: started.elapsed().as_secs_f64(),
    }
}

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("numbers: budget runs"))
        .collect();
    let budget = args.first().copied().unwrap_or(400);
    let runs = args.get(1).copied().unwrap_or(3) as u64;
    let seeded: Vec<Run> = (1..=runs).map(|s| run(Start::Ksa, budget, s)).collect();
    let unseeded: Vec<Run> = (1..=runs).map(|s| run(Start::Even, budget, s)).collect();
    let ksa_objective = seeded[0].start_objective;
    let mut finals: Vec<f64> = seeded.iter().map(Run::best).collect();
    finals.sort_by(f64::total_cmp);
    let seeded_final = finals[finals.len() / 2];
    println!(
        "Hilbert, draft search model, budget {budget}; KSA seed objective {ksa_objective:.4}, seeded median final {seeded_final:.4}\n"
    );
    println!(
        "| start | CMA-ES seed | start objective | best after {budget} | evaluations to reach {ksa_objective:.4} (KSA seed) | evaluations to reach {seeded_final:.4} (seeded median final) | shape error % (verified) | wall s |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let show = |n: Option<usize>| n.map_or(format!("not within {budget}"), |n| n.to_string());
    for (name, list) in [("KSA", &seeded), ("unseeded", &unseeded)] {
        for (i, r) in list.iter().enumerate() {
            println!(
                "| {name} | {} | {:.4} | {:.4} | {} | {} | {:.2} | {:.0} |",
                i + 1,
                r.start_objective,
                r.best(),
                show(r.evaluations_to(ksa_objective)),
                show(r.evaluations_to(seeded_final)),
                r.shape_error_percent,
                r.wall_s
            );
        }
    }
}
