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
