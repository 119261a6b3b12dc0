//! Closed-form and property tests of the curve geometry.

use nalgebra::{Rotation3, Vector3};
use patchwork_core::curve::presets::{HelixParams, LineParams, TrefoilParams};
use patchwork_core::curve::{
    AnalysisOptions, Curve, Point, Preset, ReferenceCurve, analyse, bishop_frames, dtw,
    frenet_frames, interpolate, seeded_stroke, shape_error,
};
use patchwork_core::inverse::input::Smoothing;
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use std::f64::consts::PI;

fn helix_closed_form(a: f64, pitch: f64) -> (f64, f64) {
    let b = pitch / std::f64::consts::TAU;
    (a / (a * a + b * b), b / (a * a + b * b))
}

/// Tolerance stated by the issue: κ and τ within 0.5 % at 200 samples, at every
/// sample including the ends.
#[test]
fn helix_curvature_and_torsion_match_closed_form() {
    for (a, pitch, turns) in [
        (20.0, 60.0, 4.0),
        (5.0, 3.0, 2.0),
        (30.0, -40.0, 1.5),
        (10.0, 200.0, 3.0),
    ] {
        let curve = Preset::helix(a, pitch, turns).generate(200).unwrap();
        let analysis = analyse(&curve, &AnalysisOptions::default());
        let (kappa, tau) = helix_closed_form(a, pitch);
        for i in 0..analysis.len() {
            let ek = (analysis.curvature[i] - kappa).abs() / kappa;
            let et = (analysis.torsion[i] - tau).abs() / tau.abs();
            assert!(
                ek < 5e-3,
                "helix a={a} p={pitch}: κ[{i}] off by {:.3} %",
                100.0 * ek
            );
            assert!(
                et < 5e-3,
                "helix a={a} p={pitch}: τ[{i}] off by {:.3} %",
                100.0 * et
            );
            assert!(analysis.torsion_defined[i]);
        }
    }
}

#[test]
fn straight_line_has_zero_curvature_and_flagged_torsion() {
    let line = Preset::Line(LineParams { length_mm: 250.0 })
        .generate(100)
        .unwrap();
    let moved = line.transformed(
        &Rotation3::from_euler_angles(0.4, 0.2, -1.3),
        &Point::new(3.0, 4.0, 5.0),
    );
    let analysis = analyse(&moved, &AnalysisOptions::default());
    for i in 0..analysis.len() {
        assert!(analysis.curvature[i] < 1e-9);
        assert_eq!(analysis.torsion[i], 0.0);
        assert!(!analysis.torsion_defined[i]);
        assert!(analysis.torsion[i].is_finite());
    }
    let frames = frenet_frames(&analysis);
    assert!(analysis.torsion_defined.iter().all(|d| !d));
    for f in frames {
        assert_orthonormal(f.tangent, f.first, f.second);
    }
}

#[test]
fn planar_curve_has_zero_torsion() {
    let arc = Preset::from_name(
        "arc",
        serde_json::json!({"radius_mm": 50, "angle_deg": 270}),
    )
    .unwrap()
    .generate(300)
    .unwrap();
    let analysis = analyse(&arc, &AnalysisOptions::default());
    for i in 0..analysis.len() {
        assert!((analysis.curvature[i] - 0.02).abs() < 1e-4);
        assert!(analysis.torsion[i].abs() < 1e-9);
    }
}

#[test]
fn smoothing_removes_noise_and_leaves_reference_curves_alone() {
    let clean = Preset::helix(20.0, 60.0, 3.0).generate(600).unwrap();
    // Deterministic pseudo-noise, ±0.2 mm (1 % of the radius), 0.7 mm spacing.
    let noisy: Vec<Point> = clean
        .points()
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let h = |k: f64| ((i as f64 * 12.9898 + k * 78.233).sin() * 43758.5453).fract() - 0.5;
            p + 0.4 * Vector3::new(h(1.0), h(2.0), h(3.0))
        })
        .collect();
    let noisy = Curve::from_points(noisy).unwrap();
    let (kappa, _) = helix_closed_form(20.0, 60.0);
    let median_error = |c: &Curve| {
        let a = analyse(c, &AnalysisOptions::default());
        let mut e: Vec<f64> = a
            .curvature
            .iter()
            .map(|k| (k - kappa).abs() / kappa)
            .collect();
        e.sort_by(f64::total_cmp);
        e[e.len() / 2]
    };
    // Measured: σ = 6 mm (≈ 9 spacings) gives 2.5 %; bias exp(−κ²σ²/2) is 3.7 %.
    let smoothed = noisy.smoothed(6.0).unwrap();
    let (before, after) = (median_error(&noisy), median_error(&smoothed));
    assert!(before > 0.5, "noise should swamp κ: {before}");
    assert!(after < 0.05 && after < before / 10.0, "{before} → {after}");

    for reference in ReferenceCurve::ALL {
        let c = reference.curve();
        let s = c.smoothed(1.0).unwrap();
        let moved = c.largest_gap(&s);
        assert!(moved < 0.05, "{reference:?} moved {moved} mm");
    }
    assert!(c_err(noisy.smoothed(-1.0)));
    assert!(c_err(noisy.smoothed(f64::NAN)));
}

