//! `patchwork spread DESIGN.json [--tolerances JSON] [--json]`: how far the
//! inflated centreline moves under the tolerances a lab works to — each
//! patch's placement, angle and size, the pressure, the wall and the
//! modulus — and which of them matter most (the core's `spread`).

use anyhow::{Context, Result};
use clap::Args;
use patchwork_core::curve::{Curve, Point};
use patchwork_core::fe::SimulateOptions;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::spread::{Check, Tolerances, linear_spread};

use super::input::{json_argument, read_text_argument};
use super::output::{emit, emit_json};
use super::simulate_cmd::design_of;
use super::spread_summary::summary;

#[derive(Args)]
pub struct SpreadArgs {
    /// The design.json that `design` writes (its target is measured
    /// against), or a design JSON as `simulate` takes it; `-` reads stdin.
    design: String,
    /// Tolerances, each one standard deviation, as JSON; fields left out
    /// keep their defaults: {"placement_mm": 1, "angle_deg": 2, "size_mm":
    /// 0.2, "pressure_kpa": 0.5, "wall_percent": 5, "modulus_percent": 3}
    /// (0 leaves a source out).
    #[arg(long)]
    tolerances: Option<String>,
    /// How many of the largest contributors to list.
    #[arg(long, default_value_t = 3)]
    top: usize,
    /// Threads for the solves [default: every core].
    #[arg(long)]
    threads: Option<usize>,
    /// Check the linear estimate with this many samples, every source drawn
    /// at once and solved in full (in parallel): the sampled RMS against
    /// the linear one, and whether they agree within 20 %.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(2..=10000))]
    monte_carlo: Option<u64>,
    /// The Monte-Carlo samples' random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Print the spread as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(args: SpreadArgs) -> Result<()> {
    let text = read_text_argument(&args.design)?;
    let design =
        design_of(&text).with_context(|| format!("{}: invalid design JSON", args.design))?;
    let target = target_of(&text).with_context(|| format!("{}: target_mm", args.design))?;
    let tolerances: Tolerances = match &args.tolerances {
        Some(text) => json_argument("tolerances", text)?,
        None => Tolerances::default(),
    };
    tolerances
        .validate()
        .map_err(|e| anyhow::anyhow!("--tolerances: {e}"))?;
    let options = SimulateOptions {
        mesh: MeshSpec::default_simulation(),
        ..SimulateOptions::default()
    };
    let threads = args.threads.unwrap_or_else(patchwork_core::available_cores);
    let check = args.monte_carlo.map(|samples| Check {
        // At most 10000 (the parser's range).
        samples: samples as usize,
        seed: args.seed,
    });
    let spread = linear_spread(
        &design,
        target.as_ref(),
        &tolerances,
        (&options, None),
        threads,
        check,
    )?;
    match args.json {
        true => emit_json(&spread),
        false => emit(&summary(&spread, args.top)),
    }
}

/// design.json's `target_mm`, where it has one.
fn target_of(text: &str) -> Result<Option<Curve>> {
    let value: serde_json::Value = serde_json::from_str(text)?;
    let Some(points) = value.get("target_mm") else {
        return Ok(None);
    };
    let points: Vec<[f64; 3]> = serde_json::from_value(points.clone())?;
    let points = points
        .iter()
        .map(|p| Point::new(p[0], p[1], p[2]))
        .collect();
    Ok(Some(Curve::from_points(points)?))
}
