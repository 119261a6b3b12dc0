//! A smooth curve through given points: the cubic spline with not-a-knot
//! ends, parametrised by chord length.

use super::{Curve, CurveError, Point};

impl Curve {
    /// `samples` points of the cubic spline through `points`, evenly spaced
    /// in its parameter, the chord length u (uᵢ₊₁ − uᵢ = |Pᵢ₊₁ − Pᵢ|, which
    /// the arc length exceeds by about θ²/24 of a chord turning by θ). On
    /// [uᵢ, uᵢ₊₁], with h = uᵢ₊₁ − uᵢ and second derivatives Mᵢ at the points,
    ///
    ///   S(u) = Mᵢ (uᵢ₊₁ − u)³ / 6h + Mᵢ₊₁ (u − uᵢ)³ / 6h
    ///        + (Pᵢ/h − Mᵢ h/6)(uᵢ₊₁ − u) + (Pᵢ₊₁/h − Mᵢ₊₁ h/6)(u − uᵢ),
    ///
    /// continuous in value, tangent and curvature at every point: interior
    /// rows hᵢ₋₁ Mᵢ₋₁ + 2 (hᵢ₋₁ + hᵢ) Mᵢ + hᵢ Mᵢ₊₁ = 6 (Δᵢ/hᵢ − Δᵢ₋₁/hᵢ₋₁).
    /// The ends are not-a-knot (the third derivative is continuous at the
    /// second and last-but-one points), so a curve bending at its ends keeps
    /// that bend, where a natural spline would straighten it. Three points
    /// give the parabola through them (M constant). Fewer points, or
    /// coincident consecutive ones, are [`Curve::from_points`]'s errors.
    ///
    /// Its curvature is accurate to about (h κ)²/12 and its torsion to
    /// O(h κ) for chords h: on a helix given 33° apart, 3 % and 6 % (a test
    /// pins them), while its points stay within 0.05 mm of the helix (0.13 mm
    /// in the end chords).
    pub fn through(points: &[Point], samples: usize) -> Result<Curve, CurveError> {
        if points.len() < 3 || samples < 2 {
            return Curve::from_points(points.to_vec());
        }
        let mut u = vec![0.0; points.len()];
        for i in 1..points.len() {
            let chord = (points[i] - points[i - 1]).norm();
            if chord == 0.0 {
                // Coincident points: the curve's own error names them.
                return Curve::from_points(points.to_vec());
            }
            u[i] = u[i - 1] + chord;
        }
        let m = second_derivatives(points, &u);
        let total = u[u.len() - 1];
        let mut segment = 0;
        let sampled = (0..samples)
            .map(|k| {
                let x = total * k as f64 / (samples - 1) as f64;
                while segment + 2 < u.len() && u[segment + 1] < x {
                    segment += 1;
                }
                let (i, h) = (segment, u[segment + 1] - u[segment]);
                let (a, b) = (u[i + 1] - x, x - u[i]);
                m[i] * (a * a * a / (6.0 * h))
                    + m[i + 1] * (b * b * b / (6.0 * h))
                    + (points[i] / h - m[i] * (h / 6.0)) * a
                    + (points[i + 1] / h - m[i + 1] * (h / 6.0)) * b
            })
            .collect();
        Curve::from_points(sampled)
    }
}

/// How a seeded stroke is drawn: the cubic spline through `points` control
/// points `spacing_mm` apart along x, each moved by seeded Gaussian offsets
/// (σ a quarter of the spacing along x, `spread_mm` across).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrokeShape {
    pub points: usize,
    pub spacing_mm: f64,
    pub spread_mm: f64,
}

impl StrokeShape {
    /// Eight points 40 mm apart, 40 mm across: about 500–700 mm long, with
    /// bends as tight as 1–8 mm in radius (tighter than a balloon bends).
    pub const HAND: StrokeShape = StrokeShape {
        points: 8,
        spacing_mm: 40.0,
        spread_mm: 40.0,
    };

