//! How the reach stage measures a curve's bend, targets and the table's
//! centrelines alike: smoothed over a quarter of the bend window, analysed,
//! and its bend per length averaged over windows of that length.

use super::helix::window;
use crate::curve::{Analysis, AnalysisOptions, Curve, analyse};

/// The most samples analysed.
const MAX_SAMPLES: usize = 8000;

/// A curve analysed as the verdict judges it, targets and the table's
/// centrelines alike: smoothed along its own arc length over a quarter of
/// the bend window first (drawing noise makes the raw polyline longer than
/// the curve it samples), then analysed as it is (the analysis takes
/// uneven spacing), or resampled and smoothed by a spacing when it has too
/// many samples (linear interpolation between samples adds kinks of its
/// own).
pub fn analysed(curve: &Curve, bend_mm: f64) -> Analysis {
    let smooth = curve
        .smoothed(0.25 * bend_mm)
        .unwrap_or_else(|_| curve.clone());
    analysed_from(smooth)
}

/// [`analysed`] for a curve whose points are already smooth (the table's FE
/// centrelines): the same Gaussian, once along the polyline's own arc
/// length: a centreline has no noise to rescale its arc length for.
pub fn analysed_smooth(curve: &Curve, bend_mm: f64) -> Analysis {
    let smooth = curve
        .convolved(0.25 * bend_mm)
        .unwrap_or_else(|_| curve.clone());
    analysed_from(smooth)
}

fn analysed_from(smooth: Curve) -> Analysis {
    let fine = match smooth.len() > MAX_SAMPLES {
        false => smooth,
        true => {
            let spacing = smooth.length() / MAX_SAMPLES as f64;
            let even = smooth.resample(MAX_SAMPLES).unwrap_or(smooth);
            even.convolved(spacing).unwrap_or(even)
        }
    };
    analyse(&fine, &AnalysisOptions::default())
}

/// The bend per length κ̄ = ∫κ ds / w over the window of `bend_mm` centred
/// on each sample.
pub fn bends(analysis: &Analysis, bend_mm: f64) -> Vec<f64> {
    let s = &analysis.s;
    let bend = Prefix::new(s, &analysis.curvature);
    s.iter()
        .map(|&at| {
            let (width, turned) = bend.around(at, bend_mm);
            turned / width
        })
        .collect()
}

/// Prefix integrals (trapezoid) of a profile over arc length.
struct Prefix<'a> {
    s: &'a [f64],
    sum: Vec<f64>,
}

impl<'a> Prefix<'a> {
    fn new(s: &'a [f64], values: &[f64]) -> Prefix<'a> {
        let mut sum = vec![0.0; s.len()];
        for i in 1..s.len() {
            sum[i] = sum[i - 1] + 0.5 * (s[i] - s[i - 1]) * (values[i] + values[i - 1]);
        }
        Prefix { s, sum }
    }

    /// The window of `length` around `at`: its length and the integral
    /// over it.
    fn around(&self, at: f64, length: f64) -> (f64, f64) {
        let (a, b) = window(self.s, at, length);
        (
            (self.s[b] - self.s[a]).max(f64::EPSILON),
            self.sum[b] - self.sum[a],
        )
    }
}
