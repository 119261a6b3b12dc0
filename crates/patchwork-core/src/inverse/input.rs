//! The target as the design sees it: drawing noise found and smoothed away
//! (or the user's smoothing), and whether it lies in a plane.
//!
//! Automatic smoothing estimates the noise on the samples
//! ([`Curve::noise_estimate`]) and, when it is above `NOISE_FLOOR_MM`,
//! smooths with the σ that brings the curvature noise down to a fifth of
//! KSA's curvature tolerance ([`Curve::smoothing_for`]): what is left
//! cannot mark a sample for a patch on its own.

use serde::{Deserialize, Serialize};

use crate::curve::{Curve, CurveError, Point};

/// Noise below this (mm per coordinate) is left alone: far below any
/// cutting tolerance, and the rounding of coordinates written to 0.01 mm.
const NOISE_FLOOR_MM: f64 = 0.01;

/// The largest automatic smoothing (mm): beyond it the curve's own bends
/// would lose more than the noise.
const MAX_AUTO_SMOOTHING_MM: f64 = 8.0;

/// Points closer than σ / `SAMPLES_PER_SIGMA` along the curve are
/// resampled to that spacing before smoothing: a Gaussian of σ leaves
/// nothing finer, and the smoothing's cost grows with the points under the
/// kernel (100 000 points at σ = a quarter of the length took minutes).
const SAMPLES_PER_SIGMA: f64 = 16.0;

/// Points further apart than this (median, mm) are read through a spline:
/// KSA's merge distance, beyond which marked samples cannot form a run, so
/// a bend sampled that sparsely gets no patch at all.
const SPARSE_SPACING_MM: f64 = 20.0;

/// Points whose chords stray further than this from the smooth curve
/// through them (mm; a chord c turning by θ at its ends strays by about
/// c θ / 8; the 90th percentile over the points) are read through a spline:
/// the design would otherwise aim at the polyline's corners. Not lower: a
/// spline ripples on the straight stretches of a curve given this sparsely
/// (through the authors' spring, 64 points 13 mm apart whose chords stray
/// by 0.45 mm, its torsion spikes to 3.3 mm⁻¹ where the curve is straight,
/// and the design misses by 3.9 % against 0.5 % on the points as given).
/// The authors' Hilbert and pancake curves stray by 0.08 and 0.19 mm.
const SPARSE_SAGITTA_MM: f64 = 1.0;

/// The spacing of the spline's samples (mm).
const INTERPOLATED_SPACING_MM: f64 = 1.0;

/// A curve whose points lie within this fraction of its length (RMS) of
/// one plane is planar.
const PLANAR_TOLERANCE: f64 = 1e-3;

/// How the target is smoothed before the design.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Smoothing {
    /// Found from the noise on the samples.
    #[default]
    Auto,
    /// A Gaussian of this σ along arc length (mm); 0 leaves the curve as
    /// given (sparse points are not read through a spline either).
    Sigma(f64),
}

/// What was done to the target before the design.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct InputReport {
    /// The noise found on the samples (mm per coordinate, standard
    /// deviation); 0 for points too far apart to tell noise from bends
    /// (median spacing over 20 mm; `interpolated`).
    pub noise_mm: f64,
    /// The σ of the Gaussian smoothing applied (mm); 0: none.
    pub smoothing_mm: f64,
    /// Whether the smoothing was chosen from the noise (or given).
    pub automatic: bool,
    /// Whether the target lies in a plane (within 0.1 % of its length, or
    /// the noise found, RMS).
    pub planar: bool,
    /// Whether the design was kept planar: patches at Θ = 0 on one line of
    /// the tube and the line opposite (`planar.rs`).
    #[serde(default)]
    pub planar_design: bool,
    /// Where the points were too sparse for their bends: the curve the
    /// design aimed at is the cubic spline through them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interpolated: Option<Interpolated>,
    /// Whether the design was kept clear of itself (tuning `keep_clear`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub keep_clear: bool,
    /// Where a tube along the target would pass through itself and the
    /// design was kept clear of itself: the design aimed at the nearest
    /// clear curve ([`super::clearing`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cleared: Option<Cleared>,
}

