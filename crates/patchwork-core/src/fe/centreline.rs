//! The inflated centreline: cross-section rings at equally spaced *material*
//! axial positions, each fitted with a circle (best-fit plane by SVD, then the
//! algebraic Kåsa fit in that plane); the centres form the centreline.

use nalgebra::{Matrix3, Vector3};

use super::mesh::TubeMesh;
use crate::curve::Point;

/// One fitted cross-section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ring {
    /// Material axial position (uninflated Y, mm).
    pub y: f64,
    pub centre: Point,
    pub radius: f64,
}

/// Rings at `count` material positions from the base to the cap (inclusive).
pub fn rings(mesh: &TubeMesh, x: &[Point], count: usize) -> Vec<Ring> {
    let count = count.max(2);
    (0..count)
        .map(|i| {
            let y = mesh.length * i as f64 / (count - 1) as f64;
            let points = ring_points(mesh, x, y);
            let (centre, radius) = fit_circle(&points);
            Ring { y, centre, radius }
        })
        .collect()
}

/// Deformed positions of the material ring at axial position `y`, interpolated
/// between the two mesh rings around it.
pub fn ring_points(mesh: &TubeMesh, x: &[Point], y: f64) -> Vec<Point> {
    let k = mesh
        .ring_y
        .partition_point(|&r| r <= y)
        .clamp(1, mesh.ring_y.len() - 1);
    let (y0, y1) = (mesh.ring_y[k - 1], mesh.ring_y[k]);
    let t = ((y - y0) / (y1 - y0)).clamp(0.0, 1.0);
    (0..mesh.around)
        .map(|j| x[(k - 1) * mesh.around + j] * (1.0 - t) + x[k * mesh.around + j] * t)
        .collect()
}

/// Least-squares circle through 3D points: plane by SVD of the centred points,
/// then Kåsa's linear fit x² + y² + D x + E y + F = 0 in plane coordinates.
pub fn fit_circle(points: &[Point]) -> (Point, f64) {
    let n = points.len() as f64;
    let mean = points.iter().sum::<Point>() / n;
    let mut scatter = Matrix3::zeros();
    for p in points {
        let d = p - mean;
        scatter += d * d.transpose();
    }
    let eigen = scatter.symmetric_eigen();
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
    let e1: Vector3<f64> = eigen.eigenvectors.column(order[0]).into();
    let e2: Vector3<f64> = eigen.eigenvectors.column(order[1]).into();
    let mut ata = Matrix3::zeros();
    let mut atb = Vector3::zeros();
    for p in points {
        let d = p - mean;
        let (u, v) = (d.dot(&e1), d.dot(&e2));
        let row = Vector3::new(u, v, 1.0);
        ata += row * row.transpose();
        atb += row * -(u * u + v * v);
    }
    match ata.lu().solve(&atb) {
        Some(s) => {
            let (cu, cv) = (-s[0] / 2.0, -s[1] / 2.0);
            let radius = (cu * cu + cv * cv - s[2]).max(0.0).sqrt();
            (mean + e1 * cu + e2 * cv, radius)
        }
        None => (mean, 0.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_a_tilted_circle_exactly() {
        let centre = Point::new(3.0, -2.0, 7.0);
        let rotation = nalgebra::Rotation3::from_euler_angles(0.4, -0.9, 1.7);
        let points: Vec<Point> = (0..24)
            .map(|i| {
                let t = i as f64 * 0.26; // uneven coverage, not a full turn
                centre + rotation * Point::new(5.0 * t.cos(), 5.0 * t.sin(), 0.0)
            })
            .collect();
        let (c, r) = fit_circle(&points);
        assert!((c - centre).norm() < 1e-9);
        assert!((r - 5.0).abs() < 1e-9);
    }
}
