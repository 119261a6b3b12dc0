//! Comparisons whose answers are known: a centreline measured exactly as
//! predicted, one with a bend added under one patch, noise, a wrong unit.

use nalgebra::Rotation3;

use super::*;
use crate::curve::{Curve, Point, Preset, shape_error};
use crate::design::{Design, Patch};

/// 200 mm of balloon (uninflated) with three 20 mm patches along its axis.
fn three_patch_design() -> Design {
    let mut design = Design::reference(
        [50.0, 100.0, 150.0]
            .iter()
            .map(|&y_mm| Patch {
                x_mm: 0.0,
                y_mm,
                h_mm: 20.0,
                w_mm: 3.0,
                theta_deg: 0.0,
            })
            .collect(),
    );
    design.balloon.length_mm = 200.0;
    design
}

/// A planar curve of `length` mm whose curvature at arc length s is
/// `kappa(s)`, sampled at `n` points (tangent angle and position
/// integrated by the midpoint rule on a fine grid).
fn planar(length: f64, n: usize, kappa: impl Fn(f64) -> f64) -> Curve {
    let fine = 20 * n;
    let ds = length / fine as f64;
    let (mut angle, mut p) = (0.0_f64, Point::zeros());
    let mut points = vec![p];
    for k in 0..fine {
        let s = (k as f64 + 0.5) * ds;
        let half = angle + 0.5 * kappa(s) * ds;
        p += Point::new(half.cos(), half.sin(), 0.0) * ds;
        angle += kappa(s) * ds;
        if (k + 1) % 20 == 0 {
            points.push(p);
        }
    }
    Curve::from_points(points).unwrap()
}

/// The predicted centreline: a 300 mm arc of radius 150 mm (inflation
/// stretches the 200 mm balloon by 1.5), 73 rings.
fn prediction() -> Prediction {
    let arc = planar(300.0, 72, |_| 1.0 / 150.0);
    Prediction::new(three_patch_design(), arc.points(), None).unwrap()
}

#[test]
fn a_balloon_built_as_predicted_matches_everywhere_in_either_direction() {
    let prediction = prediction();
    let fine = planar(300.0, 600, |_| 1.0 / 150.0);
    let mut points: Vec<Point> = fine.points().to_vec();
    points.reverse();
    let moved = Curve::from_points(points).unwrap().transformed(
        &Rotation3::from_euler_angles(0.4, -0.9, 2.1),
        &Point::new(30.0, -5.0, 8.0),
    );
    let c = compare(&prediction, &moved).unwrap();
    assert!(c.measured.reversed);
    // The 73-ring polyline is shorter than the arc by its chords' sagitta.
    assert!(
        c.against_prediction.shape_error_mm < 0.05,
        "{:?}",
        c.against_prediction
    );
    assert!(
        c.length_difference_mm.abs() < 0.1,
        "{}",
        c.length_difference_mm
    );
    assert_eq!(c.patches.len(), 3);
    for region in &c.patches {
        assert!(region.local_error_mm < 0.01, "{region:?}");
        // 20 mm of patch inflated to 30 mm of an arc of radius 150 mm:
        // 11.46°.
        let expected = (30.0_f64 / 150.0).to_degrees();
        assert!(
            (region.measured_bend_deg - expected).abs() < 0.3,
            "{region:?}"
        );
        assert!(
            (region.predicted_bend_deg - expected).abs() < 0.3,
            "{region:?}"
        );
        assert!((region.to_fraction - region.from_fraction - 0.1).abs() < 1e-9);
    }
    assert!(c.against_target.is_none() && c.profiles.target_curvature_per_mm.is_empty());
}

#[test]
fn a_bend_added_under_one_patch_is_found_there() {
    let prediction = prediction();
    // P2 covers 135..165 mm of the inflated arc: 10° more bend there.
    let extra = 10.0_f64.to_radians() / 30.0;
    let kappa = |s: f64| {
        1.0 / 150.0
            + if (135.0..165.0).contains(&s) {
                extra
            } else {
                0.0
            }
    };
    let measured = planar(300.0, 600, kappa);
    let c = compare(&prediction, &measured).unwrap();
    assert_eq!(c.most_divergent_patch, Some(2), "{:#?}", c.patches);
    let added: Vec<f64> = c
        .patches
        .iter()
        .map(|r| r.measured_bend_deg - r.predicted_bend_deg)
        .collect();
    // The profiles are smoothed (σ = 1 % of the length, 3 mm): some of the
    // added bend spreads past the stretch's ends.
    assert!((7.0..10.5).contains(&added[1]), "{added:?}");
    assert!(added[0].abs() < 1.0 && added[2].abs() < 1.0, "{added:?}");
    assert!(c.against_prediction.shape_error_mm > 1.0);
}

