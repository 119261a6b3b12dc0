//! How the target preparation treats hand-drawn strokes (`seeded_stroke`:
//! cubic splines through eight seeded random points, 350 samples, 540–870 mm)
//! with 0.3–3 mm of seeded noise per coordinate, prepared as a design
//! prepares them (automatic smoothing) and compared with their clean curves
//! (shape error, % of length). "inflation" is how much longer the noisy
//! polyline is than its smoothing: what the smoothing's arc-length scale
//! corrects (`Curve::smoothed`).
//!
//! cargo run --release -p patchwork-core --example stroke_smoothing

use patchwork_core::curve::{seeded_stroke, shape_error};
use patchwork_core::inverse::input::{Smoothing, prepare};

fn main() {
    println!(
        "| noise mm | seed | clean mm | given mm | inflation | σ mm | prepared vs clean % | smallest, largest spacing mm |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for noise in [0.3, 1.0, 2.0, 3.0] {
        for seed in 1..=8u64 {
            let clean = seeded_stroke(seed, 350).unwrap();
            let noisy = clean.with_noise(noise / clean.length(), seed).unwrap();
            let (prepared, report) = prepare(&noisy, Smoothing::Auto, 0.01).unwrap();
            let error = shape_error(&prepared, &clean, 200).unwrap();
            let spacing: Vec<f64> = prepared
                .points()
                .windows(2)
                .map(|w| (w[1] - w[0]).norm())
                .collect();
            let (least, most) = spacing
                .iter()
                .fold((f64::MAX, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
            let inflation = noisy.length() / noisy.convolved(report.smoothing_mm).unwrap().length();
            println!(
                "| {noise} | {seed} | {:.1} | {:.1} | {inflation:.2} | {:.2} | {:.2} | {least:.3}, {most:.2} |",
                clean.length(),
                noisy.length(),
                report.smoothing_mm,
                error.percent_of_length
            );
        }
    }
}
