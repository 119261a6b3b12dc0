//! A first centreline: the scanned surface cut into bands by the distance
//! along it from one end, each band's centroid a point of the axis.
//!
//! On a tube, the surface points at one distance from an end form a ring
//! around the axis (skewed by at most half the circumference at a bend),
//! so the centroids of narrow bands trace the axis. The mean distance of a
//! band's points from its centroid is about the tube's radius.

use crate::curve::{Curve, CurveError, Point, interpolate};

/// One band: the distance along the surface at its middle, its centroid,
/// and the mean distance of its points from the centroid.
#[derive(Debug, Clone, Copy)]
struct Band {
    level: f64,
    centroid: Point,
    spread: f64,
    count: usize,
}

/// The first centreline through the band centroids of `points` (voxel
/// centroids) at `distance` from one end, in bands `width` wide: smoothed
/// over the radius found and resampled at a quarter of it; with the
/// distance along the surface at each of its points, and the radius.
pub struct Skeleton {
    pub curve: Curve,
    pub levels: Vec<f64>,
    pub radius: f64,
}

/// Bands holding fewer points are skipped (a hole in the scan).
const MIN_BAND_POINTS: usize = 6;

pub fn skeleton(points: &[Point], distance: &[f64], width: f64) -> Result<Skeleton, CurveError> {
    let bands = bands(points, distance, width);
    let mut spreads: Vec<f64> = bands.iter().map(|b| b.spread).collect();
    spreads.sort_by(f64::total_cmp);
    let radius = spreads.get(spreads.len() / 2).copied().unwrap_or(0.0);
    let first = Curve::from_points(bands.iter().map(|b| b.centroid).collect())?;
    let smoothed = first.smoothed(radius).unwrap_or(first.clone());
    let spacing = (radius / 4.0).max(smoothed.length() / (Curve::MAX_POINTS / 10) as f64);
    let n = ((smoothed.length() / spacing).ceil() as usize + 1).max(Curve::MIN_POINTS);
    let curve = smoothed.resample(n)?;
    // Each point's level, by its fraction of the length along the bands.
    let band_levels: Vec<f64> = bands.iter().map(|b| b.level).collect();
    let fractions: Vec<f64> = first
        .arc_length()
        .iter()
        .map(|s| s / first.length())
        .collect();
    let levels = (0..n)
        .map(|i| interpolate(&fractions, &band_levels, i as f64 / (n - 1) as f64))
        .collect();
    Ok(Skeleton {
        curve,
        levels,
        radius,
    })
}

/// The bands in order of distance, those with enough points.
fn bands(points: &[Point], distance: &[f64], width: f64) -> Vec<Band> {
    let top = distance
        .iter()
        .filter(|d| d.is_finite())
        .fold(0.0_f64, |a, &d| a.max(d));
    let count = (top / width).floor() as usize + 1;
    let mut sums = vec![(Point::zeros(), 0usize); count];
    let band_of = |d: f64| (d / width).floor() as usize;
    for (p, &d) in points.iter().zip(distance).filter(|(_, d)| d.is_finite()) {
        let entry = &mut sums[band_of(d).min(count - 1)];
        entry.0 += p;
        entry.1 += 1;
    }
    let centroids: Vec<Point> = sums
        .iter()
        .map(|(sum, n)| sum / (*n).max(1) as f64)
        .collect();
    let mut spread = vec![0.0; count];
    for (p, &d) in points.iter().zip(distance).filter(|(_, d)| d.is_finite()) {
        let k = band_of(d).min(count - 1);
        spread[k] += (p - centroids[k]).norm();
    }
    (0..count)
        .filter(|&k| sums[k].1 >= MIN_BAND_POINTS)
        .map(|k| Band {
            level: (k as f64 + 0.5) * width,
            centroid: centroids[k],
            spread: spread[k] / sums[k].1 as f64,
            count: sums[k].1,
        })
        .filter(|b| b.count >= MIN_BAND_POINTS)
        .collect()
}
