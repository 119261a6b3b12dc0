//! Parameter checks and sampling uniform in arc length, shared by the
//! preset families.

use super::super::{Curve, CurveError, Point};

/// The largest magnitude of a preset parameter (mm, degrees or turns).
pub const MAX_PARAMETER: f64 = 1e5;
/// The smallest value of a parameter that must be positive.
pub const MIN_POSITIVE_PARAMETER: f64 = 1e-3;

/// A signed parameter: finite, at most [`MAX_PARAMETER`] in magnitude.
pub(super) fn finite(name: &'static str, value: f64) -> Result<(), CurveError> {
    if value.is_finite() && value.abs() <= MAX_PARAMETER {
        Ok(())
    } else {
        Err(CurveError::InvalidParameter {
            name,
            value,
            reason: "must be a number within ±100000",
        })
    }
}

/// A positive parameter: from [`MIN_POSITIVE_PARAMETER`] to [`MAX_PARAMETER`].
pub(super) fn positive(name: &'static str, value: f64) -> Result<(), CurveError> {
    if (MIN_POSITIVE_PARAMETER..=MAX_PARAMETER).contains(&value) {
        Ok(())
    } else {
        Err(CurveError::InvalidParameter {
            name,
            value,
            reason: "must be between 0.001 and 100000",
        })
    }
}

/// Samples `f` on `[0, end]` at `n` points equally spaced in arc length: a dense
/// polyline gives the arc-length-to-parameter map, then each sample is evaluated
/// on `f` itself so it lies exactly on the curve.
pub(super) fn by_arc_length(
    f: impl Fn(f64) -> Point,
    end: f64,
    n: usize,
) -> Result<Curve, CurveError> {
    let dense = (n * 16).max(4096);
    let t: Vec<f64> = (0..=dense).map(|i| end * i as f64 / dense as f64).collect();
    let mut s = vec![0.0; t.len()];
    for i in 1..t.len() {
        s[i] = s[i - 1] + (f(t[i]) - f(t[i - 1])).norm();
    }
    let total = s[dense];
    let mut points = Vec::with_capacity(n);
    let mut k = 1;
    for i in 0..n {
        let target = total * i as f64 / (n - 1) as f64;
        while k < dense && s[k] < target {
            k += 1;
        }
        let w = ((target - s[k - 1]) / (s[k] - s[k - 1])).clamp(0.0, 1.0);
        points.push(f(t[k - 1] + w * (t[k] - t[k - 1])));
    }
    Curve::from_points(points)
}
