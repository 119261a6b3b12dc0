//! Running a suite: each curve under each setting, once per seed.
//!
//! Every run reports its error twice: on its own verification model, and with
//! its design re-simulated on one common reference model (`REFERENCE_MESH`) —
//! a coarse preset's own verification flatters it, so only the second compares
//! settings fairly. The plot uses the reference error; the re-simulation is not
//! part of the wall time.

use std::cell::Cell;
use std::ops::RangeInclusive;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::Result;
use patchwork_core::curve::{Curve, shape_error};
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::simulate;
use patchwork_core::inverse::input::prepare;
use patchwork_core::inverse::objective::SHAPE_SAMPLES;
use patchwork_core::inverse::{
    DesignOutcome, DesignProgress, Plan, Smoothing, StageName, UserSettings, design,
};

use super::args::BenchArgs;
use super::cases::{Setting, Suite, Target, laid_over};
use super::curves_out::write_curves;
use super::row::{Row, Sample, median};
use super::suite::suite;

/// The common model every run's design is re-simulated on: the finest
/// verification model of the presets.
const REFERENCE_MESH: MeshSpec = MeshSpec {
    element_mm: 0.5,
    around: None,
    straight_mm: None,
};

/// The curves of `which` that `--curves` names (all when it names none),
/// each under the settings `keep` keeps, measured in order at seeds
/// 1..=`--runs`; the curves first written to `curves_to` where given.
pub fn measure_suite(
    which: Suite,
    keep: impl Fn(&Setting) -> bool,
    args: &BenchArgs,
    curves_to: Option<&Path>,
) -> Result<Vec<Row>> {
    measure_at_seeds(which, keep, args, 1..=args.runs as u64, curves_to)
}

/// [`measure_suite`] at `seeds`, first writing the curves it designs to
/// `curves_to` where given ([`write_curves`]).
pub fn measure_at_seeds(
    which: Suite,
    keep: impl Fn(&Setting) -> bool,
    args: &BenchArgs,
    seeds: RangeInclusive<u64>,
    curves_to: Option<&Path>,
) -> Result<Vec<Row>> {
    let (mut curves, mut settings) = suite(which)?;
    curves.retain(|t| {
        args.curves.is_empty()
            || args
                .curves
                .iter()
                .any(|f| t.name.to_lowercase().contains(&f.to_lowercase()))
    });
    settings.retain(|s| keep(s));
    anyhow::ensure!(
        !curves.is_empty() && !settings.is_empty(),
        "--curves/--settings select nothing from the {which:?} suite"
    );
    if let Some(dir) = curves_to {
        write_curves(dir, &curves)?;
    }
    let mut rows = Vec::new();
    for target in &curves {
        for setting in &settings {
            let row = measure_row(target, setting, args, seeds.clone())?;
            eprintln!(
                "{:<40} {:<24} {:>8.2} s {:>6.0} evals {:>6.2} % (reference model {:.2} %), {} patches, {} beyond limits",
                row.curve,
                row.setting,
                row.figures.wall_s,
                row.figures.evaluations,
                row.figures.shape_error_percent,
                row.figures.reference_error_percent,
                row.figures.patches,
                row.figures.beyond_limits
            );
            rows.push(row);
        }
    }
    Ok(rows)
}

/// `setting` on `target`, once per seed of `seeds`: the medians (the most
/// beyond limits), the reach verdict and the failures.
fn measure_row(
    target: &Target,
    setting: &Setting,
    args: &BenchArgs,
    seeds: RangeInclusive<u64>,
) -> Result<Row> {
    let several = seeds != (1..=1);
    let mut samples = Vec::new();
    let mut failures = 0;
    let mut reach = String::from("–");
    let mut aimed: Option<Curve> = None;
    let mut stages = Vec::new();
    let mut first = None;
    for seed in seeds {
        let settings = UserSettings {
            fidelity: setting.fidelity,
            budget: Some(setting.budget),
            seed,
            threads: args.threads,
            ..UserSettings::default()
        };
        let overrides = laid_over(&setting.overrides(), &args.overrides)?;
        let plan = Plan::resolve(settings, &overrides)?;
        // Each run is timed as a fresh process would run it: with caches
        // of its own.
        let started = Instant::now();
        let spread_from = Cell::new(f64::NAN);
        let mut observe = stage_clock(StageName::Spread, started, &spread_from);
        match design(&target.curve, &plan, &AtomicBool::new(false), &mut observe) {
            Ok(o) => {
                let wall_s = started.elapsed().as_secs_f64();
                reach = verdict(&o);
                if first.is_none() {
                    stages = o.stage_times.iter().map(|t| (t.stage, t.seconds)).collect();
                    first = Some(o.design.clone());
                }
                // The target the runs aimed at: smoothed as they smoothed
                // it, the same for every seed.
                if aimed.is_none() {
                    let kappa_tol = plan.tuning().kappa_tol;
                    aimed = Some(prepare(&target.curve, Smoothing::Auto, kappa_tol)?.0);
                }
                if let Some(aimed) = &aimed {
                    let times = (wall_s, wall_s - spread_from.get());
                    let run = sample(target, aimed, &plan, &o, times);
                    if several {
                        eprintln!(
                            "  {}, {}, seed {seed}: {}",
                            target.name,
                            setting.name,
                            one_run(&run)
                        );
                    }
                    samples.push(run);
                }
            }
            Err(e) => {
                eprintln!("{}, {}, seed {seed}: {e}", target.name, setting.name);
                failures += 1;
            }
        }
    }
    Ok(Row {
        curve: target.name.clone(),
        setting: setting.name.to_string(),
        figures: medians(&samples),
        runs: samples,
        reach,
        failures,
        stages,
        design: first,
    })
}

