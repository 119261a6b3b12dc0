use crate::curve::presets::Preset;
use crate::curve::{AnalysisOptions, Curve, analyse};

fn helix() -> Curve {
    Preset::helix(20.0, 40.0, 2.0).generate(400).unwrap()
}

#[test]
fn a_smooth_curve_has_no_noise_worth_smoothing() {
    let noise = helix().noise_estimate();
    assert!(noise < 1e-4, "{noise}");
}

#[test]
fn the_estimate_finds_the_noise_added() {
    // 400 samples 0.65 mm apart; noise of 0.05, 0.3 and 1 mm per coordinate.
    let clean = helix();
    for sigma in [0.05, 0.3, 1.0] {
        let noisy = clean.with_noise(sigma / clean.length(), 3).unwrap();
        let found = noisy.noise_estimate();
        assert!((found / sigma - 1.0).abs() < 0.15, "{sigma}: {found}");
    }
}

#[test]
fn the_smoothing_chosen_brings_curvature_noise_down_to_what_was_asked() {
    // κ of the helix is 20 / (20² + (40/2π)²) = 0.0454 mm⁻¹.
    let clean = helix();
    let noisy = clean.with_noise(0.3 / clean.length(), 5).unwrap();
    let sigma = noisy.smoothing_for(noisy.noise_estimate(), 0.002);
    let smooth = noisy.smoothed(sigma).unwrap();
    let kappa = analyse(&smooth, &AnalysisOptions::default()).curvature;
    let inner = &kappa[40..360];
    let mean = inner.iter().sum::<f64>() / inner.len() as f64;
    let sd = (inner.iter().map(|k| (k - mean).powi(2)).sum::<f64>() / inner.len() as f64).sqrt();
    // Smoothing a helix along its arc draws it in, which raises κ by a few
    // per cent; the noise left is what was asked for (the formula is for
    // white noise on an even spacing).
    assert!(sigma > 1.0 && sigma < 8.0, "{sigma}");
    assert!((mean - 0.0454).abs() < 0.0454 * 0.05, "{mean}");
    assert!(sd < 0.003, "{sd}");
}

/// A helix of radius 25 mm sampled 10 mm apart: the cubic's residual there
/// is geometry (of the order of noise of a few tenths of a millimetre).
fn coarse_helix() -> Curve {
    Preset::helix(25.0, 60.0, 4.0).generate(72).unwrap()
}

#[test]
fn a_coarsely_sampled_curve_is_not_read_as_noisy() {
    let helix = coarse_helix();
    let spacing = helix.length() / 71.0;
    assert!(spacing > 9.0, "{spacing}");
    assert!(helix.residual_scale(1).unwrap() > 0.1);
    let noise = helix.noise_estimate();
    assert!(noise < 0.01, "{noise}");
}

#[test]
fn noise_on_a_coarser_curve_is_found_and_never_overestimated() {
    // 150 samples 4.5 mm apart: the bends leave a residual of 0.01 mm, and
    // noise of 0.3 mm is found; at 72 samples 9.5 mm apart the bends
    // dominate and the noise is underestimated (smoothed less), not more.
    let clean = Preset::helix(25.0, 60.0, 4.0).generate(150).unwrap();
    let noisy = clean.with_noise(0.3 / clean.length(), 3).unwrap();
    let found = noisy.noise_estimate();
    assert!((found / 0.3 - 1.0).abs() < 0.15, "{found}");
    let clean = coarse_helix();
    for sigma in [0.1, 0.5, 2.0] {
        let found = clean
            .with_noise(sigma / clean.length(), 3)
            .unwrap()
            .noise_estimate();
        assert!(found < sigma * 1.15, "{sigma}: {found}");
    }
}

#[test]
fn too_few_samples_to_tell_noise_from_bends_read_as_none() {
    let short = Preset::helix(20.0, 40.0, 1.0).generate(13).unwrap();
    assert_eq!(short.noise_estimate(), 0.0);
}
