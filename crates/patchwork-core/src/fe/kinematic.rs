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
use crate::material::ABAQUS_EXPLICIT_BULK_RATIO;
use crate::material::Material;

/// Samples around the circumference for the coverage estimate.
const SAMPLES: usize = 72;

/// How many times too little the equal-force stretch estimate bends an
/// incompressible balloon, and the reference (compressible, K₀/μ₀ = 20,
/// Poisson's ratio ν₀ = 0.475) balloon. On ten curves' KSA seeds and three
/// CMA-ES-sized perturbations of each, cold solves on the reference balloon
/// take a median of 14 Newton iterations on the draft search mesh and 14 on
/// its verification mesh at 2×, against 27 and 26 at 3× (which fails 3 of
/// the trefoil's 4 designs), 23 and 25 at 1.5×, 18 and 20 at 1.75×, 13 and
/// 13 at 2.25× (worse than 2× on the Hilbert curve and the trefoil, the
/// dearest solves) (`cargo run --release -p patchwork-core --example
/// kinematic_scale -- 3 1.5 1.75 2 2.25 3`). The same curves incompressible
/// (two perturbations each) take a median of 13 and 14 at 3×, against 19
/// and 22 at 2×, 15 and 18 at 2.5×, 18 and 17 at 3.5× (`... -- 2 2 2.5 3
/// 3.5 incompressible`).
const SCALE_INCOMPRESSIBLE: f64 = 3.0;
const SCALE_REFERENCE: f64 = 2.0;
/// The reference balloon's ν₀.
const NU_REFERENCE: f64 = poisson(ABAQUS_EXPLICIT_BULK_RATIO);

/// The curvature scale of the kinematic start for a balloon of `material`:
/// measured at ν₀ = 0.475 and 0.5 (above), linear in Poisson's ratio
/// between them, the reference's below. Any value only changes where
/// Newton starts, not where it ends.
pub fn calibrated_scale(material: &Material) -> f64 {
    let ratio = material.bulk_modulus() / material.shear_modulus();
    let nu = match ratio.is_finite() {
        true => poisson(ratio),
        false => 0.5,
    };
    let share = ((nu - NU_REFERENCE) / (0.5 - NU_REFERENCE)).clamp(0.0, 1.0);
    SCALE_REFERENCE + share * (SCALE_INCOMPRESSIBLE - SCALE_REFERENCE)
}

/// Poisson's ratio ν₀ = (3K₀/μ₀ − 2)/(6K₀/μ₀ + 2) at small strain.
const fn poisson(bulk_ratio: f64) -> f64 {
    (3.0 * bulk_ratio - 2.0) / (6.0 * bulk_ratio + 2.0)
}

/// Node positions of the kinematic estimate.
pub fn kinematic_state(
    design: &Design,
    mesh: &TubeMesh,
    state: TubeState,
    scale: f64,
) -> Vec<Point> {
    let r0 = mesh.radius;
    let rings = rod_frames(design, &mesh.ring_y, state, scale);
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

/// The kinematic estimate as a rod: the centre and the material frame of
/// the cross-section at each uninflated height of `heights` (ascending,
/// from the clamp at 0), integrated from the clamp along the tube.
pub fn rod_frames(
    design: &Design,
    heights: &[f64],
    state: TubeState,
    scale: f64,
) -> Vec<(Point, Rotation3<f64>)> {
    let c = design.balloon.circumference();
    let wall = design.balloon.material.shear_modulus() * design.balloon.wall_mm;
    let patch = design.patch.material.shear_modulus() * design.patch.thickness_mm;
    let r = state.hoop * design.balloon.radius_mm;
    let (mut centre, mut frame) = (Point::zeros(), Rotation3::identity());
    let mut rings = Vec::with_capacity(heights.len());
    let mut previous_y = 0.0;
    for &y in heights {
        let (mean, kx, ky) = bending(design, y, c, wall, patch, state.axial);
        let ds = (y - previous_y) * mean;
        previous_y = y;
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
    rings
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Compressibility;

    /// The two measured ends and a balloon between them.
    #[test]
    fn the_scale_runs_from_the_reference_balloon_to_an_incompressible_one() {
        let reference = Design::reference(vec![]).balloon.material;
        assert!((calibrated_scale(&reference) - SCALE_REFERENCE).abs() < 1e-9);
        let with = |c| Material {
            compressibility: c,
            ..reference.clone()
        };
        let incompressible = with(Compressibility::Incompressible);
        assert_eq!(calibrated_scale(&incompressible), SCALE_INCOMPRESSIBLE);
        let between = calibrated_scale(&with(Compressibility::BulkRatio(100.0)));
        assert!(between > 2.7 && between < 2.9, "{between}");
        let softer = with(Compressibility::BulkRatio(5.0));
        assert_eq!(calibrated_scale(&softer), SCALE_REFERENCE);
    }
}
