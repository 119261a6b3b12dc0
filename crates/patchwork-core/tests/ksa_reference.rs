//! KSA against the authors' published segmentation, and its edge cases.

use patchwork_core::curve::presets::{ArcParams, LineParams};
use patchwork_core::curve::{Curve, Point, Preset, ReferenceCurve};
use patchwork_core::design::Patch;
use patchwork_core::ksa::{KsaParams, Stretch, ksa};

/// DESIGN.md: the authors' KSA on `hilbert_curve.csv` (L0 = 292 mm, R0 = 3.18 mm,
/// κ_tol = 0.01 mm⁻¹, merge 20 mm) gives 6 patches with these axial centres and
/// lengths (mm). Tolerance from the issue: 1.5 mm each.
#[test]
fn reproduces_the_authors_hilbert_segmentation() {
    let centres = [43.3, 87.9, 128.2, 163.9, 204.8, 248.8];
    let lengths = [18.4, 17.0, 17.0, 17.0, 18.5, 18.5];
    let result = ksa(&ReferenceCurve::Hilbert.curve(), &KsaParams::default()).unwrap();
    assert!((result.stretch - 899.05 / 292.0).abs() < 1e-3);
    assert_eq!(result.patches.len(), 6);
    for (i, patch) in result.patches.iter().enumerate() {
        assert!(
            (patch.y_mm - centres[i]).abs() < 1.5,
            "patch {i}: Y = {}",
            patch.y_mm
        );
        assert!(
            (patch.h_mm - lengths[i]).abs() < 1.5,
            "patch {i}: H = {}",
            patch.h_mm
        );
        assert_eq!(patch.w_mm, 1.5);
        // The Hilbert curve's corners are planar turns: no twist, no angle.
        assert!(
            patch.theta_deg.abs() < 0.5,
            "patch {i}: Θ = {}",
            patch.theta_deg
        );
    }
    // Corners 1–2 bend in one plane, 3–4 in a plane a quarter turn round the
    // tube, 5–6 back in the first: X = 0, 0, πR0/2, πR0/2, 0, 0.
    let quarter = std::f64::consts::FRAC_PI_2 * 3.18;
    let expected_x = [0.0, 0.0, quarter, quarter, 0.0, 0.0];
    for (patch, x) in result.patches.iter().zip(expected_x) {
        assert!(
            (patch.x_mm - x).abs() < 0.2,
            "X = {} expected {x}",
            patch.x_mm
        );
    }
}

#[test]
fn straight_curve_needs_no_patches() {
    let line = Preset::Line(LineParams { length_mm: 600.0 })
        .generate(300)
        .unwrap();
    let result = ksa(&line, &KsaParams::default()).unwrap();
    assert!(result.patches.is_empty());
    assert!((result.stretch - 600.0 / 292.0).abs() < 1e-12);
}

#[test]
fn every_x_lies_in_the_unrolled_rectangle() {
    let circumference = std::f64::consts::TAU * 3.18;
    for curve in [
        ReferenceCurve::Pancake.curve(),
        ReferenceCurve::Spring.curve(),
        Preset::from_name("trefoil", serde_json::json!({"scale_mm": 60}))
            .unwrap()
            .generate(600)
            .unwrap(),
    ] {
        let result = ksa(&curve, &KsaParams::default()).unwrap();
        assert!(!result.patches.is_empty());
        assert_eq!(result.patches[0].x_mm, 0.0);
        for p in &result.patches {
            assert!((0.0..circumference).contains(&p.x_mm), "X = {}", p.x_mm);
            assert!(p.y_mm - p.h_mm / 2.0 >= -1e-9 && p.y_mm + p.h_mm / 2.0 <= 292.0 + 1e-9);
        }
    }
}

#[test]
fn planar_arc_bends_one_way_with_one_patch() {
    let arc = Preset::Arc(ArcParams {
        radius_mm: 40.0,
        angle_deg: 90.0,
    });
    // Straight lead-in, a 40 mm-radius quarter turn, straight lead-out.
    let mut points: Vec<Point> = (0..50)
        .map(|i| Point::new(-200.0 + 4.0 * i as f64, 0.0, 0.0))
        .collect();
    points.extend(arc.generate(40).unwrap().points().iter().skip(1));
    let end = *points.last().unwrap();
    points.extend((1..50).map(|i| end + Point::new(0.0, 4.0 * i as f64, 0.0)));
    let curve = Curve::from_points(points).unwrap();
    let result = ksa(&curve, &KsaParams::default()).unwrap();
    assert_eq!(result.patches.len(), 1);
    let p = result.patches[0];
    let lambda = result.stretch;
    let arc_length = std::f64::consts::FRAC_PI_2 * 40.0;
    assert!(
        (p.h_mm - arc_length / lambda).abs() < 8.0 / lambda,
        "H = {}",
        p.h_mm
    );
    assert!((p.y_mm - (200.0 + arc_length / 2.0) / lambda).abs() < 4.0 / lambda);
}

