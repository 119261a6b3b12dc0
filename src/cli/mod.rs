//! Command-line contract. Scripts depend on these names: change with care.

mod bench;
mod calibrate_cmd;
mod calibrate_table;
mod compare_cmd;
mod curve_cmd;
pub(crate) mod design_cmd;
mod design_summary;
mod input;
mod ksa_cmd;
mod output;
mod preset_cmd;
mod reach_cache;
mod redesign_cmd;
mod simulate_cmd;
mod spread_cmd;
mod spread_summary;

use anyhow::Result;
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "patchwork",
    version,
    about = "Inverse design of patch-clad cylindrical inflatables",
    long_about = "Patchwork takes the 3D centreline a lab wants an inflated latex balloon to \
                  follow and works out where to glue strain-limiting patches."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Analyse a target curve: length, point count, curvature and torsion.
    #[command(
        after_help = "Example:\n  patchwork preset helix > helix.csv && patchwork curve helix.csv"
    )]
    Curve(curve_cmd::CurveArgs),
    /// Kinematic Segmentation Algorithm: a first guess at the patches.
    #[command(after_help = "Example:\n  patchwork ksa helix.csv --json")]
    Ksa(ksa_cmd::KsaArgs),
    /// Write a preset curve as CSV to stdout (`patchwork preset list` for names).
    #[command(
        after_help = "Example:\n  patchwork preset grasp diameter_mm=40 turns=1.5 > grasp.csv"
    )]
    Preset(preset_cmd::PresetArgs),
    /// Forward model: inflate a design and report its centreline.
    #[command(after_help = "Example:\n  patchwork simulate out/design.json --out inflated/")]
    Simulate(simulate_cmd::SimulateArgs),
    /// How sure a design is: the spread of its inflated centreline under
    /// fabrication and pressure tolerances, and what matters most.
    #[command(
        after_help = "Example:\n  patchwork spread grasp/design.json --tolerances '{\"angle_deg\": 1}'"
    )]
    Spread(spread_cmd::SpreadArgs),
    /// Inverse design: patches for a target curve, with cut files.
    #[command(after_help = "Example:\n  patchwork design grasp.csv --out grasp/ --fidelity draft")]
    Design(design_cmd::DesignArgs),
    /// A built balloon's measured centreline against its design: shape
    /// error, length, bend and twist under every patch.
    #[command(
        after_help = "Example:\n  patchwork compare grasp/design.json measured.csv --out grasp/compare"
    )]
    Compare(compare_cmd::CompareArgs),
    /// The materials fitted to measurements of the lab's own balloons (bare
    /// inflation, pressure–volume, built designs' centrelines or scans), by
    /// least squares on the FE model.
    #[command(
        after_help = "Example:\n  patchwork calibrate inflation.csv --out my-balloon.json && patchwork design grasp.csv --options my-balloon.json --out grasp/"
    )]
    Calibrate(calibrate_cmd::CalibrateArgs),
    /// From a built balloon to a new design: compare its measured
    /// centreline (or scan) with its design, calibrate the materials to it,
    /// and design the target again on them.
    #[command(
        after_help = "Example:\n  patchwork redesign grasp/design.json measured.csv --out grasp-2/ --fidelity draft"
    )]
    Redesign(redesign_cmd::RedesignArgs),
    /// Run time against error: a fixed suite of curves × fidelity settings.
    #[command(after_help = "Example:\n  patchwork bench --quick --out bench-out")]
    Bench(bench::BenchArgs),
    /// HTTP design service: REST API, SQLite job store, worker pool.
    #[command(after_help = "Example:\n  patchwork serve --addr 0.0.0.0:8080 --db patchwork.db")]
    Serve(crate::service::ServeArgs),
    /// Copy every job (events, iterations, result files) from one job store
    /// into another: a SQLite file into PostgreSQL, or back.
    #[command(
        after_help = "Example:\n  patchwork copy-jobs --from ./patchwork.db --to postgres://patchwork:secret@db.lab/patchwork"
    )]
    CopyJobs(crate::service::CopyJobsArgs),
}

pub fn run() -> Result<()> {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => return handle_clap_error(error),
    };
    if matches!(
        cli.command,
        Command::Design(_) | Command::Redesign(_) | Command::Serve(_)
    ) {
        reach_cache::install();
    }
    match cli.command {
        Command::Curve(args) => curve_cmd::run(args),
        Command::Ksa(args) => ksa_cmd::run(args),
        Command::Preset(args) => preset_cmd::run(args),
        Command::Simulate(args) => simulate_cmd::run(args),
        Command::Spread(args) => spread_cmd::run(args),
        Command::Design(args) => design_cmd::run(args),
        Command::Compare(args) => compare_cmd::run(args),
        Command::Calibrate(args) => calibrate_cmd::run(args),
        Command::Redesign(args) => redesign_cmd::run(args),
        Command::Serve(args) => crate::service::run(args),
        Command::CopyJobs(args) => crate::service::copy_jobs::run(args),
        Command::Bench(args) => bench::run(args),
    }
}

/// Help and version go to stdout with success; a usage error becomes one line.
fn handle_clap_error(error: clap::Error) -> Result<()> {
    use clap::error::ErrorKind;
    match error.kind() {
        ErrorKind::DisplayHelp
        | ErrorKind::DisplayVersion
        | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            output::emit(&error.render().to_string())?;
            Ok(())
        }
        _ => {
            let rendered = error.render().to_string();
            let first = rendered
                .lines()
                .next()
                .unwrap_or("invalid arguments")
                .trim_start_matches("error: ");
            anyhow::bail!("{first} (see `patchwork --help`)")
        }
    }
}

/// A panic is a bug, never the user's fault: say so in one line, no backtrace.
pub fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let location = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        eprintln!(
            "error: internal error{location}; please report it with the input that caused it"
        );
    }));
}
