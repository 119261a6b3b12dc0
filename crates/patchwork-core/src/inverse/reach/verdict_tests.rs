use super::*;
use crate::curve::Point;
use crate::curve::presets::{ArcParams, Preset};
use crate::inverse::input::{Smoothing, prepare};
use crate::inverse::reach::PatchResponse;

const LENGTHS: WindowLengths = WindowLengths {
    bend_mm: 10.0,
    twist_mm: 30.0,
};

/// A table of one width whose tightest bend is a 25 mm radius (no twist),
/// and whose most twist per bend is 1 (at a 40 mm radius of curvature).
fn table() -> ReachTable {
    let entry = |theta: f64, k: f64, t: f64| PatchResponse {
        width_mm: 3.0,
        theta_deg: theta,
        curvature_per_mm: k,
        torsion_per_mm: t,
        peak_curvature_per_mm: k,
    };
    ReachTable {
        patch_length_mm: 30.0,
        entries: vec![entry(0.0, 0.04, 0.0), entry(30.0, 0.025, -0.025)],
    }
}

fn arc(radius: f64, angle: f64) -> Curve {
    Preset::Arc(ArcParams {
        radius_mm: radius,
        angle_deg: angle,
    })
    .generate(400)
    .unwrap()
}

#[test]
fn the_envelope_is_what_the_angles_make_and_less_in_proportion() {
    let envelope = Envelope::new(&table());
    assert_eq!(envelope.curvature_at(0.0), Some(0.04));
    // Between the entries the path is (0.04 − 0.015 s, 0.025 s): at q = 0.2,
    // κ = τ/q where s = 0.04 / (0.125 + 0.015).
    let s = 0.04 / 0.14;
    let expected = 0.04 - 0.015 * s;
    assert!((envelope.curvature_at(0.2).unwrap() - expected).abs() < 1e-12);
    // At the steepest entry's twist per bend, its bend; beyond, nothing.
    assert!((envelope.curvature_at(1.0).unwrap() - 0.025).abs() < 1e-12);
    assert_eq!(envelope.curvature_at(2.0), None);
    assert_eq!(envelope.most_twist(), 1.0);
    let untwisted = Envelope {
        paths: vec![vec![(0.04, 0.0)]],
    };
    assert_eq!(untwisted.curvature_at(0.1), None);
}

#[test]
fn an_arc_within_the_tightest_bend_is_reachable() {
    let report = judge(&arc(40.0, 180.0), table(), LENGTHS, 0.01);
    assert!(report.reachable(), "{:?}", report.out_of_reach);
    assert!((report.tightest_bend_radius_mm - 25.0).abs() < 1e-9);
    assert!((report.most_twist_per_bend - 1.0).abs() < 1e-9);
}

#[test]
fn a_tighter_arc_is_out_of_reach_over_its_whole_length_with_its_radius() {
    let curve = arc(15.0, 180.0);
    let report = judge(&curve, table(), LENGTHS, 0.01);
    assert_eq!(report.out_of_reach.len(), 1, "{:?}", report.out_of_reach);
    let span = &report.out_of_reach[0];
    assert!(span.s_start_mm < 1.0 && span.s_end_mm > curve.length() - 1.0);
    // Smoothing shrinks κ by exp(−κ²σ²/2) ≈ 0.986 at σ = 2.5 mm.
    assert!((span.needs_bend_radius_mm - 15.0).abs() < 0.5, "{span:?}");
    let tightest = span.tightest_bend_radius_mm.unwrap();
    assert!((tightest - 25.0).abs() < 1e-9, "{span:?}");
    assert!(
        span.message.contains("bend radius of 15 mm"),
        "{}",
        span.message
    );
}

/// Straight 100 mm, a 90° bend of radius 15 mm, straight 100 mm.
fn line_bend_line() -> Curve {
    let mut points = Vec::new();
    for i in 0..100 {
        points.push(Point::new(0.0, 0.0, i as f64));
    }
    let r = 15.0;
    for i in 0..=47 {
        let a = std::f64::consts::FRAC_PI_2 * i as f64 / 47.0;
        points.push(Point::new(r * (1.0 - a.cos()), 0.0, 100.0 + r * a.sin()));
    }
    for i in 1..=100 {
        points.push(Point::new(r + i as f64, 0.0, 100.0 + r));
    }
    Curve::from_points(points).unwrap()
}

#[test]
fn a_tight_corner_is_reported_where_it_is() {
    let report = judge(&line_bend_line(), table(), LENGTHS, 0.01);
    assert_eq!(report.out_of_reach.len(), 1, "{:?}", report.out_of_reach);
    let span = &report.out_of_reach[0];
    // The bend runs from s = 100 to 100 + 15π/2 ≈ 123.6 mm; windows of 10 mm
    // that overlap it widen the span by at most half a window each side.
    assert!(
        span.s_start_mm > 94.0 && span.s_start_mm < 106.0,
        "{span:?}"
    );
    assert!(span.s_end_mm > 118.0 && span.s_end_mm < 130.0, "{span:?}");
}

#[test]
fn a_helix_twisting_more_per_bend_than_any_patch_is_out_of_reach() {
    // Radius 10, pitch 2π·15: κ = 10/325, τ = 15/325, twist per bend 1.5,
    // beyond the table's 1.
    let helix = Preset::helix(10.0, std::f64::consts::TAU * 15.0, 2.0)
        .generate(400)
        .unwrap();
    let report = judge(&helix, table(), LENGTHS, 0.01);
    assert_eq!(report.out_of_reach.len(), 1, "{:?}", report.out_of_reach);
    let span = &report.out_of_reach[0];
    // The tightest window is near an end, where the fit sees part of a
    // turn: within 10 % of the helix's values.
    assert!((span.needs_twist_per_bend - 1.5).abs() < 0.15, "{span:?}");
    assert!((span.needs_bend_radius_mm - 32.5).abs() < 1.0, "{span:?}");
    assert_eq!(span.tightest_bend_radius_mm, None);
    assert!(
        span.message.contains("the most a patch makes is 1.00"),
        "{}",
        span.message
    );
}

#[test]
fn drawing_noise_smoothed_as_the_run_does_leaves_a_reachable_arc_reachable() {
    // ±0.3 mm of noise on a 126 mm arc (0.24 % of its length).
    let noisy = arc(40.0, 180.0).with_noise(0.3 / 126.0, 7).unwrap();
    let (prepared, _) = prepare(&noisy, Smoothing::Auto, 0.01).unwrap();
    let report = judge(&prepared, table(), LENGTHS, 0.01);
    assert!(report.reachable(), "{:?}", report.out_of_reach);
}