#[test]
fn run_at_the_end_is_clipped_to_the_balloon() {
    // At a fixed stretch of 2 the balloon reaches 584 mm of curve. A turn from
    // 556 mm to 619 mm straddles that end and is clipped onto the balloon; the
    // same turn after 800 mm of straight lies wholly beyond it and is dropped.
    let curve_with_turn_after = |straight: usize| {
        let mut points: Vec<Point> = (0..straight)
            .map(|i| Point::new(4.0 * i as f64, 0.0, 0.0))
            .collect();
        let end = *points.last().unwrap();
        let turn = Preset::Arc(ArcParams {
            radius_mm: 30.0,
            angle_deg: 120.0,
        })
        .generate(30)
        .unwrap();
        points.extend(turn.points().iter().skip(1).map(|p| end + p));
        Curve::from_points(points).unwrap()
    };
    let params = KsaParams {
        stretch: Stretch::Fixed(2.0),
        ..KsaParams::default()
    };
    let result = ksa(&curve_with_turn_after(140), &params).unwrap();
    assert_eq!(result.patches.len(), 1);
    assert_eq!(result.clipped, vec![0]);
    let p = result.patches[0];
    assert!((p.y_mm + p.h_mm / 2.0 - 292.0).abs() < 1e-9);
    assert!(p.h_mm > 0.0 && p.y_mm - p.h_mm / 2.0 > 270.0);

    let result = ksa(&curve_with_turn_after(200), &params).unwrap();
    assert!(result.patches.is_empty());
    assert_eq!(result.off_balloon, vec![0]);
}

#[test]
fn twisted_run_gets_an_angle_whose_sign_follows_torsion() {
    let right = Preset::helix(30.0, 80.0, 1.0).generate(200).unwrap();
    let left = Preset::helix(30.0, -80.0, 1.0).generate(200).unwrap();
    let theta = |c: &Curve| ksa(c, &KsaParams::default()).unwrap().patches[0].theta_deg;
    assert!(theta(&right) > 1.0);
    assert!((theta(&right) + theta(&left)).abs() < 1e-6);
}

#[test]
fn invalid_parameters_are_named() {
    let curve = ReferenceCurve::Hilbert.curve();
    for (params, name) in [
        (
            KsaParams {
                l0_mm: -1.0,
                ..KsaParams::default()
            },
            "l0_mm",
        ),
        (
            KsaParams {
                r0_mm: f64::NAN,
                ..KsaParams::default()
            },
            "r0_mm",
        ),
        (
            KsaParams {
                kappa_tol: 0.0,
                ..KsaParams::default()
            },
            "kappa_tol",
        ),
        (
            KsaParams {
                merge_mm: -3.0,
                ..KsaParams::default()
            },
            "merge_mm",
        ),
        (
            KsaParams {
                stretch: Stretch::Fixed(0.0),
                ..KsaParams::default()
            },
            "stretch",
        ),
    ] {
        let err = ksa(&curve, &params).unwrap_err();
        assert_eq!(err.name, name);
    }
}

/// A bend longer than the longest patch becomes a train: on a 180° arc of
/// radius 80 mm KSA's one patch spans the balloon (H ≈ 290 mm); with a
/// 30 mm limit and 2 mm gaps it becomes ⌈(H + 2) / 32⌉ patches, every one
/// within the limit, in order along the balloon, bending the same way (X
/// equal: a planar arc), covering the same span.
#[test]
fn a_long_bend_becomes_a_train_of_patches_within_the_limit() {
    let arc = Preset::Arc(ArcParams {
        radius_mm: 80.0,
        angle_deg: 180.0,
    })
    .generate(400)
    .unwrap();
    let whole = ksa(&arc, &KsaParams::default()).unwrap();
    assert_eq!(whole.patches.len(), 1);
    let single = whole.patches[0];
    assert!(single.h_mm > 250.0, "{single:?}");
    let params = KsaParams {
        max_patch_mm: Some(30.0),
        ..KsaParams::default()
    };
    let train = ksa(&arc, &params).unwrap();
    let patches = &train.patches;
    let expected = ((single.h_mm + 2.0) / 32.0).ceil() as usize;
    assert_eq!(patches.len(), expected, "{patches:?}");
    assert!(patches.iter().all(|p| p.h_mm <= 30.0 && p.h_mm > 25.0));
    for pair in patches.windows(2) {
        let gap = (pair[1].y_mm - pair[1].h_mm / 2.0) - (pair[0].y_mm + pair[0].h_mm / 2.0);
        assert!((2.0..3.5).contains(&gap), "gap {gap} mm");
        assert!((pair[1].x_mm - pair[0].x_mm).abs() < 1e-6);
    }
    // The train covers the span the single patch covered.
    let (first, last) = (patches[0], patches[expected - 1]);
    let start = |p: Patch| p.y_mm - p.h_mm / 2.0;
    let end = |p: Patch| p.y_mm + p.h_mm / 2.0;
    assert!((start(first) - start(single)).abs() < 1e-9);
    assert!((end(last) - end(single)).abs() < 1.5);
    // A limit that is not positive is refused by name.
    let bad = KsaParams {
        max_patch_mm: Some(0.0),
        ..KsaParams::default()
    };
    assert_eq!(ksa(&arc, &bad).unwrap_err().name, "max_patch_mm");
}
