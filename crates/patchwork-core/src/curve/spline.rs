//! A smooth curve through given points: the uniform Catmull–Rom spline.

use super::{Curve, CurveError, Point};

impl Curve {
    /// `samples` points of the uniform Catmull–Rom spline through `points`
    /// (at least two), evenly spaced in the spline's parameter: on segment
    /// k, between `points[k]` and `points[k + 1]`, with t ∈ [0, 1],
    ///
    ///   C(t) = ½ [2 P₁ + (P₂ − P₀) t + (2 P₀ − 5 P₁ + 4 P₂ − P₃) t²
    ///             + (3 P₁ − P₀ − 3 P₂ + P₃) t³],
    ///
    /// which passes through every point with a continuous tangent
    /// (P₂ − P₀)/2 there. Beyond the ends the points are extended by
    /// reflection (P₋₁ = 2 P₀ − P₁), so the ends have no curvature of their
    /// own.
    pub fn through(points: &[Point], samples: usize) -> Result<Curve, CurveError> {
        if points.len() < 2 || samples < 2 {
            return Curve::from_points(points.to_vec());
        }
        let segments = points.len() - 1;
        let at = |k: isize| -> Point {
            match k {
                -1 => 2.0 * points[0] - points[1],
                k if k as usize > segments => 2.0 * points[segments] - points[segments - 1],
                k => points[k as usize],
            }
        };
        let sampled = (0..samples)
            .map(|i| {
                let u = i as f64 / (samples - 1) as f64 * segments as f64;
                let k = (u.floor() as usize).min(segments - 1);
                let t = u - k as f64;
                let k = k as isize;
                let (p0, p1, p2, p3) = (at(k - 1), at(k), at(k + 1), at(k + 2));
                0.5 * (2.0 * p1
                    + (p2 - p0) * t
                    + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t * t
                    + (3.0 * p1 - p0 - 3.0 * p2 + p3) * t * t * t)
            })
            .collect();
        Curve::from_points(sampled)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spline_passes_through_its_points_and_keeps_a_line_straight() {
        let points = [
            Point::new(0.0, 0.0, 0.0),
            Point::new(10.0, 5.0, 0.0),
            Point::new(20.0, 0.0, 3.0),
            Point::new(30.0, -4.0, 1.0),
        ];
        // 3 segments × 10 samples each, plus the last point.
        let curve = Curve::through(&points, 31).unwrap();
        for (k, p) in points.iter().enumerate() {
            assert!((curve.points()[10 * k] - p).norm() < 1e-12, "{k}");
        }
        let line: Vec<Point> = (0..5)
            .map(|i| Point::new(i as f64, 2.0 * i as f64, 0.0))
            .collect();
        let straight = Curve::through(&line, 41).unwrap();
        for p in straight.points() {
            assert!((p.y - 2.0 * p.x).abs() < 1e-12 && p.z == 0.0, "{p}");
        }
        assert!((straight.length() - line[4].norm()).abs() < 1e-9);
    }
}
