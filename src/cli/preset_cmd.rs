//! `patchwork preset NAME [KEY=VALUE ...] [--points N]`.

use anyhow::{Context, Result, bail};
use clap::Args;
use patchwork_core::curve::Preset;
use serde_json::{Map, Value};

use super::output::emit;

#[derive(Args)]
pub struct PresetArgs {
    /// helix, hilbert, saddle, trefoil, arc, line, spiral, s_curve, hook,
    /// grasp, reference — or `list`.
    name: String,
    /// Parameters as KEY=VALUE, e.g. `radius_mm=20 pitch_mm=60 turns=4`;
    /// `reference name=hilbert|pancake|spring`.
    params: Vec<String>,
    /// Number of samples (default 400; reference curves: as published).
    #[arg(long)]
    points: Option<usize>,
}

pub fn run(args: PresetArgs) -> Result<()> {
    if args.name == "list" {
        return emit(&list());
    }
    let mut params = Map::new();
    for pair in &args.params {
        let Some((key, value)) = pair.split_once('=') else {
            bail!("preset parameter {pair:?} is not KEY=VALUE");
        };
        let value = match value.parse::<f64>() {
            Ok(number) => serde_json::Number::from_f64(number)
                .map(Value::Number)
                .with_context(|| format!("preset parameter {key} = {value} is not finite"))?,
            Err(_) => Value::String(value.to_string()),
        };
        params.insert(key.to_string(), value);
    }
    let preset =
        Preset::from_name(&args.name, Value::Object(params)).map_err(anyhow::Error::msg)?;
    let curve = preset.curve(args.points)?;
    let mut csv = String::with_capacity(curve.len() * 40);
    csv.push_str("x,y,z\n");
    for p in curve.points() {
        csv.push_str(&format!(
            "{},{},{}\n",
            six_decimals(p.x),
            six_decimals(p.y),
            six_decimals(p.z)
        ));
    }
    emit(&csv)
}

fn list() -> String {
    let mut text = String::from("presets (parameters with defaults):\n");
    for name in Preset::NAMES {
        let defaults = match Preset::from_name(name, Value::Object(Map::new())) {
            Ok(preset) => serde_json::to_value(&preset)
                .ok()
                .and_then(|v| v.get("params").cloned())
                .map(|p| p.to_string())
                .unwrap_or_default(),
            Err(_) => "name=hilbert|pancake|spring".to_string(),
        };
        text.push_str(&format!("  {name:<10} {defaults}\n"));
    }
    text
}

/// Millimetres to six decimals (a nanometre), trailing zeros trimmed.
fn six_decimals(value: f64) -> String {
    let text = format!("{:.6}", value + 0.0);
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".to_string()
    } else {
        text.to_string()
    }
}