    /// Seven points 100 mm apart, 30 mm across: about 640–810 mm long, its
    /// tightest bends 13–60 mm in radius (seeds 21, 22, 31–36), mostly
    /// within a balloon's reach.
    pub const SWEEPING: StrokeShape = StrokeShape {
        points: 7,
        spacing_mm: 100.0,
        spread_mm: 30.0,
    };
}

/// A smooth random stroke, as a hand might draw in 3D
/// ([`StrokeShape::HAND`]), `samples` points. For studies, tests and the
/// bench: the same seed gives the same stroke.
pub fn seeded_stroke(seed: u64, samples: usize) -> Result<Curve, CurveError> {
    seeded_stroke_shaped(seed, samples, StrokeShape::HAND)
}

/// A seeded stroke of the given `shape`, `samples` points.
pub fn seeded_stroke_shaped(
    seed: u64,
    samples: usize,
    shape: StrokeShape,
) -> Result<Curve, CurveError> {
    let mut rng = crate::cmaes::SeededRng::new(seed);
    let control: Vec<Point> = (0..shape.points)
        .map(|i| {
            Point::new(
                shape.spacing_mm * (i as f64 + 0.25 * rng.normal()),
                shape.spread_mm * rng.normal(),
                shape.spread_mm * rng.normal(),
            )
        })
        .collect();
    Curve::through(&control, samples)
}

/// The spline's second derivatives at the points (one vector per point),
/// from the interior continuity rows and the not-a-knot ends; equal at all
/// three points of a three-point curve (its parabola). The not-a-knot
/// conditions give M₀ and Mₙ₋₁ from their two neighbours; put into the
/// first and last interior rows, they leave a tridiagonal system in
/// M₁ … Mₙ₋₂, solved in O(n) (a curve may have thousands of sparse points).
fn second_derivatives(points: &[Point], u: &[f64]) -> Vec<Point> {
    let n = points.len();
    let h: Vec<f64> = u.windows(2).map(|w| w[1] - w[0]).collect();
    // Interior row i (1 ≤ i ≤ n − 2), stored at i − 1:
    // lower M[i−1] + diag M[i] + upper M[i+1] = rhs.
    let m = n - 2;
    let mut lower: Vec<f64> = (1..n - 1).map(|i| h[i - 1]).collect();
    let mut diag: Vec<f64> = (1..n - 1).map(|i| 2.0 * (h[i - 1] + h[i])).collect();
    let mut upper: Vec<f64> = (1..n - 1).map(|i| h[i]).collect();
    let mut rhs: Vec<Point> = (1..n - 1)
        .map(|i| {
            6.0 * ((points[i + 1] - points[i]) / h[i] - (points[i] - points[i - 1]) / h[i - 1])
        })
        .collect();
    if n == 3 {
        // M₀ = M₁ = M₂: the parabola.
        let second = rhs[0] / (lower[0] + diag[0] + upper[0]);
        return vec![second; 3];
    }
    // (M₁ − M₀)/h₀ = (M₂ − M₁)/h₁: M₀ = ((h₀ + h₁) M₁ − h₀ M₂)/h₁.
    let (h0, h1) = (h[0], h[1]);
    diag[0] += lower[0] * (h0 + h1) / h1;
    upper[0] -= lower[0] * h0 / h1;
    // At the far end, with p, q the last two chords:
    // Mₙ₋₁ = ((p + q) Mₙ₋₂ − q Mₙ₋₃)/p.
    let (p, q) = (h[n - 3], h[n - 2]);
    diag[m - 1] += upper[m - 1] * (p + q) / p;
    lower[m - 1] -= upper[m - 1] * q / p;
    thomas(&lower, &mut diag, &upper, &mut rhs);
    let first = (rhs[0] * (h0 + h1) - rhs[1] * h0) / h1;
    let last = (rhs[m - 1] * (p + q) - rhs[m - 2] * q) / p;
    let mut second = Vec::with_capacity(n);
    second.push(first);
    second.extend(rhs);
    second.push(last);
    second
}

