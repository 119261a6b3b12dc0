//! `patchwork bench [--suite quick|reference|curves|round-trips] [--out DIR] [--runs N]`:
//! run time against error. A fixed suite of target curves × fidelity
//! settings (`bench_suite.rs`), each run with seeds
//! 1..=N; writes `bench.md` (medians: wall time, evaluations, shape error, DTW
//! κ and τ) and `bench.svg` (shape error against time, Pareto front per curve).
//!
//! Every run reports its error twice: on its own verification model, and with
//! its design re-simulated on one common reference model (`REFERENCE_MESH`) —
//! a coarse preset's own verification flatters it, so only the second compares
//! settings fairly. The plot uses the reference error; the re-simulation is not
//! part of the wall time.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use patchwork_core::chart::{self, Axis, COLOURS, Mark, Panel, Series};
use patchwork_core::curve::{Curve, shape_error};
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::simulate;
use patchwork_core::inverse::input::prepare;
use patchwork_core::inverse::objective::SHAPE_SAMPLES;
use patchwork_core::inverse::{DesignOutcome, Plan, Smoothing, UserSettings, design};

use super::bench_suite::{Setting, Suite, Target, suite};
use super::output::emit;
use super::{bench_replot, bench_report};

#[derive(Args)]
pub struct BenchArgs {
    /// The small suite (two short curves, draft and standard, small budgets):
    /// minutes instead of hours. The same as `--suite quick`.
    #[arg(long)]
    quick: bool,
    /// Which suite: quick, reference (the presets and their variants on the
    /// reference curves), curves (curves unlike the references, draft and
    /// standard), round-trips (simulated random designs, the layout
    /// unknown), users (curves as users send them: gentle arcs, sparse CAD
    /// exports, noisy strokes, new kinds; draft), or report (BENCHMARKS.md:
    /// forward solves, curves under draft and standard, round trips and
    /// users' curves under draft; about 100 minutes on 2 cores).
    #[arg(long, value_enum, default_value = "reference")]
    suite: Suite,
    /// Folder for bench.md and bench.svg (the report: its tables and plot).
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Redraw `--out`/bench.svg from this bench.md table instead of running
    /// anything.
    #[arg(long, value_name = "BENCH_MD")]
    replot: Option<PathBuf>,
    /// The report's file (`--suite report` only).
    #[arg(long, default_value = "BENCHMARKS.md")]
    pub report: PathBuf,
    /// Runs per case (seeds 1..=N); the table shows medians.
    #[arg(long, default_value_t = 3)]
    pub runs: usize,
    /// Only the curves whose name contains one of these (comma-separated,
    /// case-insensitive), e.g. `hilbert`.
    #[arg(long, value_delimiter = ',')]
    pub curves: Vec<String>,
    /// Only these settings (comma-separated names as in the table, e.g.
    /// `draft,fine`).
    #[arg(long, value_delimiter = ',')]
    settings: Vec<String>,
    /// Threads evaluating a generation.
    #[arg(long, default_value_t = std::thread::available_parallelism().map_or(1, |n| n.get()))]
    pub threads: usize,
}

/// The common model every run's design is re-simulated on: the finest
/// verification model of the presets.
const REFERENCE_MESH: MeshSpec = MeshSpec {
    element_mm: 0.5,
    around: None,
    straight_mm: None,
};

pub struct Row {
    pub curve: String,
    pub setting: String,
    /// Medians over the runs (the most beyond limits).
    pub figures: Sample,
    /// The reach stage's verdict: "yes", or the stretches out of reach.
    pub reach: String,
    pub failures: usize,
}

pub fn run(args: BenchArgs) -> Result<()> {
    anyhow::ensure!(args.runs >= 1, "--runs must be at least 1");
    anyhow::ensure!(args.threads >= 1, "--threads must be at least 1");
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    if let Some(table) = &args.replot {
        let text = std::fs::read_to_string(table)
            .with_context(|| format!("cannot read {}", table.display()))?;
        let rows = bench_replot::rows(&text)?;
        return Ok(std::fs::write(args.out.join("bench.svg"), plot(&rows))?);
    }
    let chosen = if args.quick { Suite::Quick } else { args.suite };
    let command = command_line(&args, chosen);
    if chosen == Suite::Report {
        return bench_report::run(&args, &command);
    }
    let rows = measure_suite(
        chosen,
        |s| args.settings.is_empty() || args.settings.iter().any(|f| f == s.name),
        &args,
    )?;
    let table = table(&rows, &command);
    std::fs::write(args.out.join("bench.md"), &table)?;
    std::fs::write(args.out.join("bench.svg"), plot(&rows))?;
    emit(&table)
}

