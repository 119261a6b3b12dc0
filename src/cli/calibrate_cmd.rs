//! `patchwork calibrate DATA.csv [--balloon JSON] [--fit modulus,lambda_m]
//! [--json] [--out FILE]`: the balloon's material fitted to its measured
//! inflation.

use std::path::PathBuf;

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use patchwork_core::calibrate::{Calibration, Inflation, Parameter, calibrate};
use patchwork_core::design::Balloon;
use patchwork_core::material::Law;

use super::input::{json_argument, read_text_argument};
use super::output::{emit, emit_json};

#[derive(Args)]
pub struct CalibrateArgs {
    /// The bare balloon measured inflated: CSV with a header naming
    /// `pressure_kpa` and `length_mm` (clamp to tip) and/or `diameter_mm`
    /// (across the middle), one pressure per line; an empty cell is not
    /// measured. `-` reads stdin.
    data: String,
    /// The uninflated balloon and the material to start from (design
    /// JSON's `balloon`: length_mm, radius_mm, wall_mm, material) [default:
    /// the reference scene's].
    #[arg(long)]
    balloon: Option<String>,
    /// The parameters to fit, comma-separated: `modulus` (every modulus of
    /// the law scaled alike), `lambda_m` (Arruda–Boyce), `jm` (Gent),
    /// `bulk_ratio` [default: modulus and the law's stiffening].
    #[arg(long)]
    fit: Option<String>,
    /// Print the calibration as JSON.
    #[arg(long)]
    json: bool,
    /// Write `{"balloon": …}` with the calibrated material here: what
    /// `design --options` and `simulate` take.
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(args: CalibrateArgs) -> Result<()> {
    let data = read_data(&read_text_argument(&args.data)?).with_context(|| args.data.clone())?;
    let balloon: Balloon = match &args.balloon {
        Some(text) => json_argument("balloon", text)?,
        None => Balloon::default(),
    };
    balloon
        .material
        .validate()
        .map_err(|e| anyhow!("--balloon: {e}"))?;
    let fit = parameters(args.fit.as_deref(), &balloon)?;
    let calibration = calibrate(&balloon, &data, &fit)?;
    if let Some(path) = &args.out {
        let options = serde_json::json!({"balloon": Balloon {
            material: calibration.material.clone(),
            ..balloon
        }});
        std::fs::write(path, serde_json::to_string_pretty(&options)? + "\n")
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    match args.json {
        true => emit_json(&calibration),
        false => emit(&summary(&calibration)),
    }
}

/// The CSV's inflations; errors name the line and the column.
fn read_data(text: &str) -> Result<Vec<Inflation>> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (_, header) = lines.next().ok_or_else(|| anyhow!("no header line"))?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let column = |name: &str| names.iter().position(|n| *n == name);
    let pressure =
        column("pressure_kpa").ok_or_else(|| anyhow!("line 1: no `pressure_kpa` column"))?;
    let (length, diameter) = (column("length_mm"), column("diameter_mm"));
    if length.is_none() && diameter.is_none() {
        bail!("line 1: neither a `length_mm` nor a `diameter_mm` column");
    }
    lines
        .map(|(number, line)| {
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            let cell = |index: Option<usize>| -> Result<Option<f64>> {
                match index.and_then(|i| cells.get(i)).filter(|c| !c.is_empty()) {
                    None => Ok(None),
                    Some(text) => text
                        .parse()
                        .map(Some)
                        .map_err(|_| anyhow!("line {}: {text:?} is not a number", number + 1)),
                }
            };
            Ok(Inflation {
                pressure_kpa: cell(Some(pressure))?
                    .ok_or_else(|| anyhow!("line {}: no pressure", number + 1))?,
                length_mm: cell(length)?,
                diameter_mm: cell(diameter)?,
            })
        })
        .collect()
}

fn parameters(names: Option<&str>, balloon: &Balloon) -> Result<Vec<Parameter>> {
    let Some(names) = names else {
        return Ok(match balloon.material.law {
            Law::ArrudaBoyce { .. } => vec![Parameter::Modulus, Parameter::LambdaM],
            Law::Gent { .. } => vec![Parameter::Modulus, Parameter::Jm],
            _ => vec![Parameter::Modulus],
        });
    };
    names
        .split(',')
        .map(|n| {
            Parameter::from_name(n.trim()).ok_or_else(|| {
                anyhow!("--fit: unknown parameter {n:?}: use modulus, lambda_m, jm or bulk_ratio")
            })
        })
        .collect()
}

fn summary(c: &Calibration) -> String {
    let mut text = format!(
        "calibrated:   {} FE solves, residuals {:.2} % RMS\n",
        c.solves, c.rms_percent
    );
    for p in &c.parameters {
        let interval = p.interval95.map_or("no interval".to_string(), |[lo, hi]| {
            format!("95 %: {lo:.4} – {hi:.4}")
        });
        text += &format!(
            "  {:<10} {:.4}  ({interval}; from {:.4})\n",
            p.parameter.name(),
            p.value,
            p.start
        );
    }
    for r in &c.residuals {
        text += &format!(
            "  {:>6.1} kPa  {:<12} measured {:>8.2}  model {:>8.2}  ({:+.2} %)\n",
            r.pressure_kpa, r.quantity, r.measured, r.predicted, r.percent
        );
    }
    for w in &c.warnings {
        text += &format!("warning:      {w}\n");
    }
    text + &format!(
        "material:     {}\n",
        serde_json::to_string(&c.material).unwrap_or_default()
    )
}
