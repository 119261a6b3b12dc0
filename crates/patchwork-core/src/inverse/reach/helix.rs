//! The helix that best fits a stretch of a curve: its Darboux vector d
//! (T′ = d × T along a helix, d = τT + κB) by least squares over the
//! stretch's samples, from tangents and curvature vectors alone (no τ, a
//! third derivative):
//!
//! ```text
//! d = (∫ (I − T Tᵀ) ds)⁻¹ ∫ κB ds,   τ = d · T̄,   κ = |d − τ T̄|
//! ```
//!
//! with T̄ the stretch's mean tangent (κB = T × T′). On a helix these are its
//! κ and τ exactly; on a plane curve d ∥ B ⟂ T̄ and τ = 0. Prefix sums make
//! each stretch's fit O(1).

use crate::curve::{Analysis, Point};

/// Prefix sums, over the samples, of the least-squares fit of a helix's
/// Darboux vector: ∫(I − TTᵀ) ds and ∫κB ds, and ∫T ds.
pub struct HelixFit<'a> {
    s: &'a [f64],
    normal: Vec<nalgebra::Matrix3<f64>>,
    rhs: Vec<Point>,
    tangent: Vec<Point>,
}

impl<'a> HelixFit<'a> {
    pub fn new(analysis: &'a Analysis) -> HelixFit<'a> {
        let s = &analysis.s;
        let n = s.len();
        let identity = nalgebra::Matrix3::identity();
        let mut fit = HelixFit {
            s,
            normal: vec![nalgebra::Matrix3::zeros(); n],
            rhs: vec![Point::zeros(); n],
            tangent: vec![Point::zeros(); n],
        };
        for i in 1..n {
            let ds = s[i] - s[i - 1];
            let at = |j: usize| {
                let t = analysis.tangent[j];
                let kb = analysis.curvature[j] * analysis.binormal[j];
                (identity - t * t.transpose(), kb, t)
            };
            let ((m0, b0, t0), (m1, b1, t1)) = (at(i - 1), at(i));
            fit.normal[i] = fit.normal[i - 1] + 0.5 * ds * (m0 + m1);
            fit.rhs[i] = fit.rhs[i - 1] + 0.5 * ds * (b0 + b1);
            fit.tangent[i] = fit.tangent[i - 1] + 0.5 * ds * (t0 + t1);
        }
        fit
    }

    /// τ/κ of the helix fitted to the window of `length` around `at`; 0
    /// where the tangent turns too little to tell.
    pub fn twist_per_bend(&self, at: f64, length: f64) -> f64 {
        let (a, b) = window(self.s, at, length);
        let (bend, twist) = self.between(a, b);
        match bend > 0.0 {
            true => twist.abs() / bend,
            false => 0.0,
        }
    }

    /// κ and τ (signed) of the helix fitted between samples `a` and `b`;
    /// zeros where the fit is undetermined.
    pub fn between(&self, a: usize, b: usize) -> (f64, f64) {
        let normal = self.normal[b] - self.normal[a];
        let rhs = self.rhs[b] - self.rhs[a];
        let mean = (self.tangent[b] - self.tangent[a]).normalize();
        let Ok(d) = normal.svd(true, true).solve(&rhs, 1e-9 * normal.norm()) else {
            return (0.0, 0.0);
        };
        let twist = d.dot(&mean);
        match twist.is_finite() {
            true => ((d - twist * mean).norm(), twist),
            false => (0.0, 0.0),
        }
    }
}

/// The samples bounding the window of `length` centred on `at`, shifted to
/// stay on the curve and shortened when the curve is shorter.
pub fn window(s: &[f64], at: f64, length: f64) -> (usize, usize) {
    let end = s[s.len() - 1];
    let half = 0.5 * length.min(end);
    let from = at.clamp(half, end - half) - half;
    let a = s.partition_point(|&x| x < from);
    let b = s
        .partition_point(|&x| x <= from + 2.0 * half)
        .min(s.len() - 1);
    (a.min(b), b)
}