#[test]
fn noise_is_found_and_smoothed_and_the_shape_error_sees_it() {
    let prediction = prediction();
    // Motion capture's markers: a point every millimetre, 0.2 mm of noise.
    let fine = planar(300.0, 300, |_| 1.0 / 150.0);
    let noisy = fine.with_noise(0.2 / 300.0, 7).unwrap();
    let c = compare(&prediction, &noisy).unwrap();
    assert!(c.measured.input.noise_mm > 0.05, "{:?}", c.measured.input);
    assert!(c.measured.input.smoothing_mm > 0.0);
    assert!(
        c.against_prediction.shape_error_mm < 1.0,
        "{:?}",
        c.against_prediction
    );
    // Noise lengthens the polyline; the smoothed length is the balloon's.
    assert!(c.measured.length_mm > c.measured.smoothed_length_mm);
    assert!(
        c.length_difference_mm.abs() < 1.0,
        "{}",
        c.length_difference_mm
    );
    for region in &c.patches {
        let off = region.measured_bend_deg - region.predicted_bend_deg;
        assert!(off.abs() < 3.0, "{region:?}");
    }
}

#[test]
fn the_target_is_measured_against_as_given() {
    let target = planar(300.0, 300, |_| 1.0 / 140.0);
    let prediction = prediction().with_target(target.clone());
    let measured = planar(300.0, 600, |_| 1.0 / 160.0);
    let c = compare(&prediction, &measured).unwrap();
    let expected = shape_error(&measured, &target, 200).unwrap();
    let got = c.against_target.unwrap();
    assert!((got.shape_error_mm - expected.rms_mm).abs() < 1e-9 * expected.rms_mm);
    assert!(c.prediction_against_target.unwrap().shape_error_mm > 0.1);
    assert_eq!(c.profiles.target_curvature_per_mm.len(), PROFILE_SAMPLES);
}

#[test]
fn a_measurement_in_the_wrong_units_is_refused_naming_both_lengths() {
    let prediction = prediction();
    let in_metres = planar(0.3, 100, |_| 150.0);
    let error = compare(&prediction, &in_metres).unwrap_err();
    assert!(matches!(error, CompareError::Length { .. }));
    let text = error.to_string();
    assert!(text.contains("0.3 mm") && text.contains("300.0 mm") && text.contains("units"));
}

#[test]
fn design_json_without_a_centreline_is_refused_naming_the_field() {
    let design = serde_json::to_string(&three_patch_design()).unwrap();
    let error = Prediction::from_design_json(&format!("{{\"design\": {design}}}")).unwrap_err();
    assert!(error.to_string().contains("centreline_mm"), "{error}");
    let short = format!("{{\"design\": {design}, \"centreline_mm\": [[0,0,0],[0,0,1]]}}");
    let error = Prediction::from_design_json(&short).unwrap_err();
    assert!(
        error.to_string().contains("centreline_mm: 2 points"),
        "{error}"
    );
    let error = Prediction::from_design_json("{\"centreline_mm\": []}").unwrap_err();
    assert!(error.to_string().contains("design"), "{error}");
}

#[test]
fn a_helix_bends_and_twists_by_its_curvature_and_torsion_in_every_stretch() {
    // Radius 20 mm, pitch 40 mm: κ = r/(r² + c²), τ = c/(r² + c²), c = p/2π.
    let (r, c) = (20.0, 40.0 / std::f64::consts::TAU);
    let (kappa, tau) = (r / (r * r + c * c), c / (r * r + c * c));
    let helix = |n| Preset::helix(r, 40.0, 2.0).generate(n).unwrap();
    let prediction = Prediction::new(three_patch_design(), helix(73).points(), None).unwrap();
    let measured = helix(400).with_noise(0.1 / 264.0, 3).unwrap();
    let c = compare(&prediction, &measured).unwrap();
    assert!(!c.measured.input.planar);
    for region in &c.patches {
        let stretch = (region.to_fraction - region.from_fraction) * measured.length();
        let (bend, twist) = ((kappa * stretch).to_degrees(), (tau * stretch).to_degrees());
        // The prediction's 73 rings, read through a spline: within 5 %; the
        // noisy measurement, smoothed: κ within 10 %, τ (a third derivative,
        // over 26 mm) within 20 %.
        for (got, expected, tolerance) in [
            (region.predicted_bend_deg, bend, 0.05),
            (region.measured_bend_deg, bend, 0.1),
            (region.predicted_twist_deg, twist, 0.05),
            (region.measured_twist_deg, twist, 0.2),
        ] {
            assert!(
                (got - expected).abs() < tolerance * expected,
                "{got} against {expected}: {region:?}"
            );
        }
        assert!(region.local_error_mm < 0.1, "{region:?}");
    }
}