impl InputReport {
    /// Whether the target the design aimed at differs from the points as
    /// given: smoothed, read through a spline, or cleared of itself.
    pub fn changed_target(&self) -> bool {
        self.smoothing_mm > 0.0 || self.interpolated.is_some() || self.cleared.is_some()
    }

    /// Whether the points were too far apart to look for noise on them
    /// (`noise_mm` is then 0 without meaning none).
    pub fn too_sparse_for_noise(&self) -> bool {
        self.interpolated
            .is_some_and(|i| i.median_spacing_mm > SPARSE_SPACING_MM)
    }
}

/// What clearing the target of itself did ([`super::clearing`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Cleared {
    /// The tube's radius it was cleared for (mm).
    pub radius_mm: f64,
    /// How far the tube along the target as given passed into itself at
    /// the deepest (mm).
    pub overlap_mm: f64,
    /// How far the cleared curve lies from the target: at most and RMS
    /// over its samples (mm).
    pub moved_max_mm: f64,
    pub moved_rms_mm: f64,
    /// Whether every pair came clear within the rounds (otherwise the
    /// design aims at the last round's curve, still closer than the tube).
    pub converged: bool,
}

/// Sparse points read through a cubic spline ([`Curve::through`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Interpolated {
    /// The points given.
    pub points: usize,
    /// Their median spacing (mm).
    pub median_spacing_mm: f64,
    /// How far their chords stray from the spline (mm, c θ / 8; the 90th
    /// percentile over the points).
    pub sagitta_mm: f64,
    /// The spline's samples.
    pub samples: usize,
}

/// The target the design aims at, and what was done to get it.
pub fn prepare(
    target: &Curve,
    smoothing: Smoothing,
    kappa_tol: f64,
) -> Result<(Curve, InputReport), CurveError> {
    check_smoothing(target, smoothing)?;
    // Points this far apart have no noise to find: the local fits that
    // estimate it would read the bends as noise. (Only the spacing: noise
    // turns every chord, and the sagitta test would read it as sparseness.)
    let noise = match median_spacing(&target.chords()) > SPARSE_SPACING_MM {
        true => 0.0,
        false => target.noise_estimate(),
    };
    let (sigma, automatic) = match smoothing {
        Smoothing::Sigma(sigma) => (sigma, false),
        Smoothing::Auto if noise < NOISE_FLOOR_MM => (0.0, true),
        Smoothing::Auto => (
            target
                .smoothing_for(noise, kappa_tol / 5.0)
                .min(MAX_AUTO_SMOOTHING_MM),
            true,
        ),
    };
    let smoothed = match sigma > 0.0 {
        true => with_ends_fitted(&thinned(target, sigma)?, sigma)?.smoothed_twice(sigma)?,
        false => target.clone(),
    };
    // σ = 0 asks for the curve as given: no spline either.
    let as_given = smoothing == Smoothing::Sigma(0.0);
    let (prepared, interpolated) = match sparseness(&smoothed).filter(|_| !as_given) {
        Some((median_spacing_mm, sagitta_mm)) => {
            let samples = ((smoothed.length() / INTERPOLATED_SPACING_MM).ceil() as usize + 1)
                .clamp(smoothed.len(), Curve::MAX_POINTS);
            let spline = Curve::through(smoothed.points(), samples)?;
            let report = Interpolated {
                points: smoothed.len(),
                median_spacing_mm,
                sagitta_mm,
                samples,
            };
            (spline, Some(report))
        }
        None => (smoothed, None),
    };
    let report = InputReport {
        noise_mm: noise,
        smoothing_mm: sigma,
        automatic,
        planar: is_planar(&prepared, noise),
        planar_design: false,
        interpolated,
        keep_clear: false,
        cleared: None,
    };
    Ok((prepared, report))
}

/// The median distance between consecutive points (mm).
fn median_spacing(chords: &[f64]) -> f64 {
    let mut sorted = chords.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted[sorted.len() / 2]
}

