//! `patchwork spread DESIGN.json [--tolerances JSON] [--mesh-mm M
//! [--straight-mm S]] [--json]`: how far the inflated centreline moves under
//! the tolerances a lab works to — each patch's placement, angle and size,
//! the pressure, the wall and the modulus — and which of them matter most
//! (the core's `spread`), on the models a design run finds its spread on
//! unless a mesh is given.

use anyhow::{Context, Result};
use clap::Args;
use patchwork_core::curve::{Curve, Point};
use patchwork_core::fe::SimulateOptions;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::inverse::Fidelity;
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
    /// Solve every source on this mesh (element size, mm; uniform unless
    /// `--straight-mm` is given too) [default: the models a design run
    /// uses: the balloon's sources on the 1 mm verification model (4 mm
    /// along bare stretches), each patch's on graded 2 mm (6 mm), so the
    /// figures are design.json's `spread`]. `--mesh-mm 0.5 --straight-mm 4`
    /// is `simulate`'s default mesh: a few per cent apart, several times
    /// the time.
    #[arg(long)]
    mesh_mm: Option<f64>,
    /// Axial element size along bare stretches (mm): every source on a
    /// graded mesh, `--mesh-mm` (default 0.5) under patches and at the ends.
    #[arg(long)]
    straight_mm: Option<f64>,
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
    let threads = args.threads.unwrap_or_else(patchwork_core::available_cores);
    let (options, patch_model) = models(&args, design.balloon.radius_mm, threads);
    let check = args.monte_carlo.map(|samples| Check {
        // At most 10000 (the parser's range).
        samples: samples as usize,
        seed: args.seed,
    });
    let spread = linear_spread(
        &design,
        target.as_ref(),
        &tolerances,
        (&options, patch_model.as_ref()),
        threads,
        check,
    )?;
    match args.json {
        true => emit_json(&spread),
        false => emit(&summary(&spread, args.top)),
    }
}

/// The model the balloon's sources (and the Monte-Carlo check) are solved
/// on, and the patches' where it differs: a design run's (every preset
/// finds its spread on the same pair), or the one mesh the user gave.
fn models(
    args: &SpreadArgs,
    radius_mm: f64,
    threads: usize,
) -> (SimulateOptions, Option<SimulateOptions>) {
    let tuning = Fidelity::Draft.tuning(radius_mm);
    let on = |mesh| SimulateOptions {
        threads,
        ..tuning.model(mesh)
    };
    if args.mesh_mm.is_some() || args.straight_mm.is_some() {
        return (
            on(MeshSpec::from_options(args.mesh_mm, args.straight_mm)),
            None,
        );
    }
    (on(tuning.verify_mesh), tuning.spread_patch_mesh.map(on))
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
