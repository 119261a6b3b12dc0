//! `patchwork compare DESIGN.json MEASURED [--units U] [--target FILE]
//! [--json] [--out DIR]`: a built balloon's centreline against its design.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use patchwork_core::curve::{Units, read_curve};
use patchwork_core::measure::scan::centreline_from_scan;
use patchwork_core::measure::scan::read::{ScanFormat, read_scan};
use patchwork_core::measure::{
    Comparison, Prediction, ShapeFigures, compare, compare_scan, comparison_svg, median_along,
};

use super::input::{parse_units, read_text_argument};
use super::output::{emit, emit_json};

#[derive(Args)]
pub struct CompareArgs {
    /// The design.json that `design` wrote (the API's `design.json` file
    /// alike): the design, its predicted centreline and the target.
    design: String,
    /// What was measured on the inflated balloon: its centreline, as
    /// CSV/whitespace text (`x y z` per line) or JSON (`{"points": [...]}`),
    /// base to tip or tip to base (`-` reads stdin); or a 3D scan of its
    /// surface, told by the file's extension: `.ply`, `.obj`, `.stl`,
    /// `.xyz` or `.pts` (the centreline is extracted from it).
    measured: String,
    /// Units of the measured coordinates (JSON's own `units` field wins).
    #[arg(long, default_value = "mm", value_parser = parse_units)]
    units: Units,
    /// The target curve to measure against (mm), instead of the one in
    /// design.json (which reports written before it was kept lack).
    #[arg(long)]
    target: Option<String>,
    /// Print the comparison as JSON.
    #[arg(long)]
    json: bool,
    /// Also write compare.json and compare.svg (κ and τ along the length,
    /// measured against predicted) here, and for a scan the centreline
    /// extracted from it with its radius (scan_centreline.csv).
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(args: CompareArgs) -> Result<()> {
    let design_text = read_text_argument(&args.design)?;
    let mut prediction =
        Prediction::from_design_json(&design_text).with_context(|| args.design.clone())?;
    if let Some(target) = &args.target {
        let curve = read_curve(&read_text_argument(target)?, Units::Mm)
            .with_context(|| format!("--target {target}"))?;
        prediction = prediction.with_target(curve);
    }
    let (comparison, _) = compare_measured(&prediction, &args.measured, args.units)?;
    if let Some(dir) = &args.out {
        write_files(dir, &comparison)?;
    }
    match args.json {
        true => emit_json(&comparison),
        false => emit(&summary(&comparison)),
    }
}

/// `measured` (a centreline file, `-`, or a scan told by its extension)
/// compared with `prediction`; and the measured centreline itself (mm): as
/// given, or for a scan as extracted, run base to tip and cut at the cap.
pub fn compare_measured(
    prediction: &Prediction,
    measured: &str,
    units: Units,
) -> Result<(Comparison, Vec<[f64; 3]>)> {
    match ScanFormat::from_name(measured) {
        Some(format) => {
            let bytes =
                std::fs::read(measured).with_context(|| format!("cannot read {measured}"))?;
            let points = read_scan(&bytes, format, units).with_context(|| measured.to_string())?;
            let scan = centreline_from_scan(&points).with_context(|| measured.to_string())?;
            let comparison = compare_scan(prediction, &scan)?;
            let centreline = comparison
                .scan
                .as_ref()
                .map_or_else(Vec::new, |s| s.centreline_mm.clone());
            Ok((comparison, centreline))
        }
        None => {
            let curve = read_curve(&read_text_argument(measured)?, units)
                .with_context(|| measured.to_string())?;
            let comparison = compare(prediction, &curve)?;
            let centreline = curve.points().iter().map(|p| [p.x, p.y, p.z]).collect();
            Ok((comparison, centreline))
        }
    }
}

/// The tube's median radius a scan measured (mm); none for a centreline.
pub fn scanned_radius(comparison: &Comparison) -> Option<f64> {
    let scan = comparison.scan.as_ref()?;
    Some(median_along(&scan.curve().ok()?, &scan.radius_mm))
}

pub fn write_files(dir: &std::path::Path, comparison: &Comparison) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let write = |name: &str, text: String| {
        let path = dir.join(name);
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))
    };
    write(
        "compare.json",
        serde_json::to_string_pretty(comparison)? + "\n",
    )?;
    if let Some(scan) = &comparison.scan {
        let rows: String = scan
            .centreline_mm
            .iter()
            .zip(&scan.radius_mm)
            .map(|(p, r)| format!("{},{},{},{}\n", p[0], p[1], p[2], r))
            .collect();
        write("scan_centreline.csv", format!("x,y,z,radius\n{rows}"))?;
    }
    write("compare.svg", comparison_svg(comparison))
}

/// The comparison as a person reads it.
pub fn summary(c: &Comparison) -> String {
    let m = &c.measured;
    let mut text = format!(
        "measured:     {} points{}, {:.1} mm as given; noise {:.2} mm, smoothed with σ {:.1} mm\n\
         length:       {:.1} mm measured against {:.1} mm predicted ({:+.1} mm, {:+.1} %)\n",
        m.points,
        if m.reversed {
            " (given tip to base)"
        } else {
            ""
        },
        m.length_mm,
        m.input.noise_mm,
        m.input.smoothing_mm,
        m.smoothed_length_mm,
        c.predicted_length_mm,
        c.length_difference_mm,
        c.length_difference_percent,
    );
    if let Some(scan) = &c.scan {
        text += &format!(
            "scan:         {} points, {} on the tube; centreline extracted at {} cross-sections, \
             their points {:.2} mm RMS off a circle\n",
            scan.points,
            scan.points_on_tube,
            scan.centreline_mm.len(),
            scan.section_residual_mm,
        );
    }
    if let Some(r) = &c.radius {
        text += &format!(
            "radius:       {:.2} mm measured against {:.2} mm predicted ({:+.1} %, medians along the length)\n",
            r.measured_median_mm, r.predicted_median_mm, r.difference_percent
        );
    }
    text += &shape_line("vs predicted", &c.against_prediction);
    if let Some(figures) = &c.against_target {
        text += &shape_line("vs target", figures);
    }
    if let Some(figures) = &c.prediction_against_target {
        text += &shape_line("design/target", figures);
    }
    if !c.patches.is_empty() {
        text += "patch  stretch (%)   bend measured/predicted (°)   twist measured/predicted (°)   local error\n";
    }
    for r in &c.patches {
        text += &format!(
            "P{:<5} {:>4.0} – {:<4.0}   {:>8.1} / {:<8.1}            {:>8.1} / {:<8.1}             {:.2} mm ({:.2} %){}\n",
            r.patch,
            100.0 * r.from_fraction,
            100.0 * r.to_fraction,
            r.measured_bend_deg,
            r.predicted_bend_deg,
            r.measured_twist_deg,
            r.predicted_twist_deg,
            r.local_error_mm,
            r.local_error_percent,
            if c.most_divergent_patch == Some(r.patch) {
                "  ← diverges most"
            } else {
                ""
            },
        );
    }
    text
}

fn shape_line(label: &str, f: &ShapeFigures) -> String {
    format!(
        "{:<13} shape error {:.2} mm ({:.2} % of the length), largest {:.2} mm at {:.0} % from the base\n",
        format!("{label}:"),
        f.shape_error_mm,
        f.shape_error_percent,
        f.largest_mm,
        100.0 * f.largest_at_fraction,
    )
}
