//! The first-order 3D Hilbert curve on a cube with circular fillets: seven
//! edges joined by quarter circles.

use std::f64::consts::{FRAC_PI_2, PI};

use super::super::{Curve, CurveError, Point};

/// One piece of a line-and-fillet path.
enum Piece {
    Line {
        from: Point,
        direction: Point,
        length: f64,
    },
    Fillet {
        corner: Point,
        incoming: Point,
        outgoing: Point,
        radius: f64,
    },
}

impl Piece {
    fn length(&self) -> f64 {
        match self {
            Piece::Line { length, .. } => *length,
            Piece::Fillet { radius, .. } => FRAC_PI_2 * radius,
        }
    }

    fn at(&self, s: f64) -> Point {
        match self {
            Piece::Line {
                from, direction, ..
            } => from + direction * s,
            Piece::Fillet {
                corner,
                incoming,
                outgoing,
                radius,
            } => {
                // Quarter circle tangent to both edges at distance r from the corner,
                // centre c = corner − r·incoming + r·outgoing.
                let alpha = s / radius;
                let centre = corner - incoming * *radius + outgoing * *radius;
                centre + *radius * (incoming * alpha.sin() - outgoing * alpha.cos())
            }
        }
    }
}

pub(super) fn hilbert(edge: f64, radius: f64, n: usize) -> Result<Curve, CurveError> {
    // Cube vertices in Gray-code order (the first-order 3D Hilbert curve), in the
    // same order as the authors' reference curve.
    let unit = [
        [0., 0., 0.],
        [0., 1., 0.],
        [0., 1., 1.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [1., 1., 0.],
        [1., 0., 0.],
    ];
    let vertex: Vec<Point> = unit.iter().map(|v| Point::from(*v) * edge).collect();
    let mut pieces = Vec::new();
    let mut start = vertex[0];
    for i in 1..vertex.len() {
        let direction = (vertex[i] - vertex[i - 1]).normalize();
        let is_last = i + 1 == vertex.len();
        let end = if is_last {
            vertex[i]
        } else {
            vertex[i] - direction * radius
        };
        pieces.push(Piece::Line {
            from: start,
            direction,
            length: (end - start).norm(),
        });
        if !is_last {
            let outgoing = (vertex[i + 1] - vertex[i]).normalize();
            pieces.push(Piece::Fillet {
                corner: vertex[i],
                incoming: direction,
                outgoing,
                radius,
            });
            start = vertex[i] + outgoing * radius;
        }
    }
    let total: f64 = pieces.iter().map(Piece::length).sum();
    let mut points = Vec::with_capacity(n);
    for i in 0..n {
        let mut s = total * i as f64 / (n - 1) as f64;
        let mut chosen = pieces.last().expect("seven edges");
        for piece in &pieces {
            if s <= piece.length() {
                chosen = piece;
                break;
            }
            s -= piece.length();
        }
        points.push(chosen.at(s.min(chosen.length())));
    }
    Curve::from_points(points)
}

/// Length of the ideal filleted Hilbert curve: 7 edges, 6 quarter-circle corners.
pub fn hilbert_length(edge: f64, radius: f64) -> f64 {
    7.0 * edge - 6.0 * (2.0 * radius - PI * radius / 2.0)
}
