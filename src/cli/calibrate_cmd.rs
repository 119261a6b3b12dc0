//! `patchwork calibrate [INFLATION.csv] [--volume PV.csv] [--built
//! DESIGN.json=MEASURED]... [--balloon JSON] [--patch JSON] [--fit LIST]
//! [--units U] [--json] [--out FILE]`: the materials fitted to what was
//! measured on the lab's own balloons.

use std::path::PathBuf;

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use patchwork_core::calibrate::{
    Built, Calibration, CalibrationError, Inflation, Measurements, Parameter, PressureVolume,
    calibrate,
};
use patchwork_core::curve::Units;
use patchwork_core::design::{Balloon, PatchSpec};
use patchwork_core::measure::Prediction;

use super::calibrate_table::{Table, read_table};
use super::compare_cmd::{compare_measured, scanned_radius};
use super::input::{json_argument, parse_units, read_text_argument};
use super::output::{emit, emit_json};

#[derive(Args)]
pub struct CalibrateArgs {
    /// The bare balloon measured inflated: CSV with a header naming
    /// `pressure_kpa` and `length_mm` (clamp to tip) and/or `diameter_mm`
    /// (across the middle), one pressure per line; an empty cell is not
    /// measured. `-` reads stdin.
    inflation: Option<String>,
    /// The bare balloon's pressure–volume curve: CSV with `pressure_kpa`
    /// and `volume_ml` columns (the volume inside the balloon: pumped in
    /// plus the uninflated balloon's own). Points past the pressure's peak
    /// are left out, and said.
    #[arg(long, value_name = "CSV")]
    volume: Option<String>,
    /// A balloon built from a design and measured: `DESIGN.json=MEASURED`,
    /// the design.json that `design` wrote and the measured centreline
    /// file or 3D scan (as `compare` takes them; a scan's radius is fitted
    /// too). Repeat for more.
    #[arg(long, value_name = "DESIGN=MEASURED")]
    built: Vec<String>,
    /// Units of the measured centrelines and scans.
    #[arg(long, default_value = "mm", value_parser = parse_units)]
    units: Units,
    /// The uninflated balloon and the material to start from (design
    /// JSON's `balloon`) [default: the first built design's, else the
    /// reference scene's].
    #[arg(long)]
    balloon: Option<String>,
    /// The patch (design JSON's `patch`) to start from [default: the first
    /// built design's, else the reference scene's].
    #[arg(long)]
    patch: Option<String>,
    /// The parameters to fit, comma-separated: `modulus` (every modulus of
    /// the balloon's law scaled alike), `lambda_m` (Arruda–Boyce), `jm`
    /// (Gent), `bulk_ratio`, `patch_modulus` (needs --built) [default: the
    /// modulus and the law's stiffening from bare-balloon data, the modulus
    /// and the patch's from built designs alone].
    #[arg(long)]
    fit: Option<String>,
    /// Print the calibration as JSON.
    #[arg(long)]
    json: bool,
    /// Write `{"balloon": …, "patch": …}` with the calibrated materials
    /// here: what `design --options` and `simulate` take.
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(args: CalibrateArgs) -> Result<()> {
    let (data, lines) = measurements(&args)?;
    let first = data.built.first().map(|b| &b.design);
    let balloon: Balloon = match &args.balloon {
        Some(text) => json_argument("balloon", text)?,
        None => first.map_or_else(Balloon::default, |d| d.balloon.clone()),
    };
    let patch: PatchSpec = match &args.patch {
        Some(text) => json_argument("patch", text)?,
        None => first.map_or_else(PatchSpec::default, |d| d.patch.clone()),
    };
    for (flag, material) in [
        ("--balloon", &balloon.material),
        ("--patch", &patch.material),
    ] {
        material.validate().map_err(|e| anyhow!("{flag}: {e}"))?;
    }
    let fit = parameters(args.fit.as_deref(), &balloon, &data)?;
    let calibration =
        calibrate(&balloon, &patch.material, &data, &fit).map_err(|e| lines.name(&args, e))?;
    if let Some(path) = &args.out {
        write_options(path, &calibration, balloon, patch)?;
    }
    match args.json {
        true => emit_json(&calibration),
        false => emit(&summary(&calibration)),
    }
}

/// Writes `{"balloon": …, "patch": …}` with the calibrated materials.
pub fn write_options(
    path: &std::path::Path,
    calibration: &Calibration,
    balloon: Balloon,
    patch: PatchSpec,
) -> Result<()> {
    let options = serde_json::json!({
        "balloon": Balloon { material: calibration.material.clone(), ..balloon },
        "patch": PatchSpec { material: calibration.patch_material.clone(), ..patch },
    });
    std::fs::write(path, serde_json::to_string_pretty(&options)? + "\n")
        .with_context(|| format!("cannot write {}", path.display()))
}

/// The CSV line of each inflation and P–V point, to name a refused one.
#[derive(Default)]
struct Lines {
    inflation: Vec<usize>,
    pressure_volume: Vec<usize>,
}

impl Lines {
    /// `error` with a refused measurement named by its file and line.
    fn name(&self, args: &CalibrateArgs, error: CalibrationError) -> anyhow::Error {
        let CalibrationError::Datum {
            kind,
            index,
            reason,
        } = &error
        else {
            return error.into();
        };
        let (file, lines) = match *kind {
            "inflation" => (args.inflation.as_deref(), &self.inflation),
            "pressure_volume" => (args.volume.as_deref(), &self.pressure_volume),
            _ => return error.into(),
        };
        match (file, lines.get(*index)) {
            (Some(file), Some(line)) => anyhow!("{file}: line {line}: {reason}"),
            _ => error.into(),
        }
    }
}

fn measurements(args: &CalibrateArgs) -> Result<(Measurements, Lines)> {
    let mut data = Measurements::default();
    let mut lines = Lines::default();
    if let Some(path) = &args.inflation {
        let table = read_table(
            &read_text_argument(path)?,
            &["pressure_kpa"],
            &["length_mm", "diameter_mm"],
        )
        .with_context(|| path.clone())?;
        data.inflation = inflations(&table).with_context(|| path.clone())?;
        lines.inflation = table.rows.iter().map(|(line, _)| *line).collect();
    }
    if let Some(path) = &args.volume {
        let table = read_table(
            &read_text_argument(path)?,
            &["pressure_kpa", "volume_ml"],
            &[],
        )
        .with_context(|| format!("--volume {path}"))?;
        lines.pressure_volume = table.rows.iter().map(|(line, _)| *line).collect();
        data.pressure_volume = table
            .rows
            .iter()
            .map(|(_, cells)| PressureVolume {
                pressure_kpa: cells[0].unwrap_or(f64::NAN),
                volume_ml: cells[1].unwrap_or(f64::NAN),
            })
            .collect();
    }
    for pair in &args.built {
        data.built.push(built(pair, args.units)?);
    }
    if data.inflation.is_empty() && data.pressure_volume.is_empty() && data.built.is_empty() {
        bail!("nothing measured: give an inflation CSV, --volume or --built");
    }
    Ok((data, lines))
}

fn inflations(table: &Table) -> Result<Vec<Inflation>> {
    if !table.has(1) && !table.has(2) {
        bail!("no `length_mm` or `diameter_mm` column");
    }
    if table.rows.is_empty() {
        bail!("no measured lines");
    }
    table
        .rows
        .iter()
        .map(|(line, cells)| {
            Ok(Inflation {
                pressure_kpa: cells[0].ok_or_else(|| anyhow!("line {line}: no pressure"))?,
                length_mm: cells[1],
                diameter_mm: cells[2],
            })
        })
        .collect()
}

/// `DESIGN.json=MEASURED`: the design and its measured centreline, base to
/// tip (a scan's as extracted and cut at the cap).
fn built(pair: &str, units: Units) -> Result<Built> {
    let (design, measured) = pair
        .split_once('=')
        .ok_or_else(|| anyhow!("--built {pair}: give DESIGN.json=MEASURED"))?;
    let prediction = Prediction::from_design_json(&read_text_argument(design)?)
        .with_context(|| format!("--built {design}"))?;
    let (comparison, centreline_mm) = compare_measured(&prediction, measured, units)
        .with_context(|| format!("--built {measured}"))?;
    Ok(Built {
        design: prediction.design,
        centreline_mm,
        radius_mm: scanned_radius(&comparison),
    })
}

/// The parameters named, or the default for the data and the law.
fn parameters(
    names: Option<&str>,
    balloon: &Balloon,
    data: &Measurements,
) -> Result<Vec<Parameter>> {
    match names {
        Some(names) => parse_fit(names),
        None => Ok(Parameter::defaults(&balloon.material, data)),
    }
}

/// `--fit`'s comma-separated parameter names.
pub fn parse_fit(names: &str) -> Result<Vec<Parameter>> {
    names
        .split(',')
        .map(|n| {
            Parameter::from_name(n.trim()).ok_or_else(|| {
                anyhow!("--fit: unknown parameter {n:?}: use {}", Parameter::names())
            })
        })
        .collect()
}

/// The calibration as a person reads it.
pub fn summary(c: &Calibration) -> String {
    let mut text = format!(
        "calibrated:   {} FE solves, residuals {:.2} % RMS\n",
        c.solves, c.rms_percent
    );
    for p in &c.parameters {
        let interval = p.interval95.map_or("no interval".to_string(), |[lo, hi]| {
            format!("95 %: {lo:.4} – {hi:.4}")
        });
        text += &format!(
            "  {:<14} {:.4}  ({interval}; from {:.4})\n",
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
    for b in &c.built {
        let radius = b.measured_radius_mm.map_or(String::new(), |r| {
            format!(
                ", radius {r:.2} mm measured, {:.2} mm model",
                b.predicted_radius_mm
            )
        });
        text += &format!(
            "  built {}: model against the measured centreline {:.2} % of its length (from {:.2} % before), length {:.1} mm measured, {:.1} mm model{radius}\n",
            b.index + 1,
            b.shape_error_percent,
            b.shape_error_start_percent,
            b.measured_length_mm,
            b.predicted_length_mm
        );
    }
    for w in &c.warnings {
        text += &format!("warning:      {w}\n");
    }
    text + &format!(
        "material:     {}\npatch:        {}\n",
        serde_json::to_string(&c.material).unwrap_or_default(),
        serde_json::to_string(&c.patch_material).unwrap_or_default()
    )
}