/// The median spacing and the 90th percentile of the sagitta (c θ / 8, with
/// c the mean of the two chords at a point and θ their turn) of points too
/// sparse for their bends; none when they are dense enough. The percentile,
/// not the largest: one kink does not make a curve sparse.
fn sparseness(curve: &Curve) -> Option<(f64, f64)> {
    let chords = curve.chords();
    let mut sagittas: Vec<f64> = curve
        .points()
        .windows(3)
        .zip(chords.windows(2))
        .map(|(p, c)| {
            let cos = (p[1] - p[0]).dot(&(p[2] - p[1])) / (c[0] * c[1]);
            0.5 * (c[0] + c[1]) * cos.clamp(-1.0, 1.0).acos() / 8.0
        })
        .collect();
    sagittas.sort_by(f64::total_cmp);
    let sagitta = sagittas[sagittas.len() * 9 / 10];
    let median = median_spacing(&chords);
    (median > SPARSE_SPACING_MM || sagitta > SPARSE_SAGITTA_MM).then_some((median, sagitta))
}

/// The curve resampled at σ / `SAMPLES_PER_SIGMA` where its points are
/// denser than that; else as it is.
fn thinned(curve: &Curve, sigma: f64) -> Result<Curve, CurveError> {
    let spacing = sigma / SAMPLES_PER_SIGMA;
    let gaps = (curve.len() - 1) as f64;
    if curve.length() / gaps >= spacing {
        return Ok(curve.clone());
    }
    curve.resample((curve.length() / spacing).ceil() as usize + 1)
}

/// A user's smoothing σ must be at most a quarter of the target's length:
/// a longer one smooths every bend away.
pub fn check_smoothing(target: &Curve, smoothing: Smoothing) -> Result<(), CurveError> {
    let length_mm = target.length();
    match smoothing {
        Smoothing::Sigma(sigma_mm) if sigma_mm > length_mm / 4.0 => {
            Err(CurveError::SmoothingTooLong {
                sigma_mm,
                length_mm,
            })
        }
        _ => Ok(()),
    }
}

/// The curve with each end point replaced by a quadratic fitted, in arc
/// length, to the points within 2σ of that end: the smoothing keeps the
/// end points and reflects the curve about them, so a noisy end point
/// would bend the smoothed curve for a few σ.
fn with_ends_fitted(curve: &Curve, sigma: f64) -> Result<Curve, CurveError> {
    let mut points = curve.points().to_vec();
    let s = curve.arc_length();
    let n = points.len();
    let near_start: Vec<usize> = (0..n).take_while(|&i| s[i] <= 2.0 * sigma).collect();
    let near_end: Vec<usize> = (0..n)
        .rev()
        .take_while(|&i| s[n - 1] - s[i] <= 2.0 * sigma)
        .collect();
    let fit = |indices: &[usize], at: f64| quadratic_at(indices, s, curve.points(), at);
    if let Some(p) = fit(&near_start, 0.0) {
        points[0] = p;
    }
    if let Some(p) = fit(&near_end, s[n - 1]) {
        points[n - 1] = p;
    }
    Curve::from_points(points)
}

/// The least-squares quadratic through `points[indices]` against arc
/// length `s`, at `at`; none with fewer than six points.
fn quadratic_at(indices: &[usize], s: &[f64], points: &[Point], at: f64) -> Option<Point> {
    if indices.len() < 6 {
        return None;
    }
    let rows = indices.len();
    let basis = nalgebra::DMatrix::from_fn(rows, 3, |r, c| (s[indices[r]] - at).powi(c as i32));
    let values = nalgebra::DMatrix::from_fn(rows, 3, |r, c| points[indices[r]][c]);
    let solution = basis.svd(true, true).solve(&values, 1e-12).ok()?;
    Some(Point::new(
        solution[(0, 0)],
        solution[(0, 1)],
        solution[(0, 2)],
    ))
}

/// Whether the curve lies in a plane: the RMS distance of its points from
/// their best-fit plane (normal to the smallest principal axis) is within
/// `PLANAR_TOLERANCE` of its length, or within the noise found on it.
pub fn is_planar(curve: &Curve, noise_mm: f64) -> bool {
    let rms = curve.off_line_and_plane().1.sqrt();
    rms <= (PLANAR_TOLERANCE * curve.length()).max(noise_mm)
}

#[cfg(test)]
#[path = "input_tests.rs"]
mod tests;
