//! `patchwork bench --suite report`: the benchmark report (BENCHMARKS.md).
//! Runs the forward solve per mesh, the curve suite under draft and
//! standard and the round trips under draft, in one invocation, and writes
//! the report with the machine, build, date and command in its header, a
//! headline table, a section per measurement and the limits the run shows.
//! The service under load comes from its own bench's markdown (it needs an
//! HTTP client), included when present.

use std::path::Path;

use anyhow::{Context, Result};

use super::bench_cmd::{BenchArgs, Row, measure_suite, median, plot, table};
use super::bench_forward::{self, ForwardRow};
use super::bench_suite::Suite;
use super::bench_text::{header, known_limits};

/// The service bench's section, written by
/// `cargo bench --bench service_load -- --out docs/bench/service.md`.
const SERVICE_SECTION: &str = "service.md";

pub fn run(args: &BenchArgs, command: &str) -> Result<()> {
    // The build and machine as the run starts (the work tree may change
    // while it runs).
    let head = header(command);
    let forward = bench_forward::measure()?;
    let curves = measured(Suite::Curves, &["draft", "standard"], args)?;
    let trips = measured(Suite::RoundTrips, &["draft"], args)?;
    std::fs::write(args.out.join("bench.svg"), plot(&curves))?;
    std::fs::write(args.out.join("curves.md"), table(&curves, command))?;
    std::fs::write(args.out.join("round-trips.md"), table(&trips, command))?;
    let service = std::fs::read_to_string(args.out.join(SERVICE_SECTION)).ok();
    let report = [
        head,
        headline(&curves, &trips, &forward, service.as_deref(), &args.out),
        curve_section(&curves, &args.out),
        trip_section(&trips),
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

/// Median and worst (within reach) shape error and the longest run of one
/// setting's rows.
struct Summary {
    curves: usize,
    median: f64,
    worst_within_reach: f64,
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
        longest_s: rows.iter().map(|r| r.figures.wall_s).fold(0.0, f64::max),
    }
}

fn headline(
    curves: &[Row],
    trips: &[Row],
    forward: &[ForwardRow],
    service: Option<&str>,
    out: &Path,
) -> String {
    let mut s = String::from("## How good, how fast\n\n| what | result |\n|---|---|\n");
    for setting in ["draft", "standard"] {
        let m = summary(curves, setting);
        s.push_str(&format!(
            "| {} curves of the suite, `{setting}` | median {:.2} %, worst within reach {:.2} %, every run ≤ {:.0} s |\n",
            m.curves, m.median, m.worst_within_reach, m.longest_s
        ));
    }
    let t = summary(trips, "draft");
    let worst = trips
        .iter()
        .map(|r| r.figures.reference_error_percent)
        .fold(f64::NAN, f64::max);
    s.push_str(&format!(
        "| {} random designs of 4–12 patches, layout unknown, `draft` | median {:.2} %, worst {worst:.2} %, every run ≤ {:.0} s |\n",
        t.curves, t.median, t.longest_s
    ));
    if let Some(default) = forward.first() {
        s.push_str(&format!(
            "| one forward solve, default mesh | {:.0} ms bare, {:.0} ms with six patches; hoop stretch {:+.2} % and axial {:+.2} % against membrane theory |\n",
            default.bare_ms,
            default.hilbert_ms,
            default.hoop_error_percent,
            default.axial_error_percent
        ));
    }
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

fn forward_section(rows: &[ForwardRow]) -> String {
    format!(
        "## Forward solve per mesh\n\n{}",
        bench_forward::section(rows)
    )
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