/// Noise larger than the point spacing (a 140° arc of radius 60 mm, 300
/// points 0.5 mm apart, seeded Gaussian noise of 1.5 mm per coordinate, as
/// the bench's hand-drawn-style curve) makes the polyline about seven times
/// longer than the arc. Smoothing along *that* arc length would see a kernel
/// of σ = 5 mm span under two points and smooth almost nothing: it used to
/// leave a curve 238 mm long with κ up to 0.6 mm⁻¹, forty times the arc's.
/// Smoothing along that arc length scaled to the smoothed curve's length
/// (the scale found as a fixed point) leaves the arc. Measured: length
/// 142.8 mm for 146.6 (the noisy end points are kept), median κ error 33 %.
#[test]
fn smoothing_holds_when_the_noise_exceeds_the_point_spacing() {
    let arc = Preset::from_name(
        "arc",
        serde_json::json!({"radius_mm": 60, "angle_deg": 140}),
    )
    .unwrap()
    .curve(Some(300))
    .unwrap();
    let noisy = arc.with_noise(0.01, 7).unwrap();
    assert!(noisy.length() > 5.0 * arc.length(), "{}", noisy.length());
    let smoothed = noisy.smoothed(10.0 * arc.length() / 300.0).unwrap();
    let kappa = 1.0 / 60.0;
    let mut errors: Vec<f64> = analyse(&smoothed, &AnalysisOptions::default())
        .curvature
        .iter()
        .map(|k| (k - kappa).abs() / kappa)
        .collect();
    errors.sort_by(f64::total_cmp);
    let median = errors[errors.len() / 2];
    println!(
        "length {:.1} mm for {:.1}; median κ error {:.1} %",
        smoothed.length(),
        arc.length(),
        100.0 * median
    );
    assert!((smoothed.length() / arc.length() - 1.0).abs() < 0.05);
    assert!(median < 0.35, "median κ error {median}");
}

fn c_err<T>(r: Result<T, patchwork_core::CurveError>) -> bool {
    r.is_err()
}

fn assert_orthonormal(t: Point, u: Point, v: Point) {
    for (a, b, expected) in [
        (t, t, 1.0),
        (u, u, 1.0),
        (v, v, 1.0),
        (t, u, 0.0),
        (t, v, 0.0),
        (u, v, 0.0),
    ] {
        assert!((a.dot(&b) - expected).abs() < 1e-9, "frame not orthonormal");
    }
    assert!((u.cross(&v) - t).norm() < 1e-9, "frame not right-handed");
}

fn random_rotation() -> impl Strategy<Value = Rotation3<f64>> {
    (-PI..PI, -1.5f64..1.5, -PI..PI).prop_map(|(r, p, y)| Rotation3::from_euler_angles(r, p, y))
}

fn random_curve() -> impl Strategy<Value = Curve> {
    prop_oneof![
        (2.0f64..40.0, -80.0f64..80.0, 0.5f64..4.0, 50usize..400).prop_map(|(a, p, t, n)| {
            let pitch = if p.abs() < 1.0 { 1.0 } else { p };
            Preset::Helix(HelixParams {
                radius_mm: a,
                pitch_mm: pitch,
                turns: t,
            })
            .generate(n)
            .unwrap()
        }),
        (5.0f64..60.0, 100usize..500).prop_map(|(k, n)| {
            Preset::Trefoil(TrefoilParams { scale_mm: k })
                .generate(n)
                .unwrap()
        }),
    ]
}

