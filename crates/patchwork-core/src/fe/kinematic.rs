//! A bent starting state for Newton: a kinematic estimate of where the patches
//! take the tube, so the solve does not have to swing long segments through
//! large rotations from a straight start.
//!
//! Around a cross-section at material height Y, the wall stretches axially by
//! λ(φ), with λ − 1 inversely proportional to the local membrane stiffness μt
//! (equal axial force per unit width: bare wall λ₂, patched wall much less).
//! A thin tube whose fibres stretch as λ(φ) = λ̄ (1 − κ r cos(φ − φₙ)) is bent
//! with curvature κ towards φₙ, so the first Fourier mode of λ(φ) gives the
//! curvature vector. Integrating it along Y like a rod (frame transported
//! without twist) gives a centreline; the rings sit around it at the inflated
//! radius.

use std::f64::consts::TAU;

use nalgebra::{Rotation3, Unit};

use super::mesh::TubeMesh;
use super::overlap::overlap_area;
use super::tube_theory::TubeState;
use crate::curve::Point;
use crate::design::{Bonding, Design};

/// Samples around the circumference for the coverage estimate.
const SAMPLES: usize = 72;

/// Node positions of the kinematic estimate.
pub fn kinematic_state(
    design: &Design,
    mesh: &TubeMesh,
    state: TubeState,
    scale: f64,
) -> Vec<Point> {
    let r0 = mesh.radius;
    let c = mesh.circumference();
    let (wall, patch) = (1.0, patch_stiffness(design, state));
    let (mut centre, mut frame) = (Point::zeros(), Rotation3::identity());
    let mut rings = Vec::with_capacity(mesh.ring_y.len());
    let mut previous_y = 0.0;
    for &y in &mesh.ring_y {
        let (mean, kx, ky) = bending(design, y, c, wall, patch, state.axial);
        let ds = (y - previous_y) * mean;
        previous_y = y;
        let r = state.hoop * r0;
        // Curvature vector in the ring's material axes, towards lower stretch.
        let curvature = Point::new(-kx, -ky, 0.0) * (scale / (mean * r));
        let tangent = frame * Point::z();
        centre += tangent * ds;
        let k = frame * curvature;
        let axis = tangent.cross(&k);
        if axis.norm() > 1e-12 {
            frame = Rotation3::from_axis_angle(&Unit::new_normalize(axis), k.norm() * ds) * frame;
        }
        rings.push((centre, frame));
    }
    let tube_nodes = mesh.ring_y.len() * mesh.around;
    let (top_centre, top_frame) = *rings.last().expect("at least two rings");
    mesh.nodes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if mesh.fixed[i] {
                return *p;
            }
            if i < tube_nodes {
                let (centre, frame) = rings[i / mesh.around];
                let hoop = 1.0 + (state.hoop - 1.0) * (1.0 - (-p.z / r0).exp());
                centre + frame * Point::new(p.x * hoop, p.y * hoop, 0.0)
            } else {
                let height = p.z - mesh.length;
                let rim = (1.0 - (height / r0).clamp(0.0, 1.0).powi(2)).sqrt();
                let hoop = 1.0 + (state.hoop - 1.0) * rim;
                top_centre
                    + top_frame * Point::new(p.x * hoop, p.y * hoop, height * state.hoop.sqrt())
            }
        })
        .collect()
}

