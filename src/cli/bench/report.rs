//! `patchwork bench --suite report`: the benchmark report (BENCHMARKS.md).
//! Runs the forward solve per mesh, the curve suite under draft and
//! standard, the run-time goals' curves at three seeds, the round trips
//! and the users' suite under draft, the rod model against FE on the
//! suite's designs, in one invocation, and writes
//! the report with the machine, build, date and command in its header, a
//! headline table, a section per measurement and the limits the run shows.
//! The service under load comes from its own bench's markdown (it needs an
//! HTTP client), included when present.

use std::path::Path;

use anyhow::{Context, Result};

use super::args::BenchArgs;
use super::cases::Suite;
use super::forward::{self, Forward};
use super::measure::measure_suite;
use super::render::{plot, stage_shares, table};
use super::rod::{self, RodAccuracy};
use super::row::{Row, median};
use super::sureness::{self, SureRow};
use super::text::{header, known_limits};
use super::timing_goals::{self, TimedGoal};
use super::users_goals::{UsersGoals, users_section};

/// The service bench's section, written by
/// `cargo bench --bench service_load -- --out docs/bench/service.md`.
const SERVICE_SECTION: &str = "service.md";

pub fn run(args: &BenchArgs, command: &str) -> Result<()> {
    // The build and machine as the run starts (the work tree may change
    // while it runs).
    let head = header(command);
    let forward = forward::measure()?;
    let curves = measured(Suite::Curves, &["draft", "standard"], args)?;
    let timed = timing_goals::measure(args, &curves)?;
    let trips = measured(Suite::RoundTrips, &["draft"], args)?;
    let rod = rod::measure(
        &[("curve suite", &curves), ("round trips", &trips)],
        args.threads,
    )?;
    let users = measured(Suite::Users, &["draft"], args)?;
    let sure = sureness::measure(args)?;
    std::fs::write(args.out.join("bench.svg"), plot(&curves))?;
    std::fs::write(args.out.join("curves.md"), table(&curves, command))?;
    std::fs::write(args.out.join("round-trips.md"), table(&trips, command))?;
    std::fs::write(args.out.join("users.md"), table(&users, command))?;
    let service = std::fs::read_to_string(args.out.join(SERVICE_SECTION)).ok();
    let goals = UsersGoals::of(&users);
    let report = [
        head,
        headline(
            (&curves, &timed, &trips, &sure),
            &rod,
            &goals,
            &forward,
            service.as_deref(),
            &args.out,
        ),
        curve_section(&curves, &args.out),
        timing_goals::section(&timed),
        trip_section(&trips),
        rod::section(&rod),
        users_section(&users, &goals, &args.out),
        sureness::section(&curves, &sure),
        forward_section(&forward),
        service_section(service.as_deref(), &args.out),
        known_limits(&curves),
    ]
    .join("\n");
    std::fs::write(&args.report, &report)
        .with_context(|| format!("cannot write {}", args.report.display()))?;
    eprintln!("wrote {}", args.report.display());
    Ok(())
}

/// The rows of the named presets over every curve of `which`.
fn measured(which: Suite, settings: &[&str], args: &BenchArgs) -> Result<Vec<Row>> {
    measure_suite(which, |s| settings.contains(&s.name), args, None)
}

/// Median and worst (within reach) shape error and the median and longest
/// run of one setting's rows.
struct Summary {
    curves: usize,
    median: f64,
    worst_within_reach: f64,
    median_s: f64,
    longest_s: f64,
}

fn summary(rows: &[Row], setting: &str) -> Summary {
    let rows: Vec<&Row> = rows.iter().filter(|r| r.setting == setting).collect();
    let errors = rows.iter().map(|r| r.figures.reference_error_percent);
    let within = rows.iter().filter(|r| r.reach == "yes");
    Summary {
        curves: rows.len(),
        median: median(errors.collect()),
        worst_within_reach: within
            .map(|r| r.figures.reference_error_percent)
            .fold(f64::NAN, f64::max),
        median_s: median(rows.iter().map(|r| r.figures.wall_s).collect()),
        longest_s: rows.iter().map(|r| r.figures.wall_s).fold(0.0, f64::max),
    }
}