proptest! {
    // A fixed seed: every run draws the same cases, so a failure reproduces.
    #![proptest_config(ProptestConfig {
        rng_seed: RngSeed::Fixed(0x5EED_C0DE),
        failure_persistence: None,
        ..ProptestConfig::with_cases(64)
    })]

    #[test]
    fn frames_are_orthonormal(curve in random_curve(), rotation in random_rotation()) {
        let curve = curve.transformed(&rotation, &Point::new(1.0, -2.0, 3.0));
        let analysis = analyse(&curve, &AnalysisOptions::default());
        let frenet = frenet_frames(&analysis);
        for f in frenet.iter().chain(&bishop_frames(&analysis)) {
            assert_orthonormal(f.tangent, f.first, f.second);
        }
    }

    #[test]
    fn curvature_and_torsion_are_invariant_under_rigid_motion(
        curve in random_curve(),
        rotation in random_rotation(),
        shift in (-500.0f64..500.0, -500.0f64..500.0, -500.0f64..500.0),
    ) {
        let moved = curve.transformed(&rotation, &Point::new(shift.0, shift.1, shift.2));
        let a = analyse(&curve, &AnalysisOptions::default());
        let b = analyse(&moved, &AnalysisOptions::default());
        for i in 0..a.len() {
            prop_assert!((a.curvature[i] - b.curvature[i]).abs() <= 1e-7 * (1.0 + a.curvature[i].abs()));
            prop_assert!((a.torsion[i] - b.torsion[i]).abs() <= 1e-6 * (1.0 + a.torsion[i].abs()));
        }
    }

    #[test]
    fn curvature_and_torsion_are_invariant_under_resampling(
        scale in 20.0f64..60.0, n in 300usize..600, m in 300usize..600,
    ) {
        // The same trefoil sampled at n and at m points gives the same κ(s), τ(s).
        let trefoil = Preset::Trefoil(TrefoilParams { scale_mm: scale });
        let a = analyse(&trefoil.generate(n).unwrap(), &AnalysisOptions::default());
        let b = analyse(&trefoil.generate(m).unwrap(), &AnalysisOptions::default());
        let kappa_scale = a.curvature.iter().fold(0.0f64, |x, &y| x.max(y));
        let tau_scale = a.torsion.iter().fold(0.0f64, |x, &y| x.max(y.abs()));
        for i in 0..b.len() {
            let s = b.s[i] / b.length() * a.length();
            prop_assert!((interpolate(&a.s, &a.curvature, s) - b.curvature[i]).abs() < 0.01 * kappa_scale);
            prop_assert!((interpolate(&a.s, &a.torsion, s) - b.torsion[i]).abs() < 0.02 * tau_scale);
        }
    }

    #[test]
    fn polyline_resampling_keeps_curvature(a in 10.0f64..40.0, pitch in 20.0f64..120.0, n in 150usize..400) {
        // Resampling a dense polyline puts samples on chords (sag h²κ/8); the
        // one-sided end stencils amplify that sag most. From 8 000 points the
        // sag (3e-6 mm) reached 1.1 % at the ends (a = 10, pitch 20, n = 373); from
        // 40 000 it is 25× smaller and κ stays within 1 % everywhere.
        let dense = Preset::helix(a, pitch, 2.0).generate(40_000).unwrap();
        let analysis = analyse(&dense.resample(n).unwrap(), &AnalysisOptions::default());
        let (kappa, _) = helix_closed_form(a, pitch);
        for k in &analysis.curvature {
            prop_assert!((k - kappa).abs() / kappa < 0.01);
        }
    }

    #[test]
    fn dtw_of_itself_is_zero_and_dtw_is_symmetric(
        a in prop::collection::vec(-10.0f64..10.0, 1..60),
        b in prop::collection::vec(-10.0f64..10.0, 1..60),
        window in prop::option::of(0usize..20),
    ) {
        prop_assert_eq!(dtw(&a, &a, window), Some(0.0));
        let ab = dtw(&a, &b, window).unwrap();
        let ba = dtw(&b, &a, window).unwrap();
        prop_assert!((ab - ba).abs() <= 1e-9 * (1.0 + ab));
        prop_assert!(ab >= 0.0);
    }
}

/// The case a random proptest seed once found (a = 10, pitch 20, n = 373): a
/// tight helix where end-stencil amplification of chord sag is largest.
#[test]
fn polyline_resampling_regression_tight_helix() {
    let dense = Preset::helix(10.0, 20.0, 2.0).generate(40_000).unwrap();
    let analysis = analyse(&dense.resample(373).unwrap(), &AnalysisOptions::default());
    let (kappa, _) = helix_closed_form(10.0, 20.0);
    let worst = analysis
        .curvature
        .iter()
        .map(|k| (k - kappa).abs() / kappa)
        .fold(0.0, f64::max);
    assert!(worst < 0.01, "worst κ error {:.3} %", 100.0 * worst);
}

/// Hand-drawn strokes: cubic splines through eight seeded random points
/// (350 samples, 540–870 mm) with 0.3 and 1 mm of seeded noise, prepared
/// for a design as users' curves are, stay within 0.4 % of their length of
/// the clean strokes (measured: worst 0.12 % and 0.18 %;
/// `examples/stroke_smoothing.rs` prints every stroke). Smoothing along each
/// point's smoothed arc length, repeated to a fixed point, left them up to
/// 1.5 and 3.7 % away, points collapsed in pairs and corners cut.
#[test]
fn noisy_strokes_are_prepared_close_to_their_clean_curves() {
    for noise in [0.3, 1.0] {
        for seed in 1..=8u64 {
            let clean = seeded_stroke(seed, 350).unwrap();
            let noisy = clean.with_noise(noise / clean.length(), seed).unwrap();
            let (prepared, report) =
                patchwork_core::inverse::input::prepare(&noisy, Smoothing::Auto, 0.01).unwrap();
            assert!(report.smoothing_mm > 0.0, "{report:?}");
            let error = shape_error(&prepared, &clean, 200)
                .unwrap()
                .percent_of_length;
            let gap = prepared
                .points()
                .windows(2)
                .map(|w| (w[1] - w[0]).norm())
                .fold(0.0, f64::max);
            assert!(
                error < 0.4 && gap < 15.0,
                "noise {noise} mm, seed {seed}: {error} % from the clean stroke, largest gap {gap} mm"
            );
        }
    }
}
