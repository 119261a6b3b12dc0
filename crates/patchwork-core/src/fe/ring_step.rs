//! A Newton step taken ring by ring, its rotations applied exactly.
//!
//! A long inflated tube is a slender structure: its soft modes are rigid
//! swings of whole stretches about the clamp. Newton's step is linear in
//! the positions, so a swing by θ moves each point along the tangent of
//! its circle: the stretch beyond a hinge lengthens by about θ²/2 and every
//! ring grows by the same factor, strains the stiff membrane answers with
//! forces far above the soft mode's. Near a long balloon's equilibrium
//! this keeps the residual of a tip that moves a few centimetres from
//! falling quadratically for several iterations.
//!
//! Here the same step is applied as the rod it mostly is. For ring k of the
//! tube (centroid cₖ, nodes at cₖ + dⱼ) the step (Δcₖ, Δdⱼ) splits into
//! the rotation ωₖ that fits the nodes' moves best,
//!
//!   ωₖ = argmin Σⱼ |Δdⱼ − ω × dⱼ|²,  (Σⱼ |dⱼ|² I − dⱼ dⱼᵀ) ωₖ = Σⱼ dⱼ × Δdⱼ,
//!
//! and the rest εⱼ = Δdⱼ − ωₖ × dⱼ. The segment sₖ = cₖ₊₁ − cₖ between
//! centroids likewise splits into a rotation ŝ × Δs / |s| and a change of
//! length Δs · ŝ. The step's end chains the segments from the clamped ring,
//! each rotated by exp of its rotation and lengthened by its change, and
//! puts each ring's nodes at c′ₖ + exp(ωₖ)(dⱼ + εⱼ); the cap's nodes follow
//! the last ring. To first order in the step this is the linear step (so
//! its slope along the gradient is the same), and a rigid swing of the tube
//! is taken without strain.
//!
//! It is an opt-in (`Steps::Rings`); solves step linearly by default. On
//! eight draft designs it ends where linear steps do (centrelines within
//! 1e-3 mm at a residual of 1e-9) in about a tenth fewer iterations, but
//! the designs a run finds move with every solve's last digits, and a
//! swing costs so little residual that a loose tolerance stops far from
//! equilibrium: docs/studies.md, "Newton steps ring by ring".

use nalgebra::{Matrix3, Rotation3};

use super::mesh::TubeMesh;
use crate::curve::Point;

/// Positions `x` moved by `t`·`dx` ring by ring (see the module's notes).
/// A ring whose fit is singular (fewer than three distinct nodes) moves
/// linearly.
pub fn stepped(mesh: &TubeMesh, x: &[Point], dx: &[Point], t: f64) -> Vec<Point> {
    let around = mesh.around;
    let ring = |k: usize| k * around..(k + 1) * around;
    // Each ring's centroid and its move, once.
    let centres: Vec<(Point, Point)> = (0..mesh.ring_y.len())
        .map(|k| (mean(&x[ring(k)]), t * mean(&dx[ring(k)])))
        .collect();
    let mut out = Vec::with_capacity(x.len());
    let (c0, dc0) = centres[0];
    let mut chained = c0 + dc0;
    let mut rotation = None;
    for (k, &(c, dc)) in centres.iter().enumerate() {
        if k > 0 {
            let (before, moved_before) = centres[k - 1];
            chained += rotated_segment(c - before, dc - moved_before);
        }
        rotation = fitted_rotation(&x[ring(k)], &dx[ring(k)], (c, dc), t);
        for node in ring(k) {
            out.push(moved_node(
                x[node],
                t * dx[node],
                (c, dc),
                (chained, &rotation),
            ));
        }
    }
    // The cap's rings and pole move with the tube's last ring.
    let last = *centres.last().expect("a tube has rings");
    for node in centres.len() * around..x.len() {
        out.push(moved_node(
            x[node],
            t * dx[node],
            last,
            (chained, &rotation),
        ));
    }
    out
}

/// A ring's rotation: exp(ω) of the best-fitting ω and ω itself; none where
/// the fit is singular.
type Fitted = Option<(Rotation3<f64>, Point)>;

