//! The users' suite: curves as users send them rather than as presets
//! write them — gentle arcs, sparse CAD exports, noisy strokes with the
//! clean strokes they were drawn from, and kinds of curve the other suites
//! lack — each designed under draft.

use std::f64::consts::{PI, TAU};

use anyhow::Result;
use patchwork_core::curve::{Curve, Point, StrokeShape, seeded_stroke_shaped};
use serde_json::json;

use super::cases::{Setting, Target, Targets, sampled_preset as preset};
use patchwork_core::inverse::Fidelity;

/// The curves of the users' suite and its one setting, draft as users get it.
pub fn users() -> Result<(Targets, Vec<Setting>)> {
    let mut curves = Vec::new();
    curves.extend(gentle_arcs()?);
    curves.extend(sparse_exports()?);
    curves.extend(noisy_strokes()?);
    curves.extend(new_kinds()?);
    Ok((curves, vec![Setting::preset("draft", Fidelity::Draft)]))
}

fn named(name: &str, curve: Curve) -> Target {
    (name.to_string(), curve).into()
}

/// Arcs of radius 200–600 mm, bending less than KSA's tolerance marks.
fn gentle_arcs() -> Result<Vec<Target>> {
    [(200, 90), (400, 75), (600, 60)]
        .into_iter()
        .map(|(radius, angle)| {
            let arc = preset(
                "arc",
                json!({"radius_mm": radius, "angle_deg": angle}),
                None,
            )?;
            Ok(named(&format!("gentle arc r{radius} {angle}°"), arc))
        })
        .collect()
}

/// Helices, a conical spiral and a stroke exported with 15–22 points.
fn sparse_exports() -> Result<Vec<Target>> {
    Ok(vec![
        named(
            "CAD helix r40 pitch 70, 22 points",
            preset(
                "helix",
                json!({"radius_mm": 40, "pitch_mm": 70, "turns": 2}),
                Some(22),
            )?,
        ),
        named(
            "CAD helix r30 pitch 90, 15 points",
            preset(
                "helix",
                json!({"radius_mm": 30, "pitch_mm": 90, "turns": 1.5}),
                Some(15),
            )?,
        ),
        named(
            "CAD conical spiral, 20 points",
            preset("spiral", json!({}), Some(20))?,
        ),
        named("CAD spline stroke, 20 points", stroke(21)?.resample(20)?),
    ])
}

/// A sweeping stroke (bends of 20–45 mm radius, within reach): the
/// hand-drawn strokes of `seeded_stroke` bend as tight as 1–8 mm, which no
/// balloon reaches, and would measure only the reach verdict.
fn stroke(seed: u64) -> Result<Curve> {
    Ok(seeded_stroke_shaped(seed, 350, StrokeShape::SWEEPING)?)
}

/// Seeded strokes with 0.3, 0.6 and 1 mm of noise, and the clean strokes.
fn noisy_strokes() -> Result<Vec<Target>> {
    let mut targets = Vec::new();
    for (label, seed, noise) in [("A", 31, 0.3), ("B", 32, 0.6), ("C", 33, 1.0)] {
        let clean = stroke(seed)?;
        let drawn = clean.with_noise(noise / clean.length(), seed)?;
        targets.push(Target {
            name: format!("stroke {label} (±{noise} mm)"),
            curve: drawn,
            clean: Some(clean.clone()),
        });
        targets.push(named(&clean_name(label), clean));
    }
    Ok(targets)
}

fn clean_name(label: &str) -> String {
    format!("stroke {label}, clean")
}

/// The name of the clean stroke the drawn stroke `drawn` was drawn from
/// (`stroke A (±0.3 mm)` → `stroke A, clean`): the report compares their
/// designs.
pub(super) fn clean_stroke_of(drawn: &str) -> Option<String> {
    let label = drawn.strip_prefix("stroke ")?.split_once(" (±")?.0;
    Some(clean_name(label))
}

/// Kinds the other suites lack: a saddle, a planar wave, Viviani's curve (a
/// figure of eight on a sphere), a planar Archimedean spiral and a question
/// mark (a straight stem into a 240° bend, its curvature jumping).
fn new_kinds() -> Result<Vec<Target>> {
    let sampled = |f: &dyn Fn(f64) -> Point| -> Result<Curve> {
        Ok(Curve::from_points(
            (0..400).map(|i| f(i as f64 / 399.0)).collect(),
        )?)
    };
    // A sine of amplitude 15 mm and wavelength 150 mm, two wavelengths:
    // radius of curvature at its crests λ²/(4π²A) = 38 mm.
    let wave = sampled(&|t| {
        let x = 300.0 * t;
        Point::new(x, 15.0 * (TAU * x / 150.0).sin(), 0.0)
    })?;
    // Viviani's curve, a = 40 mm, t in ±(π − 0.3): tightest radius 36 mm.
    let viviani = sampled(&|t| {
        let u = (PI - 0.3) * (2.0 * t - 1.0);
        Point::new(
            40.0 * (1.0 + u.cos()),
            40.0 * u.sin(),
            80.0 * (0.5 * u).sin(),
        )
    })?;
    // r = 40 + 12 θ / 2π mm over one and a half turns.
    let spiral = sampled(&|t| {
        let theta = 3.0 * PI * t;
        let r = 40.0 + 12.0 * theta / TAU;
        Point::new(r * theta.cos(), r * theta.sin(), 0.0)
    })?;
    Ok(vec![
        named("saddle", preset("saddle", json!({}), None)?),
        named("planar wave A15 λ150", wave),
        named("Viviani's curve a40", viviani),
        named("planar spiral r40→58", spiral),
        named("question mark", question_mark()?),
    ])
}

/// A straight stem of 100 mm, then 240° of a circle of radius 50 mm.
fn question_mark() -> Result<Curve> {
    let stem = (0..100).map(|i| Point::new(0.0, i as f64, 0.0));
    let bend = (0..=300).map(|i| {
        let a = (240.0_f64).to_radians() * i as f64 / 300.0;
        Point::new(50.0 * (1.0 - a.cos()), 100.0 + 50.0 * a.sin(), 0.0)
    });
    Ok(Curve::from_points(stem.chain(bend).collect())?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use patchwork_core::inverse::input::{Smoothing, prepare};

    /// The suite is what it says: 18 curves, names unique, the noisy
    /// strokes with their clean strokes, the CAD exports sparse enough to
    /// be read through the spline and nothing else so read.
    #[test]
    fn the_users_suite_holds_its_kinds() {
        let (targets, settings) = users().unwrap();
        assert_eq!(targets.len(), 18);
        assert_eq!(settings.len(), 1);
        let mut names: Vec<&str> = targets.iter().map(|t| t.name.as_str()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), targets.len());
        for target in &targets {
            let noisy = target.name.contains('±');
            assert_eq!(target.clean.is_some(), noisy, "{}", target.name);
            // A drawn stroke's clean stroke is in the suite under the name
            // the report looks for.
            if noisy {
                let clean = clean_stroke_of(&target.name).unwrap();
                let twin = targets.iter().find(|t| t.name == clean).unwrap();
                assert_eq!(Some(&twin.curve), target.clean.as_ref(), "{clean}");
            }
            let (_, input) = prepare(&target.curve, Smoothing::Auto, 0.01).unwrap();
            let sparse = target.name.starts_with("CAD");
            assert_eq!(
                input.interpolated.is_some(),
                sparse,
                "{}: {input:?}",
                target.name
            );
            assert_eq!(
                input.smoothing_mm > 0.0,
                noisy,
                "{}: {input:?}",
                target.name
            );
        }
    }
}