/// Solves the tridiagonal system in place (Thomas algorithm): `rhs`
/// becomes the solution. The spline's interior rows are diagonally
/// dominant (2 (hᵢ₋₁ + hᵢ) against hᵢ₋₁ + hᵢ), and the end substitutions
/// keep the first and last so, so no pivoting is needed.
fn thomas(lower: &[f64], diag: &mut [f64], upper: &[f64], rhs: &mut [Point]) {
    let n = diag.len();
    for i in 1..n {
        let w = lower[i] / diag[i - 1];
        diag[i] -= w * upper[i - 1];
        let above = rhs[i - 1];
        rhs[i] -= above * w;
    }
    rhs[n - 1] /= diag[n - 1];
    for i in (0..n - 1).rev() {
        let below = rhs[i + 1];
        rhs[i] = (rhs[i] - below * upper[i]) / diag[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::{AnalysisOptions, Preset, analyse};

    #[test]
    fn the_spline_passes_through_its_points_and_keeps_a_line_straight() {
        let points = [
            Point::new(0.0, 0.0, 0.0),
            Point::new(10.0, 0.0, 0.0),
            Point::new(20.0, 0.0, 0.0),
            Point::new(30.0, 0.0, 0.0),
            Point::new(40.0, 0.0, 0.0),
        ];
        // Equal chords: every tenth sample is a point.
        let line = Curve::through(&points, 41).unwrap();
        for (k, p) in points.iter().enumerate() {
            assert!((line.points()[10 * k] - p).norm() < 1e-9, "{k}");
        }
        for p in line.points() {
            assert!(p.y == 0.0 && p.z == 0.0, "{p}");
        }
        assert!((line.length() - 40.0).abs() < 1e-9);
    }

    /// Three points give one parabola in the chord parameter: through the
    /// middle point, and symmetric when the points are.
    #[test]
    fn three_points_give_their_parabola() {
        let points = [
            Point::new(-1.0, 1.0, 0.0),
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 1.0, 0.0),
        ];
        let curve = Curve::through(&points, 201).unwrap();
        assert!((curve.points()[100] - points[1]).norm() < 1e-12);
        for k in 0..100 {
            let (p, q) = (curve.points()[k], curve.points()[200 - k]);
            assert!(
                (p.x + q.x).abs() < 1e-12 && (p.y - q.y).abs() < 1e-12,
                "{k}"
            );
        }
    }

    /// A helix (radius 40, pitch 70 mm, two turns) given as 22 points 33°
    /// apart, read through the spline: away from the end chords every
    /// sample within 0.05 mm of the helix, and κ and τ within 4 and 8 % of
    /// the closed form (measured 3.0 and 5.9 %: the ripple of a cubic between points
    /// this far apart).
    #[test]
    fn a_sparse_helix_is_read_back_with_its_curvature_and_torsion() {
        let helix = Preset::helix(40.0, 70.0, 2.0).generate(22).unwrap();
        let read = Curve::through(helix.points(), 500).unwrap();
        let b = 70.0 / std::f64::consts::TAU;
        let (kappa, tau) = (40.0 / (1600.0 + b * b), b / (1600.0 + b * b));
        let analysis = analyse(&read, &AnalysisOptions::default());
        let inner = 50..450;
        let worst = |values: &[f64], truth: f64| {
            values[inner.clone()]
                .iter()
                .map(|v| (v / truth - 1.0).abs())
                .fold(0.0, f64::max)
        };
        let (dk, dt) = (
            worst(&analysis.curvature, kappa),
            worst(&analysis.torsion, tau),
        );
        assert!(dk < 0.04 && dt < 0.08, "κ {dk}, τ {dt}");
        let off_helix = read.points()[inner.clone()]
            .iter()
            .map(|p| ((p.x * p.x + p.y * p.y).sqrt() - 40.0).abs())
            .fold(0.0, f64::max);
        assert!(off_helix < 0.05, "{off_helix} mm");
    }
}
