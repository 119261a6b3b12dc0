use super::{CurveError, Location, Point};

/// A validated target curve: at least [`Curve::MIN_POINTS`] finite, distinct
/// consecutive points in millimetres, with cumulative chord arc length.
///
/// Invariants (established by [`Curve::from_points`], relied upon everywhere):
/// every coordinate finite, no two consecutive points equal, total length > 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    points: Vec<Point>,
    arc_length: Vec<f64>,
}

impl Curve {
    pub const MIN_POINTS: usize = 4;
    pub const MAX_POINTS: usize = 100_000;

    /// Validates and builds a curve. Consecutive duplicate points (closer than
    /// 1e-9 of the curve's extent) are dropped, not rejected: digitisers and
    /// spreadsheets produce them routinely.
    pub fn from_points(points: Vec<Point>) -> Result<Self, CurveError> {
        Self::from_located_points(points, Location::Index)
    }

    /// As [`Curve::from_points`], with `locate` turning an index into the user's
    /// notion of position (a file line, say) for error messages.
    pub(crate) fn from_located_points(
        points: Vec<Point>,
        locate: impl Fn(usize) -> Location,
    ) -> Result<Self, CurveError> {
        if points.len() > Self::MAX_POINTS {
            return Err(CurveError::TooManyPoints {
                found: points.len(),
                max: Self::MAX_POINTS,
            });
        }
        for (index, p) in points.iter().enumerate() {
            for (axis, value) in ['x', 'y', 'z'].into_iter().zip(p.iter()) {
                if !value.is_finite() {
                    return Err(CurveError::NonFinite {
                        at: locate(index),
                        axis,
                        value: *value,
                    });
                }
            }
        }
        let given = points.len();
        let extent = bounding_extent(&points);
        let duplicate_tol = 1e-9 * extent.max(1e-12);
        let mut distinct: Vec<Point> = Vec::with_capacity(points.len());
        for p in points {
            if distinct
                .last()
                .is_none_or(|last| (p - last).norm() > duplicate_tol)
            {
                distinct.push(p);
            }
        }
        if distinct.len() == 1 && given >= Self::MIN_POINTS {
            return Err(CurveError::ZeroLength);
        }
        if distinct.len() < Self::MIN_POINTS {
            return Err(CurveError::TooFewPoints {
                found: distinct.len(),
                min: Self::MIN_POINTS,
            });
        }
        let arc_length = cumulative_length(&distinct);
        Ok(Curve {
            points: distinct,
            arc_length,
        })
    }

    pub fn points(&self) -> &[Point] {
        &self.points
    }

    /// The largest distance between corresponding points of this curve and
    /// `other` (mm): for curves sampled alike, such as two centrelines of
    /// the same balloon's rings. Extra points of the longer curve are ignored.
    pub fn largest_gap(&self, other: &Curve) -> f64 {
        largest_gap(&self.points, &other.points)
    }

    /// Cumulative chord length at each point, starting at 0 (mm).
    pub fn arc_length(&self) -> &[f64] {
        &self.arc_length
    }

    /// Total length (mm).
    pub fn length(&self) -> f64 {
        *self.arc_length.last().unwrap_or(&0.0)
    }

    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Always false: a curve has at least [`Curve::MIN_POINTS`] points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The point at arc length `s` (clamped to the curve), by linear
    /// interpolation along the polyline.
    pub fn point_at(&self, s: f64) -> Point {
        let s = s.clamp(0.0, self.length());
        let upper = self.arc_length.partition_point(|&a| a < s).max(1);
        let (s0, s1) = (self.arc_length[upper - 1], self.arc_length[upper]);
        let t = if s1 > s0 { (s - s0) / (s1 - s0) } else { 0.0 };
        self.points[upper - 1].lerp(&self.points[upper], t)
    }

    /// `n` points equally spaced in arc length, first and last kept exactly.
    pub fn resample(&self, n: usize) -> Result<Curve, CurveError> {
        if !(Self::MIN_POINTS..=Self::MAX_POINTS).contains(&n) {
            return Err(CurveError::ResampleCount {
                requested: n,
                min: Self::MIN_POINTS,
                max: Self::MAX_POINTS,
            });
        }
        let length = self.length();
        let mut points = Vec::with_capacity(n);
        let mut segment = 1;
        for i in 0..n {
            let s = length * i as f64 / (n - 1) as f64;
            while segment < self.len() - 1 && self.arc_length[segment] < s {
                segment += 1;
            }
            let (s0, s1) = (self.arc_length[segment - 1], self.arc_length[segment]);
            let t = ((s - s0) / (s1 - s0)).clamp(0.0, 1.0);
            points.push(self.points[segment - 1].lerp(&self.points[segment], t));
        }
        Curve::from_points(points)
    }

    /// Mean squared distance of the points from their best-fit line and
    /// from their best-fit plane (mm²): the scatter matrix Σ (p − p̄)(p − p̄)ᵀ
    /// over n has the squared distances along its principal axes as
    /// eigenvalues, the plane's normal along the smallest, the line along
    /// the largest.
    pub fn off_line_and_plane(&self) -> (f64, f64) {
        let n = self.points.len() as f64;
        let mean = self.points.iter().sum::<Point>() / n;
        let scatter = self
            .points
            .iter()
            .map(|p| (p - mean) * (p - mean).transpose())
            .sum::<nalgebra::Matrix3<f64>>();
        let eigen = scatter.symmetric_eigen().eigenvalues;
        let off_line = (eigen.sum() - eigen.max()).max(0.0) / n;
        let off_plane = eigen.min().max(0.0) / n;
        (off_line, off_plane)
    }

