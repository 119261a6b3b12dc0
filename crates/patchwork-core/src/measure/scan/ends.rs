//! Where the scanned tube ends. A balloon is closed at its tip by a cap
//! and open at its base, where it is clamped; the prediction's centreline
//! runs from the clamp to where the cap begins. Which end is the tip is
//! for the comparison to find (the orientation that fits the prediction);
//! the extraction keeps every section and measures how far the scan
//! reaches past each end section along its tangent: at the tip, to the
//! cap's pole.
//!
//! A cap of radius R ends R past where it begins, and inside it a section
//! at height z has radius √(R² − z²) ≥ R − z, its distance to the pole: the
//! cap begins at the first section, counting in from the pole, whose
//! distance to the pole reaches its radius.

use super::sections::Slab;
use crate::curve::{Point, interpolate};

/// How far the scan's points reach past the end section at `centre`
/// along `outward` (mm; within twice its `radius` of it).
pub fn reach_beyond(slab: &Slab, centre: &Point, outward: &Point, radius: f64) -> f64 {
    let t = outward.normalize();
    let mut near = Vec::new();
    slab.grid
        .within(slab.points, centre, 2.0 * radius, &mut near);
    near.iter()
        .map(|&i| (slab.points[i as usize] - centre).dot(&t))
        .fold(0.0, f64::max)
}

/// The centreline `centres` (with `radii`) cut where the cap at its last
/// end begins, the pole `beyond` past the last section: `cap_height` short
/// of the pole when the cap's height is known (the prediction's), else
/// where a hemisphere would begin; with the radius at each point kept.
pub fn without_cap(
    centres: &[Point],
    radii: &[f64],
    beyond: f64,
    cap_height: Option<f64>,
) -> (Vec<Point>, Vec<f64>) {
    let n = centres.len();
    let mut s = vec![0.0];
    for w in centres.windows(2) {
        s.push(s[s.len() - 1] + (w[1] - w[0]).norm());
    }
    let pole = s[n - 1] + beyond;
    let gap = |i: usize| pole - s[i] - radii[i];
    let start = match cap_height {
        Some(height) => (pole - height).clamp(0.0, s[n - 1]),
        None => hemisphere_start(&s, &gap),
    };
    if start >= s[n - 1] {
        return (centres.to_vec(), radii.to_vec());
    }
    let k = s.partition_point(|&v| v < start).clamp(1, n - 1);
    let t = ((start - s[k - 1]) / (s[k] - s[k - 1]).max(1e-12)).clamp(0.0, 1.0);
    let mut points: Vec<Point> = centres[..k].to_vec();
    let mut radius: Vec<f64> = radii[..k].to_vec();
    points.push(centres[k - 1].lerp(&centres[k], t));
    radius.push(interpolate(&s, radii, start));
    (points, radius)
}

/// Where a hemispherical cap would begin: counting in from the pole, the
/// first section whose distance to the pole reaches its radius (linear
/// between sections); the last section when it is short of the cap.
fn hemisphere_start(s: &[f64], gap: &dyn Fn(usize) -> f64) -> f64 {
    let n = s.len();
    if gap(n - 1) >= 0.0 {
        return s[n - 1];
    }
    (1..n).rev().find(|&i| gap(i - 1) >= 0.0).map_or(0.0, |i| {
        let (a, b) = (gap(i), gap(i - 1));
        s[i] + (s[i - 1] - s[i]) * (-a / (b - a))
    })
}
