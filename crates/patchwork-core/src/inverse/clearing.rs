//! A target tighter than the tube: where a tube of the inflated balloon's
//! radius along the target would pass through itself (a helix whose pitch
//! is less than the tube's diameter, a knot's ends meeting), no balloon
//! follows it. A design kept clear of itself (tuning `keep_clear`) aims at
//! the nearest curve that a tube can follow instead, found here, and its
//! shape error is still measured against the curve as given.
//!
//! The method is position-based relaxation on the target's samples (about
//! a quarter of the tube's radius apart): every pair of segments far enough
//! apart along the curve (as in [`crate::fe::contact`]) that comes closer
//! than the tube's diameter plus the margin is pushed apart along the line
//! between their closest points, half the shortfall each, shared between a
//! segment's ends by the closest point's position; the displacement from
//! the target is then smoothed along the curve (so a push moves a stretch,
//! not a point) and every segment restored to its length (the balloon does
//! not stretch to clear itself). Repeated until no pair is within the
//! diameter and the margin; the displacement is smoothed once more and the
//! samples read through a cubic spline about 1 mm apart. A helix opens its
//! pitch; a knot's ends part.

use super::caches::Caches;
use super::input::{Cleared, InputReport};
use super::objective::CLEARANCE_MARGIN_MM;
use super::run::Setup;
use super::settings::UserSettings;
use super::stages::seed_tube_radius;
use super::tuning::Tuning;
use crate::curve::{Curve, Point, cumulative_length};
use crate::fe::contact::closest;
use crate::fe::tube_theory::bare_radius;

/// Relaxation rounds at most; a round costs one pass over the pairs.
const ROUNDS: usize = 1500;
/// Samples per tube radius along the curve.
const SAMPLES_PER_RADIUS: f64 = 4.0;
/// Smoothing passes of the displacement per round (each a [¼ ½ ¼] filter).
const SMOOTHING_PASSES: usize = 4;
/// Smoothing passes of the displacement once clear: the pushes leave a
/// ripple at the samples' spacing, which these take out (σ² of about one
/// sample spacing² per 2 passes); the rounds go on if that gave some of
/// the clearance back.
const FINAL_SMOOTHING_PASSES: usize = 16;
/// Each push is this much more than half the shortfall: the smoothing and
/// the lengths' restoring take some of it back.
const OVER_RELAXATION: f64 = 1.5;
/// Passes restoring the segments' lengths per round.
const LENGTH_PASSES: usize = 30;
/// Cleared when no pair is closer than the diameter and margin by more
/// than this (mm).
const CLEAR_MM: f64 = 0.01;

/// The target a design aims at under `tuning`: `target` itself, or, for a
/// design kept clear of itself whose tube along `target` would pass
/// through itself, the nearest clear curve and what clearing it did. The
/// tube's radius is not known before the design: patches narrow it (a
/// stretch under patches inflates to about two thirds of the bare tube's
/// radius), so the target is cleared for the radius KSA's seed inflates to
/// (the 90th percentile of its rings), and the objective keeps the design's
/// own rings clear.
pub(super) fn target_to_aim_at(
    target: Curve,
    input: &InputReport,
    (settings, tuning): (&UserSettings, &Tuning),
    caches: &Caches,
) -> (Curve, Option<Cleared>) {
    let Some(bare) = bare_radius(&settings.base).filter(|_| tuning.keep_clear) else {
        return (target, None);
    };
    // Clear even for the widest tube: nothing to do (and no seed solve).
    if overlap_along(&target, bare).is_none() {
        return (target, None);
    }
    let setup = Setup::new(&target, *input, settings, tuning);
    let radius = seed_tube_radius(&setup, caches).unwrap_or(bare);
    match clear_of_itself(&target, radius, CLEARANCE_MARGIN_MM) {
        Some((cleared, report)) => (cleared, Some(report)),
        None => (target, None),
    }
}