/// The curves of `which` that `--curves` names (all when it names none),
/// each under the settings `keep` keeps, measured in order.
pub fn measure_suite(
    which: Suite,
    keep: impl Fn(&Setting) -> bool,
    args: &BenchArgs,
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
    let mut rows = Vec::new();
    for target in &curves {
        for setting in &settings {
            let row = measure_row(target, setting, args)?;
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

pub fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    match values.len() {
        0 => f64::NAN,
        n => values[n / 2],
    }
}

/// The command that reproduces this run.
fn command_line(args: &BenchArgs, chosen: Suite) -> String {
    let suite = match chosen {
        Suite::Quick => " --quick",
        Suite::Reference => "",
        Suite::Curves => " --suite curves",
        Suite::RoundTrips => " --suite round-trips",
        Suite::Users => " --suite users",
        Suite::Report => " --suite report",
    };
    let mut command = format!(
        "patchwork bench{suite} --runs {} --threads {} --out {}",
        args.runs,
        args.threads,
        args.out.display()
    );
    if chosen == Suite::Report {
        command.push_str(&format!(" --report {}", args.report.display()));
    }
    for (flag, values) in [("curves", &args.curves), ("settings", &args.settings)] {
        if !values.is_empty() {
            let list = values.join(",");
            match list.contains(' ') {
                true => command.push_str(&format!(" --{flag} \"{list}\"")),
                false => command.push_str(&format!(" --{flag} {list}")),
            }
        }
    }
    command
}

/// One run's figures (or their medians over the runs).
pub struct Sample {
    pub wall_s: f64,
    pub evaluations: f64,
    pub shape_error_percent: f64,
    /// Shape error of the design on `REFERENCE_MESH`.
    pub reference_error_percent: f64,
    /// The same against the clean curve a drawn target was drawn from (NaN
    /// for the others).
    pub clean_error_percent: f64,
    pub dtw_curvature: f64,
    pub dtw_torsion: f64,
    pub patches: f64,
    pub beyond_limits: f64,
}

impl Sample {
    /// Every figure unknown (NaN).
    pub fn unknown() -> Sample {
        Sample {
            wall_s: f64::NAN,
            evaluations: f64::NAN,
            shape_error_percent: f64::NAN,
            reference_error_percent: f64::NAN,
            clean_error_percent: f64::NAN,
            dtw_curvature: f64::NAN,
            dtw_torsion: f64::NAN,
            patches: f64::NAN,
            beyond_limits: f64::NAN,
        }
    }
}

/// `setting` on `target`, once per seed: the medians (the most beyond
/// limits), the reach verdict and the failures.
pub fn measure_row(target: &Target, setting: &Setting, args: &BenchArgs) -> Result<Row> {
    let mut samples = Vec::new();
    let mut failures = 0;
    let mut reach = String::from("–");
    let mut aimed: Option<Curve> = None;
    for seed in 1..=args.runs as u64 {
        let settings = UserSettings {
            fidelity: setting.fidelity,
            budget: Some(setting.budget),
            seed,
            threads: args.threads,
            ..UserSettings::default()
        };
        let plan = Plan::resolve(settings, &setting.overrides())?;
        // Each run is timed as a fresh process would run it: with caches
        // of its own.
        let started = Instant::now();
        match design(&target.curve, &plan, &AtomicBool::new(false), &mut |_| {}) {
            Ok(o) => {
                let wall_s = started.elapsed().as_secs_f64();
                reach = verdict(&o);
                // The target the runs aimed at: smoothed as they smoothed
                // it, the same for every seed.
                if aimed.is_none() {
                    let kappa_tol = plan.tuning().kappa_tol;
                    aimed = Some(prepare(&target.curve, Smoothing::Auto, kappa_tol)?.0);
                }
                if let Some(aimed) = &aimed {
                    samples.push(sample(target, aimed, &plan, &o, wall_s));
                }
            }
            Err(e) => {
                eprintln!("{}, {}, seed {seed}: {e}", target.name, setting.name);
                failures += 1;
            }
        }
    }
    let column = |f: fn(&Sample) -> f64| median(samples.iter().map(f).collect());
    Ok(Row {
        curve: target.name.clone(),
        setting: setting.name.to_string(),
        figures: Sample {
            wall_s: column(|s| s.wall_s),
            evaluations: column(|s| s.evaluations),
            shape_error_percent: column(|s| s.shape_error_percent),
            reference_error_percent: column(|s| s.reference_error_percent),
            clean_error_percent: column(|s| s.clean_error_percent),
            dtw_curvature: column(|s| s.dtw_curvature),
            dtw_torsion: column(|s| s.dtw_torsion),
            patches: column(|s| s.patches),
            beyond_limits: samples.iter().map(|s| s.beyond_limits).fold(0.0, f64::max),
        },
        reach,
        failures,
    })
}

/// The figures of one finished run. The reference error is the design's
/// on `REFERENCE_MESH` against `aimed`, the target the run aimed at; a
/// drawn target's clean error is that simulation's against the clean curve
/// it was drawn from.
fn sample(target: &Target, aimed: &Curve, plan: &Plan, o: &DesignOutcome, wall_s: f64) -> Sample {
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

pub fn table(rows: &[Row], command: &str) -> String {
    let mut out = format!(
        "`{command}` — medians over the runs\n\n\
         Shape error on the run's own verification model, and of its design \
         re-simulated on the common reference model (uniform 0.5 mm).\n\n\
         | curve | setting | wall s | evaluations | shape error % (own) | shape error % (reference) | against the clean curve % | DTW κ | DTW τ | patches | beyond limits | within reach | failed runs |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
    );
    for r in rows {
        out.push_str(&format!(
            "| {} | {} | {:.2} | {:.0} | {:.2} | {:.2} | {} | {:.3} | {:.3} | {:.0} | {:.0} | {} | {} |\n",
            r.curve,
            r.setting,
            r.figures.wall_s,
            r.figures.evaluations,
            r.figures.shape_error_percent,
            r.figures.reference_error_percent,
            match r.figures.clean_error_percent.is_finite() {
                true => format!("{:.2}", r.figures.clean_error_percent),
                false => "–".into(),
            },
            r.figures.dtw_curvature,
            r.figures.dtw_torsion,
            r.figures.patches,
            r.figures.beyond_limits,
            r.reach,
            r.failures
        ));
    }
    out
}

/// Shape error against wall time (log scale), a colour per curve, each
/// curve's Pareto front (no other setting both faster and more accurate)
/// joined by a line.
pub fn plot(rows: &[Row]) -> String {
    let ok: Vec<&Row> = rows
        .iter()
        .filter(|r| r.figures.wall_s.is_finite() && r.figures.reference_error_percent.is_finite())
        .collect();
    let mut curves: Vec<&str> = Vec::new();
    for r in &ok {
        if !curves.contains(&r.curve.as_str()) {
            curves.push(&r.curve);
        }
    }
    let mut series = Vec::new();
    for (i, name) in curves.iter().enumerate() {
        // Past the palette, the colours repeat with squares for dots.
        let colour = COLOURS[i % COLOURS.len()];
        let mark = match i < COLOURS.len() {
            true => Mark::Dots,
            false => Mark::Squares,
        };
        let mut points: Vec<(f64, f64)> = ok
            .iter()
            .filter(|r| r.curve == *name)
            .map(|r| (r.figures.wall_s, r.figures.reference_error_percent))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut best = f64::INFINITY;
        let front = points
            .iter()
            .filter(|(_, error)| {
                let better = *error < best;
                best = best.min(*error);
                better
            })
            .copied()
            .collect();
        series.push(Series {
            name: Some(name.to_string()),
            colour,
            mark,
            points,
        });
        series.push(Series {
            name: None,
            colour,
            mark: Mark::Line,
            points: front,
        });
    }
    chart::svg(&[Panel {
        title: "Shape error against wall time, a dot per setting (line: each curve's Pareto front)"
            .into(),
        x: Axis::log(
            "wall time (s, log scale)",
            ok.iter().map(|r| r.figures.wall_s),
        ),
        y: Axis::log(
            "shape error (% of length, log scale)",
            ok.iter().map(|r| r.figures.reference_error_percent),
        ),
        series,
    }])
}
