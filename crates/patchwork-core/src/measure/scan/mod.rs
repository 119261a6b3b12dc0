//! A scanned balloon's centreline: from a point cloud of the inflated
//! surface (millions of points, noisy, with holes where the scanner did not
//! see) to the tube's axis and its radius along it.
//!
//! 1. Voxel downsampling (`grid.rs`), the voxel chosen from the scan's
//!    extent and density.
//! 2. Distances along the surface from one end (`geodesic.rs`): the graph
//!    of neighbouring voxels, its largest part, the farthest point from an
//!    arbitrary one (an end), Dijkstra from it.
//! 3. A first centreline through the centroids of bands of equal distance
//!    (`skeleton.rs`), which also gives the tube's radius.
//! 4. Cross-sections (`sections.rs`): the scan's points in a slab normal
//!    to the centreline, near it in space and along the surface, fitted
//!    with a circle; the centres are the new centreline, until it stops
//!    moving.
//! 5. The ends (`ends.rs`): how far the scan reaches past each, and the
//!    ring there (`sections::edge_through`: at the open base, the scan's
//!    edge, where the balloon is clamped); the cap is cut off once the
//!    comparison knows which end is the tip
//!    ([`ScanCentreline::base_to_tip`]), which begins at the base's ring.

mod ends;
mod geodesic;
mod grid;
pub mod read;
mod sections;
mod skeleton;

use serde::{Deserialize, Serialize};

use self::geodesic::{SurfaceGraph, farthest};
use self::grid::{Grid, voxel_centroids};
use self::sections::{Past, Section, Slab, fit_section};
use self::skeleton::skeleton;
use crate::curve::{Curve, Point};

/// Fewest points a scan may have.
pub const MIN_SCAN_POINTS: usize = 1000;

/// Most points a scan may have (about 1 GB of them in memory).
pub const MAX_SCAN_POINTS: usize = 30_000_000;

/// Voxels across the scan's bounding-box diagonal, at least.
const VOXELS_ACROSS: f64 = 400.0;

/// Fewest scan points per voxel on average: a sparser scan gets larger
/// voxels, so that neighbouring voxels join up over the surface.
const POINTS_PER_VOXEL: f64 = 4.0;

/// Points of the scan the cross-sections are fitted to, at most (every
/// k-th point of a larger scan).
const SECTION_POINTS: usize = 400_000;

/// Rounds of fitting cross-sections, at most.
const MAX_ROUNDS: usize = 6;

/// A section fitted worse than this fraction of its radius (RMS) is not a
/// circle.
const MAX_RELATIVE_RESIDUAL: f64 = 0.15;

/// Why a scan gives no centreline.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScanError {
    #[error("the scan has {found} points; at least {MIN_SCAN_POINTS} are needed")]
    TooFewPoints { found: usize },
    #[error("the scan has {found} points; at most {MAX_SCAN_POINTS} are accepted")]
    TooManyPoints { found: usize },
    #[error("point {index} of the scan is not finite")]
    NonFinite { index: usize },
    #[error("the scan does not look like a tube: {0}")]
    NotATube(String),
    #[error("{0}")]
    Read(String),
}

/// A ring of the scan at one of its ends.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rim {
    pub centre_mm: [f64; 3],
    pub radius_mm: f64,
}

/// What a scan gave.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScanCentreline {
    /// The tube's axis from one end to the other (mm), at about a quarter
    /// of its radius apart; which end is the base is for the comparison to
    /// find.
    pub centreline_mm: Vec<[f64; 3]>,
    /// The fitted radius at each point of the centreline (mm).
    pub radius_mm: Vec<f64>,
    /// How far the scan reaches past the first and the last section along
    /// the centreline (mm): at the tip, to the cap's pole.
    pub reach_beyond_mm: [f64; 2],
    /// The circle through the scan's outermost points past each end
    /// section: at an open end, the rim where the balloon is clamped.
    pub rims: [Option<Rim>; 2],
    /// Points in the scan, and those of its largest connected part.
    pub points: usize,
    pub points_on_tube: usize,
    /// The median RMS distance of a section's points from its circle (mm):
    /// the scan's noise, roughly.
    pub section_residual_mm: f64,
    /// The voxel the surface was sampled on for the distances along it (mm).
    pub voxel_mm: f64,
}

