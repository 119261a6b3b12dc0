//! `patchwork ksa FILE [--json] [--l0-mm] [--r0-mm] [--kappa-tol] [--merge-mm] [--width-mm]`.

use anyhow::{Result, bail};
use clap::Args;
use patchwork_core::ksa::{KsaParams, Stretch, ksa};

use super::input::CurveInput;
use super::output::{emit, emit_json, patch_table};
use crate::reports::KsaReport;

#[derive(Args)]
#[command(allow_negative_numbers = true)]
pub struct KsaArgs {
    #[command(flatten)]
    input: CurveInput,
    /// Print `{"stretch", "patches": [{"x_mm", "y_mm", "h_mm", "w_mm", "theta_deg"}]}`.
    #[arg(long)]
    json: bool,
    /// Uninflated balloon length L0 (mm).
    #[arg(long, default_value_t = 292.0)]
    l0_mm: f64,
    /// Uninflated balloon radius R0 (mm).
    #[arg(long, default_value_t = 3.18)]
    r0_mm: f64,
    /// Curvature above which a stretch of curve needs a patch (1/mm).
    #[arg(long, default_value_t = 0.01)]
    kappa_tol: f64,
    /// Marked points further apart than this (mm of arc) are separate patches.
    #[arg(long, default_value_t = 20.0)]
    merge_mm: f64,
    /// Width given to every patch (mm); KSA itself says nothing about width.
    #[arg(long, default_value_t = 1.5)]
    width_mm: f64,
    /// Axial stretch: `uniform` (the authors' L_curve/L0) or a number λ, in which
    /// case the balloon to cut is L_curve/λ long.
    #[arg(long, default_value = "uniform")]
    stretch: String,
}

pub fn run(args: KsaArgs) -> Result<()> {
    let curve = args.input.load()?;
    let stretch = match args.stretch.as_str() {
        "uniform" => Stretch::Uniform,
        text => match text.parse::<f64>() {
            Ok(lambda) => Stretch::Fixed(lambda),
            Err(_) => bail!("--stretch must be `uniform` or a number, got {text:?}"),
        },
    };
    let params = KsaParams {
        l0_mm: args.l0_mm,
        r0_mm: args.r0_mm,
        kappa_tol: args.kappa_tol,
        merge_mm: args.merge_mm,
        width_mm: args.width_mm,
        stretch,
        ..KsaParams::default()
    };
    let result = ksa(&curve, &params)?;
    let report = KsaReport::new(&curve, result, &params);
    if args.json {
        return emit_json(&report);
    }
    emit(&table(&report, &params))
}

fn table(report: &KsaReport, params: &KsaParams) -> String {
    let mut text = format!(
        "curve {:.1} mm, balloon L0 {:.1} mm × R0 {:.2} mm, stretch λ = {:.4}\n",
        report.curve_length_mm, params.l0_mm, params.r0_mm, report.stretch
    );
    if report.patches.is_empty() {
        text.push_str("no patches: the curve never exceeds the curvature tolerance\n");
    } else {
        text.push_str(&patch_table(&report.patches, |i| {
            if report.clipped.contains(&i) {
                "  clipped at the balloon's end"
            } else {
                ""
            }
        }));
    }
    if report.runs_off_balloon > 0 {
        text.push_str(&format!(
            "warning: {} curved stretch(es) lie beyond the balloon's end at this stretch; \
             cut a balloon of {:.1} mm\n",
            report.runs_off_balloon, report.uninflated_length_to_cut_mm
        ));
    }
    text
}
