//! `patchwork bench --suite report`: the benchmark report (BENCHMARKS.md).
//! Runs the forward solve per mesh, the curve suite under draft and
//! standard, the round trips and the users' suite under draft, in one
//! invocation, and writes
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
use super::row::{Row, median};
use super::sureness::{self, SureRow};
use super::text::{header, known_limits};
use super::users::clean_stroke_of;

/// The service bench's section, written by
/// `cargo bench --bench service_load -- --out docs/bench/service.md`.
const SERVICE_SECTION: &str = "service.md";

pub fn run(args: &BenchArgs, command: &str) -> Result<()> {
    // The build and machine as the run starts (the work tree may change
    // while it runs).
    let head = header(command);
    let forward = forward::measure()?;
    let curves = measured(Suite::Curves, &["draft", "standard"], args)?;
    let trips = measured(Suite::RoundTrips, &["draft"], args)?;
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
            (&curves, &trips, &sure),
            &goals,
            &forward,
            service.as_deref(),
            &args.out,
        ),
        curve_section(&curves, &args.out),
        trip_section(&trips),
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
    measure_suite(which, |s| settings.contains(&s.name), args)
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
    (curves, trips, sure): (&[Row], &[Row], &[SureRow]),
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

/// A row's shape error against the curve the user meant: the clean curve a
/// drawn target was drawn from, or the curve as given.
fn meant_error(row: &Row) -> f64 {
    match row.figures.clean_error_percent.is_finite() {
        true => row.figures.clean_error_percent,
        false => row.figures.reference_error_percent,
    }
}

/// The users' suite against issue 42's goals.
struct UsersGoals {
    curves: usize,
    /// Median and worst within reach, against the curve meant (%).
    median: f64,
    worst: f64,
    /// Curves designed without any patch.
    without_patches: Vec<String>,
    /// Most a noisy copy's error (against its clean curve) exceeds its
    /// clean curve's design (percentage points).
    noisy_gap: f64,
}

impl UsersGoals {
    fn of(rows: &[Row]) -> UsersGoals {
        let within: Vec<f64> = rows
            .iter()
            .filter(|r| r.reach == "yes")
            .map(meant_error)
            .collect();
        let noisy_gap = rows
            .iter()
            .filter(|r| r.figures.clean_error_percent.is_finite())
            .filter_map(|noisy| {
                let clean = clean_stroke_of(&noisy.curve)?;
                let clean = rows.iter().find(|r| r.curve == clean)?;
                Some(noisy.figures.clean_error_percent - clean.figures.reference_error_percent)
            })
            .fold(f64::NAN, f64::max);
        UsersGoals {
            curves: rows.len(),
            median: median(within.clone()),
            worst: within.iter().copied().fold(f64::NAN, f64::max),
            without_patches: rows
                .iter()
                .filter(|r| r.figures.patches < 1.0)
                .map(|r| r.curve.clone())
                .collect(),
            noisy_gap,
        }
    }

    /// (goal, result, met) per goal.
    fn rows(&self) -> [(String, String, bool); 4] {
        let none = self.without_patches.is_empty();
        [
            (
                "median within reach ≤ 0.5 %".into(),
                format!("{:.2} %", self.median),
                self.median <= 0.5,
            ),
            (
                "worst within reach ≤ 1.5 %".into(),
                format!("{:.2} %", self.worst),
                self.worst <= 1.5,
            ),
            (
                "every curve gets patches".into(),
                match none {
                    true => "all do".into(),
                    false => format!("none on {}", self.without_patches.join(", ")),
                },
                none,
            ),
            (
                "a noisy stroke within 0.3 points of its clean stroke's design".into(),
                format!("at most {:+.2} points", self.noisy_gap),
                self.noisy_gap <= 0.3,
            ),
        ]
    }

    fn met(&self) -> usize {
        self.rows().iter().filter(|(_, _, met)| *met).count()
    }
}

fn users_section(rows: &[Row], goals: &UsersGoals, out: &Path) -> String {
    let mut s = format!(
        "## Curves as users send them\n\n\
         Curves as they arrive rather than as presets write them, each designed \
         under `draft` from the points alone (seed 1): gentle arcs (radius \
         200–600 mm), sparse CAD exports (15–22 points) of helices, a conical \
         spiral and a spline, seeded 3D strokes with 0.3, 0.6 and 1 mm of noise \
         beside the clean strokes they were drawn from, and five kinds the suite \
         above lacks (a saddle, a planar wave, Viviani's curve, a planar \
         Archimedean spiral, a question mark: a straight stem into a 240° bend). \
         Shape error on the reference model against the curve as given, and \
         for a noisy stroke against its clean stroke (the curve meant). Every \
         figure: [`{0}/users.md`]({0}/users.md).\n\n\
         | goal (curves within reach) | result | met |\n|---|---|---|\n",
        out.display()
    );
    for (goal, result, met) in goals.rows() {
        let met = if met { "yes" } else { "**no**" };
        s.push_str(&format!("| {goal} | {result} | {met} |\n"));
    }
    s.push_str(
        "\n| curve | shape error % (as given) | against the curve meant % | patches | within reach | wall s |\n\
         |---|---|---|---|---|---|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {:.2} | {:.2} | {:.0} | {} | {:.1} |\n",
            r.curve,
            r.figures.reference_error_percent,
            meant_error(r),
            r.figures.patches,
            r.reach,
            r.figures.wall_s
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::bench::row::Sample;

    fn row(curve: &str, error: f64, clean: f64, patches: f64, reach: &str) -> Row {
        Row {
            curve: curve.into(),
            setting: "draft".into(),
            figures: Sample {
                reference_error_percent: error,
                clean_error_percent: clean,
                patches,
                ..Sample::unknown()
            },
            reach: reach.into(),
            failures: 0,
            stages: Vec::new(),
        }
    }

    /// The goals count curves within reach only, a noisy stroke against its
    /// clean stroke (the curve meant) and beside its clean stroke's design,
    /// and name the curves left without patches.
    #[test]
    fn the_users_goals_judge_the_curve_meant_within_reach() {
        let nan = f64::NAN;
        let rows = [
            row("gentle arc", 0.4, nan, 3.0, "yes"),
            row("stroke A (±0.3 mm)", 0.2, 0.7, 6.0, "yes"),
            row("stroke A, clean", 0.3, nan, 5.0, "yes"),
            row("kink", 9.0, nan, 0.0, "no: s 10–12 mm needs r 3 mm"),
        ];
        let goals = UsersGoals::of(&rows);
        assert_eq!(goals.curves, 4);
        // Within reach, against the curve meant: 0.4, 0.7 (not 0.2), 0.3.
        assert!((goals.median - 0.4).abs() < 1e-12, "{}", goals.median);
        assert!((goals.worst - 0.7).abs() < 1e-12, "{}", goals.worst);
        assert!((goals.noisy_gap - 0.4).abs() < 1e-12, "{}", goals.noisy_gap);
        assert_eq!(goals.without_patches, ["kink"]);
        let met: Vec<bool> = goals.rows().iter().map(|(_, _, met)| *met).collect();
        assert_eq!(met, [true, true, false, false]);
        assert_eq!(goals.met(), 2);
    }
}
