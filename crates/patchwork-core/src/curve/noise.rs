//! How noisy a drawn curve is, and how much smoothing that calls for.
//!
//! **Estimate.** At each interior sample a cubic fitted to its seven nearest
//! samples (by index; Savitzky–Golay weights [−2, 3, 6, 7, 6, 3, −2]/21)
//! predicts the sample; a smooth curve leaves a residual of order h⁴, white
//! noise of standard deviation σₙ one of variance σₙ²(1 − 7/21). Only the
//! residual across the local chord counts (uneven spacing along a smooth
//! curve moves samples along it), so its two components make a Rayleigh
//! variable with median σₙ √(2/3) √(2 ln 2): σₙ is the median residual over
//! that, robust to a few outliers and to corners.
//!
//! **Noise or geometry.** A curve sampled coarsely (points 10 mm apart
//! round a 25 mm radius) leaves a geometric residual as large as noise of a
//! few tenths of a millimetre. The same fit over every second sample
//! (stride 2) leaves the same noise residual but a larger geometric one:
//! 2⁴ = 16 times it where the curve is smooth on the stencil's scale, 2³
//! across a jump in curvature, and less where the stencil spans a bend
//! (4.5–18 times on simulated balloons sampled 10 mm apart). With r₁, r₂
//! the two estimates, the parts adding in quadrature and the geometric
//! gain taken as its lower bound G = 4 (a residual growing at least as the
//! spacing squared is geometry), r₁² = g² + n², r₂² ≥ G² g² + n², so
//! n² = (G² r₁² − r₂²) / (G² − 1), clamped at zero: exact for noise alone,
//! zero for geometry alone, and an underestimate of the noise when both are
//! there (a coarse curve is smoothed less, never more, than its noise asks).
//!
//! **Smoothing.** A Gaussian of σ along arc length leaves, of white noise of
//! σₙ at spacing Δ, a curvature noise of standard deviation
//! σₙ √(3Δ / (8√π)) σ^(−5/2) (the variance of the kernel's second derivative
//! against the noise). The smoothing is the σ at which that is `curvature_noise`.

use super::{Curve, Point};

/// Savitzky–Golay weights of a cubic over seven samples, at the centre.
const CUBIC_7: [f64; 7] = [-2.0, 3.0, 6.0, 7.0, 6.0, 3.0, -2.0];

/// The least a curve's own residual grows from stride 1 to stride 2.
const GEOMETRIC_GAIN: f64 = 4.0;

/// Median of a Rayleigh variable over its scale: √(2 ln 2).
const RAYLEIGH_MEDIAN: f64 = 1.177_410_022_515_474_6;

impl Curve {
    /// The standard deviation of independent noise on each coordinate of
    /// the samples (mm), estimated from the samples alone; 0 for fewer than
    /// fourteen samples, where noise cannot be told from the curve's bends.
    pub fn noise_estimate(&self) -> f64 {
        let (Some(fine), Some(coarse)) = (self.residual_scale(1), self.residual_scale(2)) else {
            return 0.0;
        };
        let gain = GEOMETRIC_GAIN * GEOMETRIC_GAIN;
        ((gain * fine * fine - coarse * coarse) / (gain - 1.0))
            .max(0.0)
            .sqrt()
    }

    /// The noise the seven-sample cubic over every `stride`-th sample
    /// reads, if the residuals were all noise (mm); none when the curve has
    /// too few samples for the stencil.
    pub(crate) fn residual_scale(&self, stride: usize) -> Option<f64> {
        let p = self.points();
        let reach = 3 * stride;
        if p.len() < 2 * reach + 2 {
            return None;
        }
        let mut residuals: Vec<f64> = (reach..p.len() - reach)
            .map(|i| {
                let fit: Point = (0..7)
                    .map(|j| CUBIC_7[j] * p[i + j * stride - reach])
                    .sum::<Point>()
                    / 21.0;
                let residual = p[i] - fit;
                let chord = p[i + stride] - p[i - stride];
                let along = match chord.norm() > 0.0 {
                    true => residual.dot(&chord) / chord.norm_squared() * chord,
                    false => Point::zeros(),
                };
                (residual - along).norm()
            })
            .collect();
        let mid = residuals.len() / 2;
        let median = *residuals
            .select_nth_unstable_by(mid, |a, b| a.total_cmp(b))
            .1;
        Some(median / (RAYLEIGH_MEDIAN * (2.0f64 / 3.0).sqrt()))
    }

    /// The Gaussian σ (mm) that brings noise of `noise_mm` on these samples
    /// down to a curvature noise of `curvature_noise` (mm⁻¹).
    pub fn smoothing_for(&self, noise_mm: f64, curvature_noise: f64) -> f64 {
        let spacing = self.length() / (self.len().max(2) - 1) as f64;
        let scale = noise_mm * (3.0 * spacing / (8.0 * std::f64::consts::PI.sqrt())).sqrt();
        (scale / curvature_noise).powf(0.4)
    }
}

#[cfg(test)]
#[path = "noise_tests.rs"]
mod tests;
