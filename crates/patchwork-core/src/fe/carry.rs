//! Warm starts across meshes: a converged state carried onto another mesh of
//! the same balloon radius, as the start of its Newton solve.
//!
//! Every node of the new mesh is placed where the old state puts the same
//! material point, found by its material coordinates:
//! - a tube node by its fraction of the length Y/L₀ and its angle t around:
//!   the old rings on either side of that fraction are interpolated axially
//!   (linear in Y), then the interpolated ring around (below);
//! - a cap node by its polar angle φ from the rim (0) to the pole (π/2) and
//!   its angle t, between the old cap rings on either side of φ (the rim is
//!   the tube's top ring, the pole a single node).
//!
//! Around a ring, the point at angle t lies between the old nodes j and j + 1
//! that bracket it, at weight w: the offset from the ring's centre c is
//! interpolated in direction and, separately, in length,
//! p = c + (|d₀|(1 − w) + |d₁| w) · n̂, n̂ = unit((1 − w) d₀ + w d₁),
//! so a coarse section carried onto a finer one keeps its radius instead of
//! cutting the chords (a 30-sided section's chord midpoints sit 0.5 % inside).
//!
//! Exact where the meshes share their rings and sections; otherwise a start a
//! few Newton iterations from the new mesh's solution: a graded mesh whose
//! fine zones moved, a balloon cut slightly longer or shorter (the refine's
//! length steps), or a finer mesh (the corrected refine's finer model started
//! from the verification model's state).

use super::centreline::ring_points;
use super::mesh::TubeMesh;
use crate::curve::Point;

/// Converged positions `x` on mesh `old` carried onto `mesh`; none if the
/// balloon radius differs.
pub(super) fn carried_state(old: &TubeMesh, x: &[Point], mesh: &TubeMesh) -> Option<Vec<Point>> {
    if old.radius != mesh.radius {
        return None;
    }
    if old.ring_y == mesh.ring_y && old.around == mesh.around && old.nodes.len() == mesh.nodes.len()
    {
        return Some(x.to_vec());
    }
    let scale = old.length / mesh.length;
    let mut carried = Vec::with_capacity(mesh.nodes.len());
    for &y in &mesh.ring_y {
        let ring = ring_points(old, x, y * scale);
        carried.extend(around(&ring, mesh.around));
    }
    let old_caps = cap_rings(old);
    let new_caps = cap_rings(mesh);
    let old_top = (old.ring_y.len() - 1) * old.around;
    let old_ring = |m: usize| -> Vec<Point> {
        if m == old_caps {
            vec![x[old.nodes.len() - 1]; old.around]
        } else {
            let start = old_top + m * old.around;
            x[start..start + old.around].to_vec()
        }
    };
    for m in 1..new_caps {
        let position = old_caps as f64 * m as f64 / new_caps as f64;
        let below = (position.floor() as usize).min(old_caps - 1);
        let w = position - below as f64;
        let (lower, upper) = (old_ring(below), old_ring(below + 1));
        let ring: Vec<Point> = lower
            .iter()
            .zip(&upper)
            .map(|(a, b)| a * (1.0 - w) + b * w)
            .collect();
        carried.extend(around(&ring, mesh.around));
    }
    carried.push(x[old.nodes.len() - 1]);
    (carried.len() == mesh.nodes.len()).then_some(carried)
}

/// Rings of the cap from the rim (0, the tube's top ring) to the pole
/// (`cap_rings`): the cap's non-tube nodes are rings 1..cap_rings − 1 and the
/// pole.
fn cap_rings(mesh: &TubeMesh) -> usize {
    let tube_nodes = mesh.ring_y.len() * mesh.around;
    (mesh.nodes.len() - tube_nodes - 1) / mesh.around + 1
}

/// `count` points at equal angles around the closed ring `ring` (whose point
/// j sits at angle 2πj/n), interpolated as in the module comment.
fn around(ring: &[Point], count: usize) -> Vec<Point> {
    let n = ring.len();
    if n == count {
        return ring.to_vec();
    }
    let centre = ring.iter().sum::<Point>() / n as f64;
    (0..count)
        .map(|j| {
            let position = n as f64 * j as f64 / count as f64;
            let below = position.floor() as usize % n;
            let w = position - position.floor();
            let (d0, d1) = (ring[below] - centre, ring[(below + 1) % n] - centre);
            let direction = d0 * (1.0 - w) + d1 * w;
            let length = d0.norm() * (1.0 - w) + d1.norm() * w;
            match direction.try_normalize(1e-12) {
                Some(unit) => centre + unit * length,
                None => centre + direction,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// A circle of radius 5 sampled with 12 points, carried onto 30: every
    /// new point on the circle (chord interpolation would sit up to 3.4 %
    /// inside it) and at its own angle.
    #[test]
    fn a_coarse_ring_carried_onto_a_finer_one_keeps_its_radius() {
        let circle = |n: usize| -> Vec<Point> {
            (0..n)
                .map(|j| {
                    let t = TAU * j as f64 / n as f64;
                    Point::new(5.0 * t.cos(), 5.0 * t.sin(), 2.0)
                })
                .collect()
        };
        let carried = around(&circle(12), 30);
        for (p, q) in carried.iter().zip(circle(30)) {
            assert!(((p - Point::new(0.0, 0.0, 2.0)).norm() - 5.0).abs() < 1e-12);
            assert!((p - q).norm() < 0.25, "{p} against {q}");
        }
        assert_eq!(around(&circle(12), 12), circle(12));
    }

    #[test]
    fn the_cap_ring_count_matches_the_mesh() {
        use super::super::mesh::MeshSpec;
        use std::f64::consts::FRAC_PI_2;
        for h in [0.5, 1.0, 2.0, 3.0] {
            let mesh = TubeMesh::new(5.0, 40.0, MeshSpec::uniform(h));
            let expected = ((FRAC_PI_2 * 5.0 / h).round() as usize).max(2);
            assert_eq!(cap_rings(&mesh), expected, "{h} mm");
        }
    }
}
