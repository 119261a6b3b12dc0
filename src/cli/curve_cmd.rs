//! `patchwork curve FILE [--json]`.

use anyhow::Result;
use clap::Args;
use patchwork_core::curve::{AnalysisOptions, analyse};

use super::input::CurveInput;
use super::output::{emit, emit_json};
use crate::reports::CurveReport;

#[derive(Args)]
pub struct CurveArgs {
    #[command(flatten)]
    input: CurveInput,
    /// Print `{"length_mm", "points", "s_mm", "curvature_per_mm", "torsion_per_mm"}`.
    #[arg(long)]
    json: bool,
}

pub fn run(args: CurveArgs) -> Result<()> {
    let curve = args.input.load()?;
    if args.json {
        return emit_json(&CurveReport::new(&curve));
    }
    let analysis = analyse(&curve, &AnalysisOptions::default());
    let defined: Vec<f64> = analysis
        .torsion
        .iter()
        .zip(&analysis.torsion_defined)
        .filter(|(_, d)| **d)
        .map(|(t, _)| *t)
        .collect();
    let kappa = Summary::of(&analysis.curvature);
    let mut text = format!(
        "length      {:.2} mm\npoints      {}\ncurvature   min {:.5}  mean {:.5}  max {:.5} mm⁻¹ (smallest radius {})\n",
        curve.length(),
        curve.len(),
        kappa.min,
        kappa.mean,
        kappa.max,
        if kappa.max > 0.0 {
            format!("{:.1} mm", 1.0 / kappa.max)
        } else {
            "∞".to_string()
        },
    );
    if defined.is_empty() {
        text.push_str("torsion     undefined everywhere (the curve is straight)\n");
    } else {
        let tau = Summary::of(&defined);
        text.push_str(&format!(
            "torsion     min {:.5}  mean {:.5}  max {:.5} mm⁻¹ (defined at {} of {} points)\n",
            tau.min,
            tau.mean,
            tau.max,
            defined.len(),
            curve.len()
        ));
    }
    emit(&text)
}

struct Summary {
    min: f64,
    mean: f64,
    max: f64,
}

impl Summary {
    fn of(values: &[f64]) -> Summary {
        let min = values.iter().copied().fold(f64::INFINITY, f64::min);
        let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Summary {
            min,
            mean: values.iter().sum::<f64>() / values.len().max(1) as f64,
            max,
        }
    }
}
