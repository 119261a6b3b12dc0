//! Reading a target curve named on the command line (`-` for stdin).

use std::io::Read;
use std::path::Path;

use anyhow::{Context, Result};
use clap::Args;
use patchwork_core::curve::{Curve, Units, read_curve};
use patchwork_core::inverse::Smoothing;

/// Options shared by every command that reads a target curve.
#[derive(Args)]
pub struct CurveInput {
    /// Target curve: CSV/whitespace text (`x y z` per line) or JSON
    /// (`{"points": [[x,y,z], ...], "units": "mm"}`); `-` reads stdin.
    pub file: String,
    /// Units of the file's coordinates (JSON's own `units` field wins).
    #[arg(long, default_value = "mm", value_parser = parse_units)]
    pub units: Units,
    /// Gaussian smoothing along arc length, σ in mm (0: off, and `design`
    /// takes the points exactly as given, without reading sparse points
    /// through a spline). `design` chooses it from the noise it finds on
    /// the points when not given; the other commands then take the curve as
    /// given.
    #[arg(long, allow_negative_numbers = true)]
    pub smooth_mm: Option<f64>,
}

pub fn parse_units(text: &str) -> Result<Units, String> {
    text.parse()
        .map_err(|e: patchwork_core::CurveError| e.to_string())
}

/// The contents of a file named on the command line, or stdin for `-`.
pub fn read_text_argument(name: &str) -> Result<String> {
    if name == "-" {
        let mut text = String::new();
        std::io::stdin()
            .read_to_string(&mut text)
            .context("reading stdin")?;
        Ok(text)
    } else {
        std::fs::read_to_string(Path::new(name)).with_context(|| format!("cannot read {name}"))
    }
}

/// A JSON option's value: inline (`{…}`), or a file to read (`-`: stdin);
/// errors name the flag (and the file).
pub fn json_argument<T: serde::de::DeserializeOwned>(flag: &str, argument: &str) -> Result<T> {
    let parsed = match argument.trim_start().starts_with('{') {
        true => serde_json::from_str(argument),
        false => serde_json::from_str(
            &read_text_argument(argument).with_context(|| format!("--{flag}"))?,
        ),
    };
    parsed.map_err(|e| match argument.trim_start().starts_with('{') {
        true => anyhow::anyhow!("--{flag}: {e}"),
        false => anyhow::anyhow!("--{flag}: {argument}: {e}"),
    })
}

impl CurveInput {
    /// The curve, smoothed by `--smooth-mm` when given.
    pub fn load(&self) -> Result<Curve> {
        let curve = self.load_as_given()?;
        Ok(curve.smoothed(self.smooth_mm.unwrap_or(0.0))?)
    }

    /// The curve as the file gives it.
    pub fn load_as_given(&self) -> Result<Curve> {
        let text = read_text_argument(&self.file)?;
        read_curve(&text, self.units).with_context(|| self.file.clone())
    }

    /// How `design` smooths it: by `--smooth-mm` when given, else from the
    /// noise found on it.
    pub fn smoothing(&self) -> Smoothing {
        self.smooth_mm.map_or(Smoothing::Auto, Smoothing::Sigma)
    }
}
