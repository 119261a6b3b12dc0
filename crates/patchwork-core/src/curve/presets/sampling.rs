//! Parameter checks and sampling uniform in arc length, shared by the
//! preset families.

use super::super::{Curve, CurveError, Point};

pub(super) fn finite(name: &'static str, value: f64) -> Result<(), CurveError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(CurveError::InvalidParameter {
            name,
            value,
            reason: "must be finite",
        })
    }
}

pub(super) fn positive(name: &'static str, value: f64) -> Result<(), CurveError> {
    finite(name, value)?;
    if value > 0.0 {
        Ok(())
    } else {
        Err(CurveError::InvalidParameter {
            name,
            value,
            reason: "must be positive",
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