/// The nearest curve to `target` along which a tube of `radius_mm` keeps
/// `margin_mm` clear of itself, and what was done; none when the tube
/// along the target itself does not pass through itself.
pub fn clear_of_itself(target: &Curve, radius_mm: f64, margin_mm: f64) -> Option<(Curve, Cleared)> {
    let (origin, overlap_mm) = overlap_along(target, radius_mm)?;
    let s = cumulative_length(&origin);
    let apart = std::f64::consts::PI * radius_mm;
    let count = origin.len();
    // Pushed towards twice the margin, cleared once every pair keeps the
    // margin: the last tenths of a millimetre converge slowly where the
    // smoothing and the lengths pull back.
    let reach = 2.0 * radius_mm + 2.0 * margin_mm;
    let lengths: Vec<f64> = origin.windows(2).map(|w| (w[1] - w[0]).norm()).collect();
    let mut x = origin.clone();
    let mut converged = false;
    // Once clear, the displacement is smoothed once more (the pushes leave
    // a ripple at the samples' spacing) and the rounds go on if that gave
    // some of the clearance back.
    let mut finished = false;
    for _ in 0..ROUNDS {
        let (pushes, worst) = pushes(&x, &s, reach, apart);
        if worst <= margin_mm + CLEAR_MM {
            if finished {
                converged = true;
                break;
            }
            smooth_displacement(&mut x, &origin, FINAL_SMOOTHING_PASSES);
            restore_lengths(&mut x, &lengths);
            finished = true;
            continue;
        }
        for (p, d) in x.iter_mut().zip(&pushes) {
            *p += d;
        }
        smooth_displacement(&mut x, &origin, SMOOTHING_PASSES);
        restore_lengths(&mut x, &lengths);
    }
    let moved: Vec<f64> = x.iter().zip(&origin).map(|(a, b)| (a - b).norm()).collect();
    let cleared = Cleared {
        radius_mm,
        overlap_mm,
        moved_max_mm: moved.iter().copied().fold(0.0, f64::max),
        moved_rms_mm: (moved.iter().map(|m| m * m).sum::<f64>() / moved.len() as f64).sqrt(),
        converged,
    };
    // Read through a cubic spline about 1 mm apart: the relaxed samples,
    // a quarter of the radius apart, would otherwise reach the design as
    // a polyline, bending only at its corners.
    let length = s[count - 1];
    let samples = (length.ceil() as usize).clamp(count, Curve::MAX_POINTS);
    Some((Curve::through(&x, samples).ok()?, cleared))
}

/// `target` sampled a quarter of `radius_mm` apart, and how far a tube of
/// that radius along it passes into itself at the deepest (mm); none where
/// it keeps clear.
fn overlap_along(target: &Curve, radius_mm: f64) -> Option<(Vec<Point>, f64)> {
    let count =
        ((target.length() * SAMPLES_PER_RADIUS / radius_mm).ceil() as usize).clamp(50, 2000);
    let origin = target.resample(count).ok()?.points().to_vec();
    let s = cumulative_length(&origin);
    let overlap_mm = deepest(
        &origin,
        &s,
        2.0 * radius_mm,
        std::f64::consts::PI * radius_mm,
    );
    (overlap_mm > CLEAR_MM).then_some((origin, overlap_mm))
}

/// The pairs of segments of `x` (arc lengths `s` along the target) more
/// than `apart` from each other along it, with their closest points and
/// distance, where that distance is below `reach`.
fn close_pairs(
    x: &[Point],
    s: &[f64],
    reach: f64,
    apart: f64,
) -> Vec<(usize, usize, f64, f64, f64)> {
    let mut pairs = Vec::new();
    for i in 0..x.len() - 1 {
        for j in i + 1..x.len() - 1 {
            if s[j] - s[i + 1] <= apart {
                continue;
            }
            let (u, v, d) = closest([x[i], x[i + 1]], [x[j], x[j + 1]]);
            if d < reach {
                pairs.push((i, j, u, v, d));
            }
        }
    }
    pairs
}

/// How far the deepest pair comes within `reach` (mm; 0 if none does).
fn deepest(x: &[Point], s: &[f64], reach: f64, apart: f64) -> f64 {
    (close_pairs(x, s, reach, apart).iter())
        .map(|&(.., d)| reach - d)
        .fold(0.0, f64::max)
}

/// Every point's push out of the pairs closer than `reach`, averaged over
/// the pairs that push it, and how far the deepest pair comes within it.
fn pushes(x: &[Point], s: &[f64], reach: f64, apart: f64) -> (Vec<Point>, f64) {
    let mut sum = vec![Point::zeros(); x.len()];
    let mut weight = vec![0.0; x.len()];
    let mut worst: f64 = 0.0;
    for (i, j, u, v, d) in close_pairs(x, s, reach, apart) {
        let (p, q) = (x[i] + (x[i + 1] - x[i]) * u, x[j] + (x[j + 1] - x[j]) * v);
        // Coincident closest points: any direction across the first segment.
        let normal = match d > 1e-9 {
            true => (p - q) / d,
            false => any_normal(x[i + 1] - x[i]),
        };
        let half = OVER_RELAXATION * 0.5 * (reach - d);
        worst = worst.max(reach - d);
        for (k, share, sign) in [
            (i, 1.0 - u, 1.0),
            (i + 1, u, 1.0),
            (j, 1.0 - v, -1.0),
            (j + 1, v, -1.0),
        ] {
            sum[k] += normal * (sign * half * share);
            weight[k] += share;
        }
    }
    let pushes = (sum.iter().zip(&weight))
        .map(|(p, w)| if *w > 0.0 { p / w.max(1.0) } else { *p })
        .collect();
    (pushes, worst)
}