impl ScanCentreline {
    /// The same centreline with its last end (`tip_last`) or its first as
    /// the tip, cut where the cap begins ([`ends::without_cap`]: the
    /// predicted cap's height short of the pole when known), begun at the
    /// open base's rim, and run base to tip.
    pub fn base_to_tip(&self, tip_last: bool, cap_height: Option<f64>) -> ScanCentreline {
        let mut centres: Vec<Point> = self.centreline_mm.iter().map(|p| Point::from(*p)).collect();
        let mut radii = self.radius_mm.clone();
        let mut beyond = self.reach_beyond_mm;
        if !tip_last {
            centres.reverse();
            radii.reverse();
            beyond.reverse();
        }
        let (mut centres, mut radii) = ends::without_cap(&centres, &radii, beyond[1], cap_height);
        let mut rims = self.rims;
        if !tip_last {
            rims.reverse();
        }
        // The open base: the centreline begins at the rim's centre.
        if let Some(rim) = rims[0].filter(|_| centres.len() > 1) {
            let outward = centres[0] - centres[1];
            let centre = Point::from(rim.centre_mm);
            if (centre - centres[0]).dot(&outward) > 0.0 {
                centres.insert(0, centre);
                radii.insert(0, rim.radius_mm);
            }
        }
        ScanCentreline {
            centreline_mm: centres.iter().map(|p| [p.x, p.y, p.z]).collect(),
            radius_mm: radii,
            reach_beyond_mm: [beyond[0], 0.0],
            rims: [None, None],
            ..self.clone()
        }
    }

    pub fn curve(&self) -> Result<Curve, crate::CurveError> {
        Curve::from_points(
            self.centreline_mm
                .iter()
                .map(|p| Point::new(p[0], p[1], p[2]))
                .collect(),
        )
    }
}

/// The centreline of the tube `points` were scanned from.
pub fn centreline_from_scan(points: &[Point]) -> Result<ScanCentreline, ScanError> {
    check(points)?;
    let voxel = voxel_size(points);
    let (centroids, voxel_of) = voxel_centroids(points, voxel);
    let graph = SurfaceGraph::new(&centroids, 2.5 * voxel);
    let (start, _) = graph.largest_part();
    let end = farthest(&graph.distances(start));
    let along = graph.distances(end);
    let first = skeleton(&centroids, &along, 2.0 * voxel)
        .map_err(|e| ScanError::NotATube(format!("no first centreline ({e})")))?;
    let radius = first.radius;
    if radius.is_nan() || radius <= 0.0 || first.curve.length() < 4.0 * radius {
        return Err(ScanError::NotATube(format!(
            "its surface reaches {:.1} mm from end to end against a radius of {radius:.1} mm",
            first.curve.length()
        )));
    }
    // Every k-th point for the sections: a slab holds thousands of them
    // still, and the fits' time grows with the points near each.
    let stride = points.len().div_ceil(SECTION_POINTS).max(1);
    let sampled: Vec<Point> = points.iter().step_by(stride).copied().collect();
    let levels: Vec<f64> = voxel_of
        .iter()
        .step_by(stride)
        .map(|&v| along[v as usize])
        .collect();
    let reach = 1.6 * radius;
    let grid = Grid::new(&sampled, reach);
    let slab = Slab {
        points: &sampled,
        grid: &grid,
        levels: &levels,
        half_width: (radius / 8.0).max(voxel),
        reach,
        band: 4.0 * radius,
    };
    let sections = refine(&slab, first.curve.points().to_vec(), first.levels)?;
    let mut residuals: Vec<f64> = sections.iter().map(|s| s.residual).collect();
    residuals.sort_by(f64::total_cmp);
    let n = sections.len();
    // Each end section and its inner neighbour, which give the end's
    // outward direction.
    let end_pairs = [(0, 1.min(n - 1)), (n - 1, n.saturating_sub(2))];
    let reach_beyond_mm = end_pairs.map(|(i, inner)| {
        let (a, b) = (&sections[i], &sections[inner]);
        ends::reach_beyond(&slab, &a.centre, &(a.centre - b.centre), a.radius)
    });
    let rims = rims(&slab, &sections, end_pairs, reach_beyond_mm);
    Ok(ScanCentreline {
        centreline_mm: sections
            .iter()
            .map(|s| s.centre)
            .map(|p| [p.x, p.y, p.z])
            .collect(),
        radius_mm: sections.iter().map(|s| s.radius).collect(),
        reach_beyond_mm,
        rims,
        points: points.len(),
        points_on_tube: voxel_of
            .iter()
            .filter(|&&v| along[v as usize].is_finite())
            .count(),
        section_residual_mm: residuals[residuals.len() / 2],
        voxel_mm: voxel,
    })
}

