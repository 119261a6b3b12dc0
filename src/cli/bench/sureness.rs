//! The report's "How sure a design is": what the spread stage costs a
//! `draft` run (from the curve suite's own runs), and on five curves of the
//! suite a `draft` design made robust (`tuning.robust`) with the
//! Monte-Carlo check of the design that stands (`tuning.monte_carlo`):
//! nominal and expected shape error under both objectives, and the sampled
//! spread against the linear one.

use std::cell::Cell;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::{Context, Result};
use patchwork_core::curve::presets::Preset;
use patchwork_core::inverse::{
    Fidelity, Plan, RobustSummary, StageName, TuningOverrides, UserSettings, design,
};
use patchwork_core::spread::MonteCarlo;
use serde_json::json;

use super::args::BenchArgs;
use super::cases::laid_over;
use super::measure::stage_clock;
use super::row::{Row, median};

/// The curves made robust and checked by sampling: a plain bend, a helix,
/// a hook, an S and a grasp (presets with these parameters).
const CURVES: [(&str, &str); 5] = [
    ("arc", r#"{"radius_mm": 80, "angle_deg": 180}"#),
    ("helix", "{}"),
    ("hook", "{}"),
    ("s_curve", "{}"),
    ("grasp", "{}"),
];

/// Designs of each Monte-Carlo check.
const SAMPLES: usize = 200;

/// One curve's robust design and its check.
pub struct SureRow {
    pub curve: String,
    pub robust: Option<RobustSummary>,
    pub linear_rms_mm: f64,
    pub check: Option<MonteCarlo>,
    pub wall_s: f64,
    /// Seconds of the robust stage, the check's included.
    pub robust_s: f64,
}

/// Each of `CURVES` designed under `draft` (seed 1) with the robust refine
/// and the Monte-Carlo check.
pub fn measure(args: &BenchArgs) -> Result<Vec<SureRow>> {
    let mut rows = Vec::new();
    let named = |name: &str| args.curves.is_empty() || args.curves.iter().any(|c| name.contains(c));
    for (name, params) in CURVES.into_iter().filter(|(name, _)| named(name)) {
        let preset =
            Preset::from_name(name, serde_json::from_str(params)?).map_err(anyhow::Error::msg)?;
        let curve = preset.curve(None)?;
        let settings = UserSettings {
            fidelity: Fidelity::Draft,
            seed: 1,
            threads: args.threads,
            ..UserSettings::default()
        };
        let own: TuningOverrides =
            serde_json::from_value(json!({"robust": true, "monte_carlo": SAMPLES}))?;
        let overrides = laid_over(&own, &args.overrides)?;
        let plan = Plan::resolve(settings, &overrides)?;
        let started = Instant::now();
        let robust_from = Cell::new(f64::NAN);
        let mut observe = stage_clock(StageName::Robust, started, &robust_from);
        let o = design(&curve, &plan, &AtomicBool::new(false), &mut observe)
            .with_context(|| format!("{name}: the robust design"))?;
        let wall_s = started.elapsed().as_secs_f64();
        let spread = o.spread.as_ref();
        let row = SureRow {
            curve: format!("{name} {params}"),
            robust: o.robust.clone(),
            linear_rms_mm: spread.map_or(f64::NAN, |s| s.rms_mm),
            check: spread.and_then(|s| s.monte_carlo.clone()),
            wall_s,
            robust_s: wall_s - robust_from.get(),
        };
        eprintln!("{:<40} robust and checked in {wall_s:.1} s", row.curve);
        rows.push(row);
    }
    Ok(rows)
}

/// The headline's line: the spread stage's share of a `draft` run, and
/// how the checks and robust designs came out.
pub fn headline(curves: &[Row], sure: &[SureRow]) -> String {
    let (share, most) = spread_share(curves);
    let agree = (sure.iter().filter_map(|r| r.check.as_ref()))
        .filter(|c| c.agrees)
        .count();
    let lower = sure
        .iter()
        .filter_map(|r| r.robust.as_ref())
        .filter(|r| r.robust_design.expected_percent < r.nominal_design.expected_percent)
        .count();
    format!(
        "| how sure a design is, `draft` | the spread stage: median {share:.0} % of a run, at most {most:.0} %; \
         Monte-Carlo ({SAMPLES} designs) agrees with the linear spread on {agree} of {n} curves; \
         the robust refine lowers the expected shape error on {lower} of {n} |\n",
        n = sure.len()
    )
}

/// The spread stage's median and largest share of a `draft` run (%).
fn spread_share(curves: &[Row]) -> (f64, f64) {
    let shares: Vec<f64> = (curves.iter())
        .filter(|r| r.setting == "draft" && r.figures.spread_s.is_finite())
        .map(|r| 100.0 * r.figures.spread_s / r.figures.wall_s)
        .collect();
    let most = shares.iter().copied().fold(f64::NAN, f64::max);
    (median(shares), most)
}

/// The section: the spread's cost per suite curve, then the robust designs
/// and their checks.
pub fn section(curves: &[Row], sure: &[SureRow]) -> String {
    let mut s = String::from("## How sure a design is\n\n");
    let draft: Vec<&Row> = curves.iter().filter(|r| r.setting == "draft").collect();
    if !draft.is_empty() {
        s.push_str(
            "Every design reports its spread at the default tolerances (every patch quantity \
             and the balloon's three linearised at once; the balloon's solved together at two \
             points of their joint variable on the verification model, the patches' at half the \
             largest change or more at + and − their tolerance on graded 2 mm; a round's solves \
             shared out over the threads). Its cost in the suite's `draft` runs above:\n\n\
             | curve | spread % of length | spread stage s | share of the run |\n|---|---|---|---|\n",
        );
    }
    for r in draft {
        let f = &r.figures;
        s.push_str(&format!(
            "| {} | {:.2} | {:.1} | {:.0} % |\n",
            r.curve,
            f.spread_percent,
            f.spread_s,
            100.0 * f.spread_s / f.wall_s
        ));
    }
    s.push_str(&format!(
        "\nFive curves designed under `draft` (seed 1) with `--tuning '{{\"robust\": true, \
         \"monte_carlo\": {SAMPLES}}}'`: the nominal design and the robust one, each as designed, \
         its spread and the error expected as built (√(nominal² + spread²), % of the length), \
         the design kept, and the Monte-Carlo check of the design kept ({SAMPLES} designs \
         drawn at the tolerances and solved in full; agreeing within 20 %).\n\n\
         | curve | nominal design: as designed, spread, expected % | robust design: as designed, spread, expected % | kept | Monte-Carlo / linear RMS | robust stage s | run s |\n\
         |---|---|---|---|---|---|---|\n"
    ));
    for r in sure {
        s.push_str(&sure_line(r));
    }
    s
}

fn sure_line(r: &SureRow) -> String {
    let figures = |e: &patchwork_core::inverse::Expected| {
        format!(
            "{:.2}, {:.2}, {:.2}",
            e.shape_error_percent, e.spread_percent, e.expected_percent
        )
    };
    let (nominal, robust, kept) = match &r.robust {
        Some(rb) => (
            figures(&rb.nominal_design),
            figures(&rb.robust_design),
            if rb.kept { "robust" } else { "nominal" },
        ),
        None => ("–".into(), "–".into(), "–"),
    };
    let check = r.check.as_ref().map_or("–".into(), |c| {
        format!(
            "{:.2} / {:.2} mm = {:.2} ± {:.2} ({})",
            c.rms_mm,
            r.linear_rms_mm,
            c.ratio,
            c.ratio_sigma,
            if c.agrees { "agrees" } else { "differs" }
        )
    });
    format!(
        "| {} | {nominal} | {robust} | {kept} | {check} | {:.0} | {:.0} |\n",
        r.curve, r.robust_s, r.wall_s
    )
}
