//! Cross-sections of the scanned tube: the points in a thin slab normal to
//! the centreline, the circle that fits them, and its centre.
//!
//! The circle is fitted in the slab's plane: Kåsa's algebraic fit
//! (x² + y² + D x + E y + F = 0, linear least squares) as the start, then
//! Gauss–Newton on the geometric distances |q − c| − R, which Kåsa's fit
//! biases when noise is large or only part of the circle was scanned.

use nalgebra::{Matrix3, Vector3};

use super::grid::Grid;
use crate::curve::Point;

/// A fitted cross-section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    pub centre: Point,
    pub radius: f64,
    /// RMS of the points' distances from the circle (mm).
    pub residual: f64,
    pub points: usize,
}

/// Where to look for a section's points.
pub struct Slab<'a> {
    pub points: &'a [Point],
    pub grid: &'a Grid,
    /// Each point's distance along the surface from the first end.
    pub levels: &'a [f64],
    /// Half the slab's thickness along the tangent (mm).
    pub half_width: f64,
    /// How far from the centre its points may be (mm).
    pub reach: f64,
    /// How far their distance along the surface may be from the section's
    /// (mm): other passes of the tube nearby are further along it.
    pub band: f64,
}

/// Fewest points a section is fitted to.
const MIN_POINTS: usize = 24;

/// The section through `centre` normal to `tangent` at distance `level`
/// along the surface; none where too few points were scanned or they do
/// not go at least half round.
pub fn fit_section(slab: &Slab, centre: &Point, tangent: &Point, level: f64) -> Option<Section> {
    let mut found = Vec::new();
    slab.grid
        .within(slab.points, centre, slab.reach, &mut found);
    let (e1, e2) = plane_basis(tangent);
    let planar: Vec<(f64, f64)> = found
        .iter()
        .map(|&i| i as usize)
        .filter(|&i| (slab.levels[i] - level).abs() <= slab.band)
        .map(|i| slab.points[i] - centre)
        .filter(|d| d.dot(tangent).abs() <= slab.half_width)
        .map(|d| (d.dot(&e1), d.dot(&e2)))
        .collect();
    let (a, b, radius, residual) = fit_planar(&planar)?;
    Some(Section {
        centre: centre + e1 * a + e2 * b,
        radius,
        residual,
        points: planar.len(),
    })
}

/// Where a ring past an end section looks: its points within `reach` of
/// `centre` whose offset along `tangent` lies in `along` (mm).
pub struct Past<'a> {
    pub centre: &'a Point,
    pub tangent: &'a Point,
    pub along: std::ops::RangeInclusive<f64>,
    pub reach: f64,
}

impl Past<'_> {
    /// The points, each as (u, v) in the plane normal to the tangent (its
    /// basis `plane_basis`) and h along it, from the centre.
    fn points(&self, slab: &Slab) -> Vec<(f64, f64, f64)> {
        let mut found = Vec::new();
        slab.grid
            .within(slab.points, self.centre, self.reach, &mut found);
        let (e1, e2) = plane_basis(self.tangent);
        found
            .iter()
            .map(|&i| slab.points[i as usize] - self.centre)
            .map(|d| (d.dot(&e1), d.dot(&e2), d.dot(self.tangent)))
            .filter(|(_, _, h)| self.along.contains(h))
            .collect()
    }

    /// The point at (u, v, h) from the centre, in space.
    fn at(&self, (u, v, h): (f64, f64, f64)) -> Point {
        let (e1, e2) = plane_basis(self.tangent);
        self.centre + e1 * u + e2 * v + self.tangent * h
    }
}

/// The circle through the points `past` looks at: its centre (in space, in
/// the mid-plane of `along`) and radius.
pub fn ring_through(slab: &Slab, past: &Past) -> Option<(Point, f64)> {
    let planar: Vec<(f64, f64)> = past.points(slab).iter().map(|&(u, v, _)| (u, v)).collect();
    let (a, b, radius, _) = fit_planar(&planar)?;
    let offset = 0.5 * (past.along.start() + past.along.end());
    Some((past.at((a, b, offset)), radius))
}

/// Sectors around the tube that [`edge_through`] takes the outermost point
/// of, and how many of them must hold points.
const EDGE_SECTORS: usize = 72;
const EDGE_COVERED: usize = 36;

/// The open edge of the scan past `centre` along `tangent`: among the
/// points within `reach` whose offset along `tangent` lies in `along`, the
/// one reaching farthest out in each of [`EDGE_SECTORS`] sectors around
/// the circle they fit; less those well below the plane through them
/// (where a hole hid the edge, the farthest point seen is on the tube
/// behind it); the circle through the rest (fitted in the plane normal to
/// `tangent`, going at least half round), at the height of their plane.
/// Where the scan ends at a clamp, that is the clamp's ring, wherever the
/// tube flares behind it and however the ring tilts from the end section;
/// none where fewer than [`EDGE_COVERED`] sectors hold points.
pub fn edge_through(slab: &Slab, past: &Past) -> Option<(Point, f64)> {
    let points = past.points(slab);
    let planar: Vec<(f64, f64)> = points.iter().map(|&(u, v, _)| (u, v)).collect();
    let (a, b, _, _) = fit_planar(&planar)?;
    let edge = outermost_per_sector(&points, (a, b));
    if edge.len() < EDGE_COVERED {
        return None;
    }
    let plane = plane_through(&edge)?;
    let below: Vec<f64> = edge.iter().map(|p| plane_height(&plane, p) - p.2).collect();
    let mut spread: Vec<f64> = below.iter().map(|d| d.abs()).collect();
    spread.sort_by(f64::total_cmp);
    // 3 robust standard deviations (1.4826 × the median absolute residual).
    let cut = 3.0 * 1.4826 * spread[spread.len() / 2];
    let kept: Vec<(f64, f64, f64)> = (edge.iter().zip(&below))
        .filter(|(_, d)| **d <= cut)
        .map(|(p, _)| *p)
        .collect();
    let ring: Vec<(f64, f64)> = kept.iter().map(|&(u, v, _)| (u, v)).collect();
    let (ka, kb, radius, _) = fit_planar(&ring)?;
    let height = plane_height(&plane_through(&kept)?, &(ka, kb, 0.0));
    Some((past.at((ka, kb, height)), radius))
}