/// A unit vector perpendicular to `d`.
fn any_normal(d: Point) -> Point {
    let axis = match d.x.abs() < 0.9 * d.norm() {
        true => Point::x(),
        false => Point::y(),
    };
    d.cross(&axis).try_normalize(1e-12).unwrap_or(Point::z())
}

/// Smooths `x`'s displacement from `origin` along the curve, the ends
/// mirrored (an end moves as its neighbours do).
fn smooth_displacement(x: &mut [Point], origin: &[Point], passes: usize) {
    let n = x.len();
    let mut d: Vec<Point> = x.iter().zip(origin).map(|(a, b)| a - b).collect();
    for _ in 0..passes {
        let previous = d.clone();
        for k in 0..n {
            let (a, b) = (previous[k.saturating_sub(1)], previous[(k + 1).min(n - 1)]);
            d[k] = 0.25 * a + 0.5 * previous[k] + 0.25 * b;
        }
    }
    for ((p, o), d) in x.iter_mut().zip(origin).zip(&d) {
        *p = o + d;
    }
}

/// Brings every segment of `x` back towards its length in `lengths`,
/// both ends moving half the difference (Gauss–Seidel passes).
fn restore_lengths(x: &mut [Point], lengths: &[f64]) {
    for _ in 0..LENGTH_PASSES {
        for (k, &length) in lengths.iter().enumerate() {
            let d = x[k + 1] - x[k];
            let now = d.norm();
            if now > 1e-12 {
                let fix = d * (0.5 * (now - length) / now);
                x[k] += fix;
                x[k + 1] -= fix;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    fn helix(radius: f64, pitch: f64, turns: f64) -> Curve {
        let points = (0..800)
            .map(|i| {
                let a = TAU * turns * i as f64 / 799.0;
                Point::new(radius * a.cos(), radius * a.sin(), pitch * a / TAU)
            })
            .collect();
        Curve::from_points(points).unwrap()
    }

    /// A helix of pitch 10 mm on a tube of radius 12 mm (turns 14 mm into
    /// each other) opens to a pitch of at least the diameter and margin,
    /// keeps its length within 1 %, and a tube along it is clear; a helix
    /// already clear is left as it is.
    #[test]
    fn a_tight_helix_opens_until_its_turns_clear() {
        let target = helix(25.0, 10.0, 2.0);
        let (cleared, report) = clear_of_itself(&target, 12.0, 0.5).expect("needs clearing");
        assert!(report.converged, "{report:?}");
        assert!((report.overlap_mm - 14.0).abs() < 0.5, "{report:?}");
        assert!((cleared.length() / target.length() - 1.0).abs() < 0.005);
        // Smooth: no bend much tighter than the helix's own 25.2 mm (three
        // consecutive samples' circle, about 1 mm apart).
        let tightest = (cleared.points().windows(3))
            .map(|w| {
                let (a, b, c) = (w[1] - w[0], w[2] - w[1], w[2] - w[0]);
                a.norm() * b.norm() * c.norm() / (2.0 * a.cross(&b).norm())
            })
            .fold(f64::INFINITY, f64::min);
        assert!(tightest > 20.0, "a bend of radius {tightest} mm");
        let overlaps = crate::fe::contact::clearance_overlaps(cleared.points(), &[12.0; 2000], 0.0);
        assert!(overlaps.iter().all(|&d| d == 0.0), "{overlaps:?}");
        let z = cleared.points().last().unwrap().z - cleared.points()[0].z;
        assert!(z > 2.0 * 24.5 * 0.9, "two turns rise {z} mm");
        assert!(report.moved_max_mm < 40.0, "{report:?}");
        assert!(clear_of_itself(&helix(25.0, 30.0, 2.0), 12.0, 0.5).is_none());
    }

    /// The trefoil preset is a closed knot: a tube of 15.3 mm (its seed's)
    /// along it passes a whole diameter into itself where its ends meet.
    /// The ends part until clear, the length kept.
    #[test]
    fn a_closed_knots_meeting_ends_part() {
        let trefoil = crate::curve::presets::Preset::from_name("trefoil", serde_json::json!({}))
            .and_then(|p| p.curve(None).map_err(|e| e.to_string()))
            .unwrap();
        let (cleared, report) = clear_of_itself(&trefoil, 15.3, 0.5).expect("needs clearing");
        assert!(
            report.converged && (report.overlap_mm - 30.6).abs() < 0.1,
            "{report:?}"
        );
        assert!((cleared.length() / trefoil.length() - 1.0).abs() < 0.005);
        let overlaps = crate::fe::contact::clearance_overlaps(cleared.points(), &[15.3; 2000], 0.0);
        assert!(overlaps.iter().all(|&d| d == 0.0), "{overlaps:?}");
    }
}