/// ωₖ of the nodes `x` moved by `t`·`dx` about their centroid `c` moved by
/// `dc`.
fn fitted_rotation(x: &[Point], dx: &[Point], (c, dc): (Point, Point), t: f64) -> Fitted {
    let mut a = Matrix3::zeros();
    let mut b = Point::zeros();
    for (p, q) in x.iter().zip(dx) {
        let d = p - c;
        let dd = t * q - dc;
        a += Matrix3::identity() * d.norm_squared() - d * d.transpose();
        b += d.cross(&dd);
    }
    let omega = a.try_inverse()? * b;
    omega
        .iter()
        .all(|w| w.is_finite())
        .then(|| (Rotation3::new(omega), omega))
}

/// A node at `p` moved by `dp` when its ring's centroid `c` moved by `dc` to
/// `chained` and the ring turned by `fitted`.
fn moved_node(
    p: Point,
    dp: Point,
    (c, dc): (Point, Point),
    (chained, fitted): (Point, &Fitted),
) -> Point {
    let Some((rotation, omega)) = fitted else {
        return p + dp + (chained - c - dc);
    };
    let d = p - c;
    let rest = (dp - dc) - omega.cross(&d);
    chained + rotation * (d + rest)
}

/// The segment `s` between two centroids after their moves differ by `ds`:
/// turned by exp(ŝ × Δs / |s|) and lengthened by Δs · ŝ.
fn rotated_segment(s: Point, ds: Point) -> Point {
    let length = s.norm();
    if length == 0.0 {
        return s + ds;
    }
    let axis = s / length;
    let turned = Rotation3::new(axis.cross(&ds) / length) * axis;
    turned * (length + ds.dot(&axis))
}

fn mean(points: &[Point]) -> Point {
    let sum = points.iter().fold(Point::zeros(), |acc, p| acc + p);
    sum / points.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::mesh::MeshSpec;

    fn tube() -> TubeMesh {
        TubeMesh::new(3.0, 40.0, MeshSpec::uniform(2.0))
    }

    /// The linear step of a rotation by `angle` about the x axis through the
    /// clamp: ω × x.
    fn swing(mesh: &TubeMesh, angle: f64) -> Vec<Point> {
        let omega = Point::new(angle, 0.0, 0.0);
        mesh.nodes.iter().map(|p| omega.cross(p)).collect()
    }

    #[test]
    fn a_rigid_swing_keeps_every_distance() {
        let mesh = tube();
        let step = swing(&mesh, 0.4);
        let moved = stepped(&mesh, &mesh.nodes, &step, 1.0);
        let exact = Rotation3::new(Point::new(0.4, 0.0, 0.0));
        for (p, q) in mesh.nodes.iter().zip(&moved) {
            assert!((exact * p - q).norm() < 1e-9, "{p} → {q}");
        }
    }

    #[test]
    fn a_small_step_is_the_linear_step_to_second_order() {
        let mesh = tube();
        // A bend growing along the tube, a twist and a stretch together.
        let step: Vec<Point> = (mesh.nodes.iter())
            .map(|p| {
                let z = p.z / 40.0;
                Point::new(0.3 * z * z - 0.1 * z * p.y, 0.1 * z * p.x, 0.05 * p.z)
            })
            .collect();
        for t in [1e-2, 1e-3] {
            let moved = stepped(&mesh, &mesh.nodes, &step, t);
            let worst = (mesh.nodes.iter().zip(&step).zip(&moved))
                .map(|((p, s), q)| (p + t * s - q).norm())
                .fold(0.0, f64::max);
            // The difference is the rotations' second-order terms: |ω|²|d|.
            assert!(worst < 2.0 * t * t, "t {t}: {worst}");
        }
    }

    #[test]
    fn the_clamped_ring_stays() {
        let mesh = tube();
        let mut step = swing(&mesh, 0.2);
        step[..mesh.around].fill(Point::zeros());
        let moved = stepped(&mesh, &mesh.nodes, &step, 0.5);
        for (p, q) in mesh.nodes.iter().zip(&moved).take(mesh.around) {
            assert!((p - q).norm() < 1e-12, "{p} → {q}");
        }
    }
}