/// In each of [`EDGE_SECTORS`] sectors around (a, b), the point (u, v, h)
/// with the largest h.
fn outermost_per_sector(points: &[(f64, f64, f64)], (a, b): (f64, f64)) -> Vec<(f64, f64, f64)> {
    let mut outermost: Vec<Option<(f64, f64, f64)>> = vec![None; EDGE_SECTORS];
    for &(u, v, h) in points {
        let turn = (v - b).atan2(u - a) / std::f64::consts::TAU + 0.5;
        let sector = ((turn * EDGE_SECTORS as f64) as usize).min(EDGE_SECTORS - 1);
        if outermost[sector].is_none_or(|(_, _, best)| h > best) {
            outermost[sector] = Some((u, v, h));
        }
    }
    outermost.into_iter().flatten().collect()
}

/// The plane h = h₀ + p u + q v through `points` (least squares).
fn plane_through(points: &[(f64, f64, f64)]) -> Option<Vector3<f64>> {
    let (mut ata, mut atb) = (Matrix3::zeros(), Vector3::zeros());
    for &(u, v, h) in points {
        let row = Vector3::new(1.0, u, v);
        ata += row * row.transpose();
        atb += row * h;
    }
    ata.lu().solve(&atb)
}

fn plane_height(plane: &Vector3<f64>, &(u, v, _): &(f64, f64, f64)) -> f64 {
    plane[0] + plane[1] * u + plane[2] * v
}

/// The circle fitted to points in a plane: centre (a, b), radius and the
/// RMS of their distances from it; none for too few points, or points
/// that do not go half way round.
fn fit_planar(planar: &[(f64, f64)]) -> Option<(f64, f64, f64, f64)> {
    if planar.len() < MIN_POINTS {
        return None;
    }
    let (a, b, radius) = geometric_fit(planar, kasa_fit(planar)?)?;
    if !covers_half(planar, a, b) {
        return None;
    }
    let residual = (planar
        .iter()
        .map(|(u, v)| ((u - a).hypot(v - b) - radius).powi(2))
        .sum::<f64>()
        / planar.len() as f64)
        .sqrt();
    Some((a, b, radius, residual))
}

/// Two unit vectors normal to `t` and to each other.
fn plane_basis(t: &Point) -> (Point, Point) {
    let helper = match t.x.abs() < 0.9 {
        true => Vector3::x(),
        false => Vector3::y(),
    };
    let e1 = t.cross(&helper).normalize();
    (e1, t.cross(&e1).normalize())
}

/// Kåsa's circle: centre (a, b) and radius.
fn kasa_fit(q: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    let (mut ata, mut atb) = (Matrix3::zeros(), Vector3::zeros());
    for &(u, v) in q {
        let row = Vector3::new(u, v, 1.0);
        ata += row * row.transpose();
        atb += row * -(u * u + v * v);
    }
    let s = ata.lu().solve(&atb)?;
    let (a, b) = (-s[0] / 2.0, -s[1] / 2.0);
    let r2 = a * a + b * b - s[2];
    (r2 > 0.0).then(|| (a, b, r2.sqrt()))
}

/// Gauss–Newton on rᵢ = |qᵢ − c| − R from `start`.
fn geometric_fit(q: &[(f64, f64)], start: (f64, f64, f64)) -> Option<(f64, f64, f64)> {
    let (mut a, mut b, mut r) = start;
    for _ in 0..8 {
        let (mut jtj, mut jtr) = (Matrix3::zeros(), Vector3::zeros());
        for &(u, v) in q {
            let d = (u - a).hypot(v - b).max(1e-12);
            let row = Vector3::new(-(u - a) / d, -(v - b) / d, -1.0);
            jtj += row * row.transpose();
            jtr += row * (d - r);
        }
        let step = jtj.lu().solve(&(-jtr))?;
        a += step[0];
        b += step[1];
        r += step[2];
        if step.norm() < 1e-9 * r.abs().max(1.0) {
            break;
        }
    }
    (r.is_finite() && r > 0.0).then_some((a, b, r))
}

/// Whether the points go at least half way round the centre (a, b): the
/// widest empty gap between their angles is under 180°.
fn covers_half(q: &[(f64, f64)], a: f64, b: f64) -> bool {
    let mut angles: Vec<f64> = q.iter().map(|(u, v)| (v - b).atan2(u - a)).collect();
    angles.sort_by(f64::total_cmp);
    let wrap = angles[0] + std::f64::consts::TAU - angles[angles.len() - 1];
    let widest = angles.windows(2).map(|w| w[1] - w[0]).fold(wrap, f64::max);
    widest < std::f64::consts::PI
}
