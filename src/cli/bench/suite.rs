//! The bench's suites: the quick suite, the reference suite (time against
//! error per preset), the any-curve suite (curves unlike the references,
//! each under the presets as users get them), the round trips, and the
//! users' suite (`users.rs`).

use anyhow::Result;
use patchwork_core::curve::{Curve, Point, Preset};
use patchwork_core::design::random::{round_trip_designs, trains};
use patchwork_core::fe::simulate;
use patchwork_core::inverse::{Fidelity, Plan, TuningOverrides, UserSettings};
use serde_json::json;

use super::cases::{Setting, Suite, Target, Targets, preset, reference_curve, targets};

/// The curves and settings of `suite`.
pub fn suite(suite: Suite) -> Result<(Targets, Vec<Setting>)> {
    match suite {
        Suite::Quick => quick(),
        Suite::Reference => reference(),
        Suite::Curves => any_curve(),
        Suite::RoundTrips => round_trips(),
        Suite::Users => super::users::users(),
        Suite::Sure => anyhow::bail!("the sure suite has its own runs (bench::sureness)"),
        Suite::Report => anyhow::bail!("the report runs several suites (bench::report)"),
    }
}

fn quick() -> Result<(Targets, Vec<Setting>)> {
    let curves = vec![
        (
            "part-turn helix (61 mm)".to_string(),
            preset(
                "helix",
                json!({"radius_mm": 15, "pitch_mm": 40, "turns": 0.6}),
            )?,
        ),
        (
            "arc 90° (63 mm)".to_string(),
            preset("arc", json!({"radius_mm": 40, "angle_deg": 90}))?,
        ),
    ];
    let draft = Fidelity::Draft;
    let settings = vec![
        Setting::new("draft 60 no refine", draft, 60, 0),
        Setting::new("draft 60 refine 60", draft, 60, 60),
        Setting {
            correction: false,
            ..Setting::new("draft 60 refine 60 uncorrected", draft, 60, 60)
        },
        Setting {
            warm_starts: true,
            ..Setting::new("draft 60 refine 60 warm starts", draft, 60, 60)
        },
        Setting::new("standard 60 refine 75", Fidelity::Standard, 60, 75),
    ];
    Ok((targets(curves), settings))
}

fn reference() -> Result<(Targets, Vec<Setting>)> {
    let curves = vec![
        (
            "Hilbert (reference)".to_string(),
            reference_curve("hilbert")?,
        ),
        (
            "pancake (reference)".to_string(),
            reference_curve("pancake")?,
        ),
        ("spring (reference)".to_string(), reference_curve("spring")?),
        (
            "helix r20 p60 ×2".to_string(),
            preset(
                "helix",
                json!({"radius_mm": 20, "pitch_mm": 60, "turns": 2}),
            )?,
        ),
        (
            "trefoil knot".to_string(),
            preset("trefoil", json!({"scale_mm": 30}))?,
        ),
        (
            "hand-drawn-style arc (1 % noise, smoothed)".to_string(),
            noisy_arc()?,
        ),
    ];
    // The presets run as users get them (cold starts, the default); one row
    // measures warm starts against that, one the coarse search alone (no
    // coarse-to-fine refine), and one the refine without its finer model's
    // correction.
    let draft = Fidelity::Draft;
    let settings = vec![
        Setting::preset("draft", draft),
        Setting {
            correction: false,
            ..Setting::preset("draft without correction", draft)
        },
        Setting::new("draft without refine", draft, draft.budget(), 0),
        Setting::preset("standard", Fidelity::Standard),
        Setting {
            warm_starts: true,
            ..Setting::preset("standard with warm starts", Fidelity::Standard)
        },
        Setting::preset("fine", Fidelity::Fine),
    ];
    Ok((targets(curves), settings))
}

/// A 150 mm arc with 1 % (of length) seeded noise, smoothed as a user would.
fn noisy_arc() -> Result<Curve> {
    let arc = Preset::from_name("arc", json!({"radius_mm": 60, "angle_deg": 140}))
        .map_err(anyhow::Error::msg)?
        .curve(Some(300))?;
    Ok(arc
        .with_noise(0.01, 7)?
        .smoothed(10.0 * arc.length() / 300.0)?)
}

