//! Where a preset's time goes and what its error is on the common reference
//! model (uniform 0.5 mm), for one reference curve, seed by seed: the study
//! behind the presets' search budgets and refine settings.
//!
//! `cargo run --release -p patchwork-core --example preset_study -- [key=value ...]`
//!
//! Settings: `curve=hilbert|pancake|spring`, `fidelity=draft|standard|fine`
//! (the preset the others modify), `budget=N` (search evaluations; default
//! the preset's), `refine=N` (refine solves; default the preset's),
//! `correction=none|preset|MM|MM/MM` (the uniform or graded mesh whose
//! centreline corrects the refine's model; default the preset's),
//! `refine_mesh=search|MM|MM/MM` (the model the refine solves on: the search's
//! own, or a uniform or graded mesh; default the preset's verification
//! model), `patience=N` (the search's), `seeds=3`, `progress=1` (print every
//! stage and generation), `warm=1` (the search's solves start from the best
//! design's state instead of the kinematic estimate).

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use patchwork_core::curve::ReferenceCurve;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::inverse::{DesignProgress, Fidelity, Plan, UserSettings, assess, design};

/// `MM` (uniform) or `MM/MM` (graded: under patches / bare stretches).
fn mesh(value: &str) -> MeshSpec {
    let number = |v: &str| v.parse::<f64>().expect("a number");
    match value.split_once('/') {
        Some((fine, straight)) => MeshSpec::graded(number(fine), number(straight)),
        None => MeshSpec::uniform(number(value)),
    }
}

fn main() {
    let mut curve = ReferenceCurve::Hilbert;
    let mut fidelity = Fidelity::Draft;
    let mut budget = None;
    let mut refine = None;
    let mut correction: Option<Option<MeshSpec>> = None;
    let mut refine_mesh: Option<Option<MeshSpec>> = None;
    let mut patience = None;
    let mut seeds = 3;
    let mut progress = false;
    let mut warm = false;
    for arg in std::env::args().skip(1) {
        let (key, value) = arg.split_once('=').expect("arguments are key=value");
        let number = || value.parse::<f64>().expect("a number");
        match key {
            "curve" => {
                curve = match value {
                    "hilbert" => ReferenceCurve::Hilbert,
                    "pancake" => ReferenceCurve::Pancake,
                    "spring" => ReferenceCurve::Spring,
                    _ => panic!("curve is hilbert, pancake or spring"),
                }
            }
            "fidelity" => fidelity = value.parse().expect("a fidelity name"),
            "budget" => budget = Some(number() as usize),
            "refine" => refine = Some(number() as usize),
            "correction" if value == "none" => correction = Some(None),
            "correction" if value == "preset" => correction = None,
            "correction" => correction = Some(Some(mesh(value))),
            "refine_mesh" if value == "search" => refine_mesh = Some(None),
            "refine_mesh" => refine_mesh = Some(Some(mesh(value))),
            "patience" => patience = Some(number() as usize),
            "seeds" => seeds = number() as u64,
            "progress" => progress = value == "1",
            "warm" => warm = value == "1",
            _ => panic!("unknown setting {key}"),
        }
    }
    let target = curve.curve();
    let reference = MeshSpec::uniform(0.5);
    println!(
        "| seed | wall s | evaluations | refine solves | shape error % (own) | shape error % (reference 0.5 mm) |"
    );
    println!("|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    for seed in 1..=seeds {
        let settings = UserSettings {
            fidelity,
            seed,
            threads: 2,
            budget,
            ..UserSettings::default()
        };
        let mut tuning = fidelity.tuning(settings.base.balloon.radius_mm);
        tuning.warm_starts = warm;
        if let Some(refine) = refine {
            tuning.refine_budget = refine;
        }
        if let Some(mesh) = refine_mesh {
            tuning.verify_mesh = mesh.unwrap_or(tuning.search_mesh);
        }
        if let Some(patience) = patience {
            tuning.search_patience = patience;
        }
        if let Some(correction) = correction {
            tuning.correction_mesh = correction;
        }
        let plan = Plan::with_tuning(settings, tuning).expect("valid settings");
        let started = Instant::now();
        let mut observer = |p: &DesignProgress| {
            if progress {
                eprintln!(
                    "{:?} {} after {} evaluations: best objective {:.4} ({:.1} s)",
                    p.stage, p.generation, p.evaluations, p.best_objective, p.elapsed_s
                )
            }
        };
        let outcome = design(&target, &plan, &AtomicBool::new(false), &mut observer)
            .expect("the design runs");
        let wall = started.elapsed().as_secs_f64();
        let on_reference = assess(&target, &outcome.design, reference, plan.tuning())
            .map_or(f64::NAN, |m| m.shape_error_percent);
        println!(
            "| {seed} | {wall:.1} | {} | {} | {:.3} | {on_reference:.3} |",
            outcome.evaluations,
            outcome.refine.map_or(0, |r| r.solves),
            outcome.metrics.shape_error_percent
        );
        rows.push((wall, on_reference));
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    println!(
        "median: {:.1} s, {:.3} % on the reference model",
        median(rows.iter().map(|r| r.0).collect()),
        median(rows.iter().map(|r| r.1).collect())
    );
}