/// The axial secant stiffness of the wall where a patch is — the patch for
/// `Replace`, wall and patch for `Laminate`, in excess of the wall's — relative
/// to the bare wall's: (λ₂ − 1)/(λ₂ₚ − 1) − [laminate: 1], where λ₂ₚ is the
/// axial stretch of a patched strip carrying the bare wall's membrane forces
/// (per reference length, hoop and axial) at the tube's state. The materials'
/// own laws, not their small-strain moduli: at a stretch of 3.7 the wall is far
/// from linear. Falls back to the ratio of μ₀t when no such state is found.
fn patch_stiffness(design: &Design, state: TubeState) -> f64 {
    let (wall, patch) = (&design.balloon, &design.patch);
    let linear = patch.material.shear_modulus() * patch.thickness_mm
        / (wall.material.shear_modulus() * wall.wall_mm);
    let laminate = design.patch.bonding == Bonding::Laminate;
    // Membrane forces (∂E/∂λ₁, ∂E/∂λ₂) of a strip's energy per reference area.
    let forces = |l1: f64, l2: f64, bare: bool| {
        let (_, p1, p2) = patch.material.principal(l1, l2);
        let (_, w1, w2) = wall.material.principal(l1, l2);
        let (wt, pt) = match (bare, laminate) {
            (true, _) => (wall.wall_mm, 0.0),
            (false, true) => (wall.wall_mm, patch.thickness_mm),
            (false, false) => (0.0, patch.thickness_mm),
        };
        [wt * w1 + pt * p1, wt * w2 + pt * p2]
    };
    let target = forces(state.hoop, state.axial, true);
    let (mut l1, mut l2) = (
        1.0 + 0.5 * (state.hoop - 1.0),
        1.0 + 0.5 * (state.axial - 1.0),
    );
    for _ in 0..50 {
        let f = forces(l1, l2, false);
        let r = [f[0] - target[0], f[1] - target[1]];
        let h = 1e-6;
        let (a, b) = (forces(l1 + h, l2, false), forces(l1, l2 + h, false));
        let j = [
            [(a[0] - f[0]) / h, (b[0] - f[0]) / h],
            [(a[1] - f[1]) / h, (b[1] - f[1]) / h],
        ];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if !det.is_finite() || det.abs() < 1e-300 {
            break;
        }
        let step = [
            (r[0] * j[1][1] - r[1] * j[0][1]) / det,
            (j[0][0] * r[1] - j[1][0] * r[0]) / det,
        ];
        // Damped: stretches stay above a third of the current ones.
        let t = [1.0, 0.5, 0.25, 0.125]
            .into_iter()
            .find(|t| l1 - t * step[0] > l1 / 3.0 && l2 - t * step[1] > l2 / 3.0)
            .unwrap_or(0.0625);
        (l1, l2) = (l1 - t * step[0], l2 - t * step[1]);
        if step[0].abs().max(step[1].abs()) < 1e-10 {
            let ratio = (state.axial - 1.0) / (l2 - 1.0);
            let excess = if laminate { ratio - 1.0 } else { ratio };
            return if excess.is_finite() && excess > 0.0 {
                excess
            } else {
                linear
            };
        }
    }
    linear
}

/// Mean axial stretch and the cos/sin Fourier coefficients of λ(φ) at height y.
fn bending(design: &Design, y: f64, c: f64, wall: f64, patch: f64, axial: f64) -> (f64, f64, f64) {
    let (mut mean, mut a, mut b) = (0.0, 0.0, 0.0);
    let h = c / SAMPLES as f64;
    for k in 0..SAMPLES {
        let x = (k as f64 + 0.5) * h;
        // Coverage of a small square cell around (x, y).
        let cell = [
            [x - h / 2.0, y - h / 2.0],
            [x + h / 2.0, y - h / 2.0],
            [x + h / 2.0, y + h / 2.0],
        ];
        let cell2 = [
            [x - h / 2.0, y - h / 2.0],
            [x + h / 2.0, y + h / 2.0],
            [x - h / 2.0, y + h / 2.0],
        ];
        let covered: f64 = design
            .patches
            .iter()
            .map(|p| overlap_area(&cell, p, c) + overlap_area(&cell2, p, c))
            .sum::<f64>()
            / (h * h);
        let share = covered.min(1.0);
        let stiffness = match design.patch.bonding {
            Bonding::Replace => wall * (1.0 - share) + patch * share,
            Bonding::Laminate => wall + patch * share,
        };
        let lambda = 1.0 + (axial - 1.0) * wall / stiffness;
        let phi = TAU * x / c;
        mean += lambda / SAMPLES as f64;
        a += 2.0 * lambda * phi.cos() / SAMPLES as f64;
        b += 2.0 * lambda * phi.sin() / SAMPLES as f64;
    }
    (mean, a, b)
}
