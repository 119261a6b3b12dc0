//! Gaussian smoothing along arc length, for noisy hand-drawn or digitised curves.

use super::{Curve, CurveError, Point};

impl Curve {
    /// Convolves the points with a Gaussian of standard deviation `sigma_mm` in
    /// arc length. Near the ends the curve is extended by point reflection
    /// (`p ↦ 2 p_end − p`), which keeps the end points and end tangents
    /// unbiased. `sigma_mm = 0` returns the curve unchanged.
    ///
    /// A circle of curvature κ shrinks by the factor exp(−κ²σ²/2), so σ well
    /// below the smallest radius of interest is safe: σ = 1 mm on a 20 mm radius
    /// changes κ by 0.1 %. For hand-drawn input, σ of about ten point spacings
    /// removes jitter: on a 20 mm-radius helix with ±1 % noise at 0.7 mm spacing,
    /// σ = 6 mm takes the median κ error from 2500 % to 2.5 % (a test pins it). The reference curves (≥ 4 mm spacing) are unchanged to
    /// rounding at σ = 1 mm.
    pub fn smoothed(&self, sigma_mm: f64) -> Result<Curve, CurveError> {
        if !(sigma_mm.is_finite() && sigma_mm >= 0.0) {
            return Err(CurveError::InvalidSmoothing(sigma_mm));
        }
        if sigma_mm == 0.0 {
            return Ok(self.clone());
        }
        let s = self.arc_length();
        let p = self.points();
        let length = self.length();
        let reach = 4.0 * sigma_mm;
        let first = p[0];
        let last = p[p.len() - 1];
        let mut smoothed = Vec::with_capacity(p.len());
        for (i, &si) in s.iter().enumerate() {
            if i == 0 || i == p.len() - 1 {
                smoothed.push(p[i]);
                continue;
            }
            let mut sum = Point::zeros();
            let mut weight_sum = 0.0;
            let lo = s.partition_point(|&x| x < si - reach);
            let hi = s.partition_point(|&x| x <= si + reach);
            for j in lo..hi {
                let cell = cell_length(s, j);
                let mut add = |sj: f64, pj: Point| {
                    let w = (-(sj - si).powi(2) / (2.0 * sigma_mm * sigma_mm)).exp() * cell;
                    sum += w * pj;
                    weight_sum += w;
                };
                add(s[j], p[j]);
                // Reflected images beyond either end.
                if s[j] > 0.0 && si + s[j] <= reach {
                    add(-s[j], 2.0 * first - p[j]);
                }
                if s[j] < length && 2.0 * length - s[j] - si <= reach {
                    add(2.0 * length - s[j], 2.0 * last - p[j]);
                }
            }
            smoothed.push(sum / weight_sum);
        }
        Curve::from_points(smoothed)
    }
}

/// Length of the arc-length cell a sample stands for (half to each neighbour).
fn cell_length(s: &[f64], j: usize) -> f64 {
    let left = if j > 0 { s[j] - s[j - 1] } else { 0.0 };
    let right = if j + 1 < s.len() {
        s[j + 1] - s[j]
    } else {
        0.0
    };
    0.5 * (left + right)
}
