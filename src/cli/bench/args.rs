//! `patchwork bench`'s options.

use std::path::PathBuf;

use clap::Args;

use super::cases::Suite;

#[derive(Args, Clone)]
pub struct BenchArgs {
    /// The small suite (two short curves, draft and standard, small budgets):
    /// minutes instead of hours. The same as `--suite quick`.
    #[arg(long)]
    pub quick: bool,
    /// Which suite: quick, reference (the presets and their variants on the
    /// reference curves), curves (curves unlike the references, draft and
    /// standard), round-trips (simulated random designs, the layout
    /// unknown), users (curves as users send them: gentle arcs, sparse CAD
    /// exports, noisy strokes, new kinds; draft), sure (five curves designed
    /// robust under draft, each checked by Monte-Carlo: sure.md), or report
    /// (BENCHMARKS.md: forward solves, curves under draft and standard, the
    /// run-time goals' curves at seeds 1–3, round trips and users' curves
    /// under draft, how sure a design is; about half an hour on 2 cores).
    #[arg(long, value_enum, default_value = "reference")]
    pub suite: Suite,
    /// Folder for bench.md and bench.svg (the report: its tables and plot)
    /// and, but for the report, curves/NAME.csv: each curve the suite
    /// designs, as `x,y,z` (a round trip's simulated target among them), to
    /// design again with `patchwork design`.
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Redraw `--out`/bench.svg from this bench.md table instead of running
    /// anything.
    #[arg(long, value_name = "BENCH_MD")]
    pub replot: Option<PathBuf>,
    /// The report's file (`--suite report` only).
    #[arg(long, default_value = "BENCHMARKS.md")]
    pub report: PathBuf,
    /// Runs per case (seeds 1..=N); the table shows medians, and each
    /// run's time and shape error go to stderr.
    #[arg(long, default_value_t = 3)]
    pub runs: usize,
    /// Only the curves whose name contains one of these (comma-separated,
    /// case-insensitive), e.g. `hilbert`.
    #[arg(long, value_delimiter = ',')]
    pub curves: Vec<String>,
    /// Only these settings (comma-separated names as in the table, e.g.
    /// `draft,fine`).
    #[arg(long, value_delimiter = ',')]
    pub settings: Vec<String>,
    /// Threads evaluating a generation.
    #[arg(long, default_value_t = patchwork_core::available_cores())]
    pub threads: usize,
    /// Tuning laid over every design run's own (as `design --tuning`:
    /// inline JSON, a file, or `-` for stdin), e.g. `'{"rod_search":
    /// false}'` to measure the search on FE beside the presets on the same
    /// machine.
    #[arg(long, value_name = "JSON")]
    pub tuning: Option<String>,
    /// `--tuning`, read once by the command (stdin cannot be read twice).
    #[arg(skip)]
    pub overrides: patchwork_core::inverse::TuningOverrides,
}