fn any_curve() -> Result<(Targets, Vec<Setting>)> {
    let mut curves = Vec::new();
    for radius in [40, 80, 150] {
        curves.push((
            format!("arc r{radius} 180°"),
            preset("arc", json!({"radius_mm": radius, "angle_deg": 180}))?,
        ));
    }
    let shapes = [
        ("planar S r60 90°", "s_curve", json!({})),
        ("S with a 30° kink", "s_curve", json!({"kink_deg": 30})),
        ("conical spiral r25→60", "spiral", json!({})),
        (
            "helix r30→50, pitch 40→80",
            "spiral",
            json!({"start_radius_mm": 30, "end_radius_mm": 50,
                   "start_pitch_mm": 40, "end_pitch_mm": 80, "turns": 1.5}),
        ),
        ("grasp a 10 mm nozzle", "grasp", json!({"diameter_mm": 10})),
        ("grasp a 40 mm pipe", "grasp", json!({"diameter_mm": 40})),
        ("hook", "hook", json!({})),
        ("trefoil knot", "trefoil", json!({"scale_mm": 30})),
    ];
    for (name, family, params) in shapes {
        curves.push((name.to_string(), preset(family, params)?));
    }
    let mut curves = targets(curves);
    for (name, three_d) in [("hand-drawn hook", false), ("hand-drawn 3D loop", true)] {
        let (clean, drawn) = hand_drawn(three_d)?;
        curves.push(Target {
            name: format!("{name} (±0.3 mm)"),
            curve: drawn,
            clean: Some(clean.clone()),
        });
        curves.push((format!("{name}, clean stroke"), clean).into());
    }
    for name in ["hilbert", "pancake", "spring"] {
        curves.push((format!("{name} (reference)"), reference_curve(name)?).into());
    }
    let settings = vec![
        Setting::preset("draft", Fidelity::Draft),
        Setting {
            trains: false,
            ..Setting::preset("draft without trains", Fidelity::Draft)
        },
        Setting {
            gentle_bends: false,
            ..Setting::preset("draft without gentle bends", Fidelity::Draft)
        },
        Setting {
            planar_designs: false,
            ..Setting::preset("draft without planar designs", Fidelity::Draft)
        },
        Setting {
            kappa_tol: Some(0.004),
            ..Setting::preset("draft κ_tol 0.004", Fidelity::Draft)
        },
        Setting::preset("standard", Fidelity::Standard),
        Setting::preset("fine", Fidelity::Fine),
    ];
    Ok((curves, settings))
}

/// The seed of the round trips' designs.
const ROUND_TRIP_SEED: u64 = 2027;

/// Ten seeded random designs, each simulated on draft's finest model (the
/// one its correction refines on); the centreline is the target, named by
/// the true layout ("trip 3: 9 patches, 5+1+3").
fn round_trips() -> Result<(Targets, Vec<Setting>)> {
    let draft = Plan::resolve(
        UserSettings {
            fidelity: Fidelity::Draft,
            ..UserSettings::default()
        },
        &TuningOverrides::default(),
    )?;
    let tuning = draft.tuning();
    let model = tuning.model(tuning.correction_mesh.unwrap_or(tuning.verify_mesh));
    let mut curves = Vec::new();
    for (i, truth) in round_trip_designs(10, ROUND_TRIP_SEED).iter().enumerate() {
        let centreline = simulate(truth, &model)?.centreline;
        let name = format!(
            "trip {}: {} patches, {}",
            i + 1,
            truth.patches.len(),
            trains(&truth.patches)
        );
        curves.push((name, centreline));
    }
    let settings = vec![
        Setting::preset("draft", Fidelity::Draft),
        Setting::preset("standard", Fidelity::Standard),
    ];
    Ok((targets(curves), settings))
}

/// A curve as a hand draws it: a smooth stroke (a few slow harmonics, planar
/// or not) sampled every millimetre or so, and the same with seeded jitter
/// of 0.3 mm.
fn hand_drawn(three_d: bool) -> Result<(Curve, Curve)> {
    let stroke = |t: f64| -> Point {
        let x = 260.0 * t + 12.0 * (3.1 * t).sin();
        let y = 70.0 * (1.0 - (2.6 * t).cos()) + 6.0 * (7.3 * t + 0.4).sin();
        let z = match three_d {
            true => 55.0 * (3.7 * t).sin() + 4.0 * (9.1 * t).cos(),
            false => 0.0,
        };
        Point::new(x, y, z)
    };
    let clean = Curve::from_points((0..320).map(|i| stroke(i as f64 / 319.0)).collect())?;
    let drawn = clean.with_noise(0.3 / clean.length(), if three_d { 31 } else { 17 })?;
    Ok((clean, drawn))
}