/// The rings past the end sections `(end, inner neighbour)`, `beyond`
/// them: the scan's edge where it has one (the clamp's ring of an open
/// end), else the circle through the points of the slab there, in its
/// mid-plane.
fn rims(
    slab: &Slab,
    sections: &[Section],
    ends: [(usize, usize); 2],
    beyond: [f64; 2],
) -> [Option<Rim>; 2] {
    let rim = |(i, inner): (usize, usize), beyond: f64| {
        let (a, b) = (&sections[i], &sections[inner]);
        let past = Past {
            centre: &a.centre,
            tangent: &(a.centre - b.centre).normalize(),
            along: (beyond - 2.0 * slab.half_width).max(0.0)..=beyond,
            reach: 2.0 * a.radius,
        };
        let ring =
            sections::edge_through(slab, &past).or_else(|| sections::ring_through(slab, &past));
        ring.map(|(c, r)| Rim {
            centre_mm: [c.x, c.y, c.z],
            radius_mm: r,
        })
    };
    [rim(ends[0], beyond[0]), rim(ends[1], beyond[1])]
}

fn check(points: &[Point]) -> Result<(), ScanError> {
    if points.len() < MIN_SCAN_POINTS {
        return Err(ScanError::TooFewPoints {
            found: points.len(),
        });
    }
    if points.len() > MAX_SCAN_POINTS {
        return Err(ScanError::TooManyPoints {
            found: points.len(),
        });
    }
    match points.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
        Some(index) => Err(ScanError::NonFinite { index }),
        None => Ok(()),
    }
}

/// The voxel: the bounding box's diagonal over `VOXELS_ACROSS`, grown
/// while the voxels hold fewer than `POINTS_PER_VOXEL` points on average.
fn voxel_size(points: &[Point]) -> f64 {
    let (lo, hi) = points.iter().fold(
        (
            Point::repeat(f64::INFINITY),
            Point::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    );
    let diagonal = (hi - lo).norm().max(1e-9);
    let mut voxel = diagonal / VOXELS_ACROSS;
    // A sample of the points is enough to judge the density.
    let step = (points.len() / 200_000).max(1);
    let sample: Vec<Point> = points.iter().step_by(step).copied().collect();
    while voxel < diagonal / 20.0 {
        let occupied = Grid::new(&sample, voxel).cells().count() as f64;
        if (sample.len() as f64) / occupied >= POINTS_PER_VOXEL / step as f64 {
            break;
        }
        voxel *= 1.5;
    }
    voxel
}

/// Cross-sections along the centreline until it stops moving.
fn refine(
    slab: &Slab,
    mut centres: Vec<Point>,
    mut levels: Vec<f64>,
) -> Result<Vec<Section>, ScanError> {
    let mut sections = Vec::new();
    for _ in 0..MAX_ROUNDS {
        let tangents = tangents(&centres);
        let fitted: Vec<(Section, f64, f64)> = centres
            .iter()
            .zip(&tangents)
            .zip(&levels)
            .filter_map(|((c, t), &level)| {
                fit_section(slab, c, t, level)
                    .filter(|s| s.residual < MAX_RELATIVE_RESIDUAL * s.radius)
                    .map(|s| (s, level, (s.centre - c).norm()))
            })
            .collect();
        if fitted.len() < Curve::MIN_POINTS || 2 * fitted.len() < centres.len() {
            return Err(ScanError::NotATube(format!(
                "only {} of {} cross-sections are circles",
                fitted.len(),
                centres.len()
            )));
        }
        let moved = fitted.iter().map(|f| f.2).fold(0.0, f64::max);
        centres = fitted.iter().map(|f| f.0.centre).collect();
        levels = fitted.iter().map(|f| f.1).collect();
        sections = fitted.into_iter().map(|f| f.0).collect();
        if moved < 0.01 {
            break;
        }
    }
    Ok(sections)
}

/// Unit tangents by differences two sections either side (one-sided, as
/// wide, at the ends): a section's centre is noisy, and a tilted slab
/// through a flaring neck is off centre.
fn tangents(centres: &[Point]) -> Vec<Point> {
    let n = centres.len();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(2), (i + 2).min(n - 1));
            let (a, b) = match (b - a) < 2 {
                true => (a.saturating_sub(1), (b + 1).min(n - 1)),
                false => (a, b),
            };
            (centres[b] - centres[a]).normalize()
        })
        .collect()
}

#[cfg(test)]
mod tests;
