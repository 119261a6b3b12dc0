//! `patchwork redesign DESIGN.json MEASURED --out DIR [--units U] [--fit
//! LIST] [design's search flags]`: from a built balloon back to a new
//! design in one command — the measurement compared with its design, the
//! materials calibrated to it, and the target designed again on them.

use std::path::PathBuf;

use anyhow::{Context, Result, anyhow};
use clap::Args;
use patchwork_core::calibrate::{Built, Materials, Measurements, Parameter, calibrate};
use patchwork_core::curve::Units;
use patchwork_core::design::Design;
use patchwork_core::inverse::Smoothing;
use patchwork_core::measure::Prediction;

use super::calibrate_cmd::{self, parse_fit, write_options};
use super::compare_cmd::{self, compare_measured, scanned_radius};
use super::design_cmd::{DesignFlags, design_into};
use super::design_summary::summary as design_summary;
use super::input::{parse_units, read_text_argument};
use super::output::emit;

#[derive(Args)]
#[command(allow_negative_numbers = true)]
pub struct RedesignArgs {
    /// The design.json of the balloon that was built (as `design` wrote
    /// it, with the target).
    design: String,
    /// Its measured centreline or 3D scan (as `compare` takes it).
    measured: String,
    /// Folder for compare/ (the built balloon against its design),
    /// calibration.json, options.json (the calibrated materials) and
    /// design/ (the new design and its cut files).
    #[arg(long)]
    out: PathBuf,
    /// Units of the measured coordinates.
    #[arg(long, default_value = "mm", value_parser = parse_units)]
    units: Units,
    /// The parameters to calibrate (as `calibrate --fit`) [default:
    /// modulus,patch_modulus].
    #[arg(long)]
    fit: Option<String>,
    #[command(flatten)]
    flags: DesignFlags,
}

pub fn run(args: RedesignArgs) -> Result<()> {
    let prediction = Prediction::from_design_json(&read_text_argument(&args.design)?)
        .with_context(|| args.design.clone())?;
    let target = prediction.target.clone().ok_or_else(|| {
        anyhow!(
            "{}: no target_mm (written by an older version): design the target again with `design --options`",
            args.design
        )
    })?;
    let fit = match &args.fit {
        None => vec![Parameter::Modulus, Parameter::PatchModulus],
        Some(names) => parse_fit(names)?,
    };
    let design = prediction.design.clone();
    // Checked before anything is computed or written.
    let base = |materials: Materials| Design {
        patches: Vec::new(),
        ..materials.on(&design)
    };
    args.flags.plan(
        base(Materials {
            balloon: design.balloon.material.clone(),
            patch: design.patch.material.clone(),
        }),
        Smoothing::Auto,
    )?;

    let (comparison, centreline_mm) = compare_measured(&prediction, &args.measured, args.units)
        .with_context(|| args.measured.clone())?;
    compare_cmd::write_files(&args.out.join("compare"), &comparison)?;
    let data = Measurements {
        built: vec![Built {
            design: design.clone(),
            centreline_mm,
            radius_mm: scanned_radius(&comparison),
        }],
        ..Measurements::default()
    };
    let calibration = calibrate(&design.balloon, &design.patch.material, &data, &fit)?;
    let write = |name: &str, text: String| {
        let path = args.out.join(name);
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))
    };
    write(
        "calibration.json",
        serde_json::to_string_pretty(&calibration)? + "\n",
    )?;
    write_options(
        &args.out.join("options.json"),
        &calibration,
        design.balloon.clone(),
        design.patch.clone(),
    )?;

    let plan = args.flags.plan(
        base(Materials {
            balloon: calibration.material.clone(),
            patch: calibration.patch_material.clone(),
        }),
        Smoothing::Auto,
    )?;
    let out = args.out.join("design");
    let report = design_into(&target, &plan, &out, None)?;
    emit(&format!(
        "— the built balloon against its design —\n{}\n— calibrated to it —\n{}\n— the new design —\n{}",
        compare_cmd::summary(&comparison),
        calibrate_cmd::summary(&calibration),
        design_summary(&report, &out)
    ))
}