/// Each figure's median over `samples` (the most beyond limits).
fn medians(samples: &[Sample]) -> Sample {
    let column = |f: fn(&Sample) -> f64| median(samples.iter().map(f).collect());
    Sample {
        wall_s: column(|s| s.wall_s),
        evaluations: column(|s| s.evaluations),
        shape_error_percent: column(|s| s.shape_error_percent),
        reference_error_percent: column(|s| s.reference_error_percent),
        clean_error_percent: column(|s| s.clean_error_percent),
        dtw_curvature: column(|s| s.dtw_curvature),
        dtw_torsion: column(|s| s.dtw_torsion),
        patches: column(|s| s.patches),
        beyond_limits: samples.iter().map(|s| s.beyond_limits).fold(0.0, f64::max),
        spread_s: column(|s| s.spread_s),
        spread_percent: column(|s| s.spread_percent),
    }
}

/// One run's time and shape errors, for the log of a case run with
/// several seeds.
fn one_run(run: &Sample) -> String {
    format!(
        "{:.2} s, {:.2} % (reference model {:.2} %)",
        run.wall_s, run.shape_error_percent, run.reference_error_percent
    )
}

/// An observer of a run begun at `started` that sets `at` to the seconds
/// at which `stage` began (left as it is if the stage never runs).
pub fn stage_clock(
    stage: StageName,
    started: Instant,
    at: &Cell<f64>,
) -> impl FnMut(&DesignProgress) + '_ {
    move |p: &DesignProgress| {
        if p.stage == stage && at.get().is_nan() {
            at.set(started.elapsed().as_secs_f64());
        }
    }
}

/// The figures of one finished run. The reference error is the design's
/// on `REFERENCE_MESH` against `aimed`, the target the run aimed at; a
/// drawn target's clean error is that simulation's against the clean curve
/// it was drawn from. `times`: the run's wall time and its spread stage's
/// (s).
fn sample(
    target: &Target,
    aimed: &Curve,
    plan: &Plan,
    o: &DesignOutcome,
    (wall_s, spread_s): (f64, f64),
) -> Sample {
    let tuning = plan.tuning();
    let on_reference = match o.verified_on == REFERENCE_MESH {
        true => Some(o.simulation.clone()),
        false => simulate(&o.design, &tuning.model(REFERENCE_MESH)).ok(),
    };
    let error_against = |curve: &Curve| {
        on_reference
            .as_ref()
            .and_then(|s| shape_error(&s.centreline, curve, SHAPE_SAMPLES).ok())
            .map_or(f64::NAN, |e| e.percent_of_length)
    };
    Sample {
        wall_s,
        evaluations: o.evaluations as f64,
        shape_error_percent: o.metrics.shape_error_percent,
        reference_error_percent: error_against(aimed),
        clean_error_percent: target.clean.as_ref().map_or(f64::NAN, error_against),
        dtw_curvature: o.metrics.dtw_curvature,
        dtw_torsion: o.metrics.dtw_torsion,
        patches: o.design.patches.len() as f64,
        beyond_limits: o.at_limits.iter().filter(|a| a.beyond).count() as f64,
        spread_s,
        spread_percent: o.spread.as_ref().map_or(f64::NAN, |s| s.rms_percent),
    }
}

/// The reach stage's verdict in a table cell.
fn verdict(o: &DesignOutcome) -> String {
    match &o.reach {
        Some(r) if r.reachable() => "yes".into(),
        Some(r) => r
            .out_of_reach
            .iter()
            .map(|span| {
                let (from, to) = (span.s_start_mm, span.s_end_mm);
                match span.tightest_bend_radius_mm {
                    // Too tight a bend for its twist per bend.
                    Some(_) => format!(
                        "no: s {from:.0}–{to:.0} mm needs r {:.0} mm",
                        span.needs_bend_radius_mm
                    ),
                    // More twist per bend than any patch makes.
                    None => format!(
                        "no: s {from:.0}–{to:.0} mm needs {:.1} twist per bend (r {:.0} mm)",
                        span.needs_twist_per_bend, span.needs_bend_radius_mm
                    ),
                }
            })
            .collect::<Vec<_>>()
            .join("; "),
        None => "–".into(),
    }
}