    /// Distances between consecutive points (mm).
    pub fn chords(&self) -> Vec<f64> {
        self.arc_length.windows(2).map(|w| w[1] - w[0]).collect()
    }

    /// The same curve moved rigidly: `p ↦ rotation · p + translation`.
    pub fn transformed(&self, rotation: &nalgebra::Rotation3<f64>, translation: &Point) -> Curve {
        let points = self
            .points
            .iter()
            .map(|p| rotation * p + translation)
            .collect();
        Curve {
            points,
            arc_length: self.arc_length.clone(),
        }
    }
}

fn bounding_extent(points: &[Point]) -> f64 {
    let Some(first) = points.first() else {
        return 0.0;
    };
    let (lo, hi) = points
        .iter()
        .fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    (hi - lo).norm()
}

/// Arc length at each point of a polyline, from 0 at the first.
pub(crate) fn cumulative_length(points: &[Point]) -> Vec<f64> {
    let mut s = Vec::with_capacity(points.len());
    let mut total = 0.0;
    s.push(0.0);
    for pair in points.windows(2) {
        total += (pair[1] - pair[0]).norm();
        s.push(total);
    }
    s
}

/// The largest distance between corresponding points of `a` and `b` (mm);
/// extra points of the longer list are ignored.
pub fn largest_gap(a: &[Point], b: &[Point]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64, z: f64) -> Point {
        Point::new(x, y, z)
    }

    #[test]
    fn consecutive_duplicates_are_dropped() {
        let c = Curve::from_points(vec![
            p(0., 0., 0.),
            p(0., 0., 0.),
            p(1., 0., 0.),
            p(2., 0., 0.),
            p(2., 0., 0.),
            p(3., 0., 0.),
        ])
        .unwrap();
        assert_eq!(c.len(), 4);
        assert_eq!(c.length(), 3.0);
    }

    #[test]
    fn all_coincident_points_are_zero_length() {
        let err = Curve::from_points(vec![p(1., 1., 1.); 10]).unwrap_err();
        assert_eq!(err, CurveError::ZeroLength);
    }

    #[test]
    fn too_few_and_non_finite_are_named() {
        let err = Curve::from_points(vec![p(0., 0., 0.), p(1., 0., 0.), p(2., 0., 0.)]);
        assert_eq!(
            err.unwrap_err(),
            CurveError::TooFewPoints { found: 3, min: 4 }
        );
        let err = Curve::from_points(vec![
            p(0., 0., 0.),
            p(1., 0., 0.),
            p(2., f64::NAN, 0.),
            p(3., 0., 0.),
        ])
        .unwrap_err();
        assert!(matches!(
            err,
            CurveError::NonFinite {
                at: Location::Index(2),
                axis: 'y',
                ..
            }
        ));
    }

    #[test]
    fn resample_is_uniform_and_keeps_ends() {
        let c = Curve::from_points(vec![
            p(0., 0., 0.),
            p(1., 0., 0.),
            p(1., 3., 0.),
            p(1., 3., 6.),
        ])
        .unwrap();
        let r = c.resample(11).unwrap();
        assert_eq!(r.len(), 11);
        assert_eq!(r.points()[0], c.points()[0]);
        assert!((r.points()[10] - c.points()[3]).norm() < 1e-12);
        for w in r.arc_length().windows(2) {
            assert!((w[1] - w[0] - 1.0).abs() < 1e-12);
        }
        assert!(c.resample(2).is_err());
    }

    #[test]
    fn largest_gap_is_the_farthest_pair() {
        let a = Curve::from_points(vec![
            p(0., 0., 0.),
            p(1., 0., 0.),
            p(2., 0., 0.),
            p(3., 0., 0.),
        ])
        .unwrap();
        // Corresponding points 0.5, 0, 1.5 and 0 mm apart.
        let mut moved = a.points().to_vec();
        moved[0].y += 0.5;
        moved[2].z += 1.5;
        let b = Curve::from_points(moved).unwrap();
        assert!((a.largest_gap(&b) - 1.5).abs() < 1e-15);
        assert_eq!(a.largest_gap(&a), 0.0);
        assert!((largest_gap(&a.points()[..2], &[p(0., 0., 2.)]) - 2.0).abs() < 1e-15);
    }

    #[test]
    fn point_at_interpolates() {
        let c = Curve::from_points(vec![
            p(0., 0., 0.),
            p(2., 0., 0.),
            p(2., 2., 0.),
            p(2., 2., 2.),
        ])
        .unwrap();
        assert!((c.point_at(3.0) - p(2., 1., 0.)).norm() < 1e-12);
        assert!((c.point_at(-5.0) - p(0., 0., 0.)).norm() < 1e-12);
        assert!((c.point_at(99.0) - p(2., 2., 2.)).norm() < 1e-12);
    }
}
