//! Issue 4's round-trip evidence: ten random feasible designs (seed 2026) on a
//! 150 mm balloon → simulate (the draft preset's finest model: its
//! correction's, on which it verifies) → design
//! from that centreline alone (balloon length from mechanics, draft preset,
//! budget 200, two threads) → shape error on the same model. Prints the table
//! in docs/studies.md. About two minutes:
//! `cargo run --release -p patchwork-core --example round_trips`
//!
//! Settings to compare, as `key=value` arguments: `fidelity=draft|standard|fine`
//! (the search, verification and correction models; the target is always
//! simulated on the model the result is verified on), `correction=none`
//! (refine and verify on the verification model, uncorrected), `budget=200`,
//! `sigma=0.2` (CMA-ES's initial step in the unit cube), `shape=10` (weight of
//! the shape error in the objective), `polish=0` (CMA-ES polish evaluations on
//! the verification model), `refine=N` (solves of the Levenberg–Marquardt
//! refine there; default the fidelity's), `trips=10`, `search=verify` (search
//! on the verification model itself: no model error in the loop), `out=DIR`
//! (write each trip's design.json there as `trip-N.json`, to compare builds).

use std::sync::atomic::AtomicBool;

use patchwork_core::cmaes::SeededRng;
use patchwork_core::design::{Balloon, Design, Patch};
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::inverse::{
    DesignReport, Fidelity, INITIAL_STEP, ObjectiveOptions, Plan, UserSettings, design,
};

/// The `key=value` settings of one comparison.
struct Settings {
    fidelity: Fidelity,
    budget: usize,
    sigma: f64,
    shape: f64,
    polish: usize,
    refine: Option<usize>,
    trips: u64,
    search_on_verify: bool,
    uncorrected: bool,
    out: Option<std::path::PathBuf>,
}

fn settings() -> Settings {
    let mut s = Settings {
        fidelity: Fidelity::Draft,
        budget: 200,
        sigma: INITIAL_STEP,
        shape: ObjectiveOptions::default().shape_weight,
        polish: 0,
        refine: None,
        trips: 10,
        search_on_verify: false,
        uncorrected: false,
        out: None,
    };
    for arg in std::env::args().skip(1) {
        let (key, value) = arg.split_once('=').expect("arguments are key=value");
        let number = || value.parse::<f64>().expect("a number");
        match key {
            "fidelity" => s.fidelity = value.parse().expect("a fidelity name"),
            "budget" => s.budget = number() as usize,
            "sigma" => s.sigma = number(),
            "shape" => s.shape = number(),
            "polish" => s.polish = number() as usize,
            "refine" => s.refine = Some(number() as usize),
            "trips" => s.trips = number() as u64,
            "search" if value == "verify" => s.search_on_verify = true,
            "correction" if value == "none" => s.uncorrected = true,
            "out" => s.out = Some(value.into()),
            _ => panic!("unknown setting {key}"),
        }
    }
    s
}

fn main() {
    let settings = settings();
    println!(
        "fidelity {:?}, budget {}, σ₀ {}, shape weight {}, polish {}, refine {}, corrected: {}, search on the verification model: {}",
        settings.fidelity,
        settings.budget,
        settings.sigma,
        settings.shape,
        settings.polish,
        settings.refine.unwrap_or(settings.fidelity.refine_budget()),
        !settings.uncorrected,
        settings.search_on_verify
    );
    let mut rng = SeededRng::new(2026);
    let mut errors = Vec::new();
    println!(
        "| # | true patches (x, y, h, w, Θ) | length cut / true (mm) | seed → final objective | shape error % | evaluations | wall s |"
    );
    println!("|---|---|---|---|---|---|---|");
    for trip in 1..=settings.trips {
        let mut between = |lo: f64, hi: f64| lo + (hi - lo) * rng.uniform();
        let count = if between(0.0, 1.0) < 0.5 { 1 } else { 2 };
        let centres: &[(f64, f64)] = if count == 1 {
            &[(40.0, 110.0)]
        } else {
            &[(30.0, 60.0), (90.0, 120.0)]
        };
        let circumference = Balloon::default().circumference();
        let patches: Vec<Patch> = centres
            .iter()
            .map(|&(lo, hi)| Patch {
                x_mm: between(0.0, circumference),
                y_mm: between(lo, hi),
                h_mm: between(10.0, 25.0),
                w_mm: between(1.5, 3.0),
                theta_deg: between(-30.0, 30.0),
            })
            .collect();
        let truth = Design {
            balloon: Balloon {
                length_mm: 150.0,
                ..Balloon::default()
            },
            ..Design::reference(patches.clone())
        };
        let user = UserSettings {
            base: Design {
                patches: vec![],
                ..truth.clone()
            },
            fidelity: settings.fidelity,
            budget: Some(settings.budget),
            seed: trip,
            threads: 2,
            ..UserSettings::default()
        };
        let mut tuning = settings.fidelity.tuning(user.base.balloon.radius_mm);
        tuning.initial_step = settings.sigma;
        tuning.objective.shape_weight = settings.shape;
        tuning.polish_budget = settings.polish;
        if let Some(refine) = settings.refine {
            tuning.refine_budget = refine;
        }
        if settings.uncorrected {
            tuning.correction_mesh = None;
        }
        if settings.search_on_verify {
            tuning.search_mesh = tuning.verify_mesh;
        }
        // The target comes from the model the result is verified on.
        let model = SimulateOptions {
            mesh: tuning.correction_mesh.unwrap_or(tuning.verify_mesh),
            ..SimulateOptions::default()
        };
        let plan = Plan::with_tuning(user, tuning).expect("valid settings");
        let target = simulate(&truth, &model)
            .expect("a feasible design")
            .centreline;
        let outcome = design(&target, &plan, &AtomicBool::new(false), &mut |_| {})
            .expect("the round trip designs");
        let shown: Vec<String> = patches
            .iter()
            .map(|p| {
                format!(
                    "({:.1}, {:.1}, {:.1}, {:.1}, {:.0}°)",
                    p.x_mm, p.y_mm, p.h_mm, p.w_mm, p.theta_deg
                )
            })
            .collect();
        println!(
            "| {trip} | {} | {:.1} / 150 | {:.3} → {:.3} | {:.2} | {} | {:.1} |",
            shown.join(" "),
            outcome.uninflated_length_to_cut_mm,
            outcome.seed_objective,
            outcome.search_objective,
            outcome.metrics.shape_error_percent,
            outcome.evaluations,
            outcome.elapsed.as_secs_f64()
        );
        assert!(outcome.metrics.shape_error_percent.is_finite());
        if let Some(dir) = &settings.out {
            std::fs::create_dir_all(dir).expect("the out folder");
            let report = DesignReport::new(&outcome, trip);
            let text = serde_json::to_string_pretty(&report).expect("serialises");
            std::fs::write(dir.join(format!("trip-{trip}.json")), text).expect("writes");
        }
        errors.push(outcome.metrics.shape_error_percent);
    }
    errors.sort_by(f64::total_cmp);
    let n = errors.len();
    let under = errors.iter().filter(|&&e| e < 0.5).count();
    println!(
        "median shape error {:.2} %, worst {:.2} %, {under}/{n} under the 0.5 % goal",
        (errors[(n - 1) / 2] + errors[n / 2]) / 2.0,
        errors[n - 1]
    );
}