fn headline(
    (curves, timed, trips, sure): (&[Row], &[TimedGoal], &[Row], &[SureRow]),
    rod: &RodAccuracy,
    goals: &UsersGoals,
    forward: &Forward,
    service: Option<&str>,
    out: &Path,
) -> String {
    let mut s = String::from("## How good, how fast\n\n| what | result |\n|---|---|\n");
    for setting in ["draft", "standard"] {
        let m = summary(curves, setting);
        s.push_str(&format!(
            "| {} curves of the suite, `{setting}` | median {:.2} %, worst within reach {:.2} %; median run {:.0} s, every run ≤ {:.0} s |\n",
            m.curves, m.median, m.worst_within_reach, m.median_s, m.longest_s
        ));
    }
    s.push_str(&timing_goals::headline(timed));
    let t = summary(trips, "draft");
    let worst = trips
        .iter()
        .map(|r| r.figures.reference_error_percent)
        .fold(f64::NAN, f64::max);
    s.push_str(&format!(
        "| {} random designs of 4–12 patches, layout unknown, `draft` | median {:.2} %, worst {worst:.2} %; median run {:.0} s, every run ≤ {:.0} s |\n",
        t.curves, t.median, t.median_s, t.longest_s
    ));
    s.push_str(&format!(
        "| {} curves as users send them, `draft` | median {:.2} %, worst within reach {:.2} % against the curve meant; {} of 4 goals met |\n",
        goals.curves, goals.median, goals.worst, goals.met()
    ));
    s.push_str(&sureness::headline(curves, sure));
    s.push_str(&rod::headline(rod));
    s.push_str(&forward::headline(forward));
    s.push_str(&match service {
        Some(text) => format!(
            "| HTTP service while designs compute | {} |\n",
            service_headline(text)
        ),
        None => "| HTTP service under load | not measured in this report (see below) |\n".into(),
    });
    s.push_str(&format!(
        "\n![Shape error against wall time, each curve's Pareto front joined]({}/bench.svg)\n",
        out.display()
    ));
    s
}

/// The service section's bold figures (median p99, SSE clients complete)
/// on one line.
fn service_headline(section: &str) -> String {
    let bold: Vec<&str> = section.split("**").skip(1).step_by(2).collect();
    match bold.as_slice() {
        [sqlite, postgres, ..] => format!(
            "500 status requests/s — SQLite, one node: {sqlite}; PostgreSQL, two nodes: {postgres}"
        ),
        _ => "see below".into(),
    }
}

fn curve_section(rows: &[Row], out: &Path) -> String {
    let mut s = format!(
        "## The curve suite\n\n\
         Each curve designed from the curve alone under `draft` and `standard`, \
         as users get them (seed 1). Shape error of the design re-simulated on the \
         uniform 0.5 mm reference model. Every figure of every run, with DTW \
         distances and evaluation counts: [`{0}/curves.md`]({0}/curves.md).\n\n\
         | curve | draft: shape error % | patches | within reach | wall s | standard: shape error % | wall s |\n\
         |---|---|---|---|---|---|---|\n",
        out.display()
    );
    let draft = rows.iter().filter(|r| r.setting == "draft");
    for d in draft {
        let standard = rows
            .iter()
            .find(|r| r.setting == "standard" && r.curve == d.curve);
        let (error, wall) = standard.map_or((f64::NAN, f64::NAN), |r| {
            (r.figures.reference_error_percent, r.figures.wall_s)
        });
        s.push_str(&format!(
            "| {} | {:.2} | {:.0} | {} | {:.1} | {error:.2} | {wall:.1} |\n",
            d.curve,
            d.figures.reference_error_percent,
            d.figures.patches,
            d.reach,
            d.figures.wall_s
        ));
    }
    s.push_str("\nWhere the time goes, each stage's share of all the curves' seconds:\n\n");
    for setting in ["draft", "standard"] {
        s.push_str(&format!("- `{setting}`: {}\n", stage_shares(rows, setting)));
    }
    s
}

fn trip_section(rows: &[Row]) -> String {
    let mut s = String::from(
        "## Round trips with an unknown layout\n\n\
         Ten seeded random feasible designs of 4–12 patches on a 400 mm balloon (lone \
         patches and trains of 2–5 adjacent patches), each simulated, then designed \
         under `draft` from the simulated centreline alone: the patch count is not \
         given. Shape error of the design on the reference model.\n\n\
         | truth | designed patches | shape error % | wall s | within reach |\n\
         |---|---|---|---|---|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {:.0} | {:.2} | {:.1} | {} |\n",
            r.curve,
            r.figures.patches,
            r.figures.reference_error_percent,
            r.figures.wall_s,
            r.reach
        ));
    }
    s
}

fn forward_section(forward: &Forward) -> String {
    format!("## Forward solve per mesh\n\n{}", forward::section(forward))
}

fn service_section(service: Option<&str>, out: &Path) -> String {
    let command = format!(
        "cargo bench --bench service_load -- --out {}/{SERVICE_SECTION}",
        out.display()
    );
    match service {
        Some(text) => format!("## HTTP service under load\n\n{text}"),
        None => format!(
            "## HTTP service under load\n\nNot measured in this report: run `{command}` \
             before the report to include it.\n"
        ),
    }
}
