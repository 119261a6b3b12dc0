//! `patchwork bench [--suite quick|reference|curves|round-trips] [--out DIR] [--runs N]`:
//! run time against error. A fixed suite of target curves × fidelity
//! settings (`cases.rs`, `suite.rs`, `users.rs`), each run with seeds
//! 1..=N; writes `bench.md` (medians: wall time, evaluations, shape error, DTW
//! κ and τ), `bench.svg` (shape error against time, Pareto front per curve)
//! and `curves/` (each curve designed, `curves_out.rs`).
//!
//! The modules import downward only: `args`, `cases` and `row` at the
//! bottom; `users` and `suite` (the curves), `curves_out` (writing them),
//! `measure` (running them),
//! `render`, `replot`, `text` and `forward` above them; `report`
//! (BENCHMARKS.md) on those; this file, the command, on top.

mod args;
mod cases;
mod curves_out;
mod forward;
mod measure;
mod render;
mod replot;
mod report;
mod rod;
mod row;
mod suite;
mod sureness;
mod text;
mod timing_goals;
mod users;
mod users_goals;

use anyhow::{Context, Result};
use patchwork_core::inverse::{Plan, UserSettings};

pub use args::BenchArgs;
use cases::Suite;
use measure::measure_suite;
use render::{plot, table};

use super::design_cmd::flag_error;
use super::input::json_argument;
use super::output::emit;

pub fn run(mut args: BenchArgs) -> Result<()> {
    anyhow::ensure!(args.runs >= 1, "--runs must be at least 1");
    anyhow::ensure!(args.threads >= 1, "--threads must be at least 1");
    read_tuning(&mut args)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    if let Some(table) = &args.replot {
        let text = std::fs::read_to_string(table)
            .with_context(|| format!("cannot read {}", table.display()))?;
        let rows = replot::rows(&text)?;
        return Ok(std::fs::write(args.out.join("bench.svg"), plot(&rows))?);
    }
    let chosen = if args.quick { Suite::Quick } else { args.suite };
    let command = command_line(&args, chosen)?;
    if chosen == Suite::Report {
        return report::run(&args, &command);
    }
    if chosen == Suite::Sure {
        let section = sureness::section(&[], &sureness::measure(&args)?);
        let text = format!("{section}\nWritten by `{command}`.\n");
        std::fs::write(args.out.join("sure.md"), &text)?;
        return emit(&text);
    }
    let rows = measure_suite(
        chosen,
        |s| args.settings.is_empty() || args.settings.iter().any(|f| f == s.name),
        &args,
        Some(&args.out.join("curves")),
    )?;
    let table = table(&rows, &command);
    std::fs::write(args.out.join("bench.md"), &table)?;
    std::fs::write(args.out.join("bench.svg"), plot(&rows))?;
    emit(&table)
}

/// Reads `--tuning` (inline, a file or stdin) into `args.overrides` once,
/// refusing a bad field before anything runs.
fn read_tuning(args: &mut BenchArgs) -> Result<()> {
    if let Some(argument) = &args.tuning {
        args.overrides = json_argument("tuning", argument)?;
        Plan::resolve(UserSettings::default(), &args.overrides).map_err(flag_error)?;
    }
    Ok(())
}

/// The command that reproduces this run.
fn command_line(args: &BenchArgs, chosen: Suite) -> Result<String> {
    let suite = match chosen {
        Suite::Quick => " --quick",
        Suite::Reference => "",
        Suite::Curves => " --suite curves",
        Suite::RoundTrips => " --suite round-trips",
        Suite::Users => " --suite users",
        Suite::Sure => " --suite sure",
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
    // The tuning as read, not as given: a file's path or `-` (stdin) would
    // not reproduce the run.
    if args.tuning.is_some() {
        let tuning = serde_json::to_string(&args.overrides)?;
        command.push_str(&format!(" --tuning '{tuning}'"));
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
    Ok(command)
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    #[derive(Parser)]
    struct Command {
        #[command(flatten)]
        bench: BenchArgs,
    }

    #[test]
    fn the_reproduce_command_carries_the_tuning_as_read() {
        let tuning = std::env::temp_dir().join("patchwork-bench-tuning.json");
        std::fs::write(&tuning, r#"{ "rod_search": false }"#).expect("writable");
        let path = tuning.to_str().expect("a UTF-8 path");
        let mut args = Command::parse_from(["bench", "--quick", "--tuning", path]).bench;
        read_tuning(&mut args).expect("valid");
        let command = command_line(&args, Suite::Quick).expect("serialisable");
        assert!(
            command.contains(r#" --tuning '{"rod_search":false}'"#),
            "{command}"
        );
        assert!(!command.contains(path), "{command}");
    }
}
