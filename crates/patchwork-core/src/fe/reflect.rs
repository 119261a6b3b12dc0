//! A start for a design moved the other way: the nominal state reflected
//! through a moved one, ring by ring.
//!
//! A source at +δ moves each ring k of the tube by a rigid motion
//! Tₖ(x) = Rₖ x + tₖ (the best fit of the nominal ring onto the moved one,
//! `kabsch`) and deforms it a little besides. The same source at −δ moves
//! it, to first order in δ, by the inverse motion Tₖ⁻¹(x) = Rₖᵀ(x − tₖ):
//! a tube swung by an angle about a hinge swings back by the same angle.
//! Applying Tₖ⁻¹ to the nominal ring keeps the ring's own (local) state
//! the nominal's, so a patch's edges start as they are rather than strained
//! the wrong way (which reflecting every node, 2x − x₊, does). The cap
//! follows the last ring.
//!
//! For whole swings of the tube the start is exact (a rigid motion's
//! inverse); for a chain of hinges it is right to first order, the
//! remainder being the response's second-order part.

use super::carry::carried_state;
use super::simulate::Simulation;
use crate::curve::{Point, kabsch};

/// `nominal`'s state with each ring moved by the inverse of its rigid
/// motion onto `moved`'s (carried onto the nominal's mesh); none where the
/// two meshes' balloons differ in radius.
pub fn reflected_start(nominal: &Simulation, moved: &Simulation) -> Option<Simulation> {
    let mesh = &nominal.mesh;
    let carried = carried_state(&moved.mesh, &moved.positions, mesh)?;
    let x = &nominal.positions;
    let tube = mesh.ring_y.len() * mesh.around;
    let mut reflected = nominal.clone();
    let mut inverse = None;
    let rings = x[..tube]
        .chunks(mesh.around)
        .zip(carried.chunks(mesh.around));
    let out = reflected.positions.chunks_mut(mesh.around);
    for ((ring, moved), out) in rings.zip(out) {
        let (rotation, translation) = kabsch(ring, moved);
        let back = rotation.inverse();
        for (o, p) in out.iter_mut().zip(ring) {
            *o = back * (p - translation);
        }
        inverse = Some((back, translation));
    }
    let (back, translation) = inverse?;
    for (o, p) in reflected.positions[tube..].iter_mut().zip(&x[tube..]) {
        *o = back * (p - translation);
    }
    Some(reflected)
}

/// A start for the design moved the other way from its linearised
/// response, to second order: with the moved state x₊ = x₀ + a + b (odd
/// part a, even part b of the response) and the linearised one
/// x_l ≈ x₀ + a, the state at −δ is x₋ = x₀ − a + b ≈ x₊ − 2(x_l − x₀),
/// node by node — the ring's own deformation (its radius under a balloon
/// source, a patch's edges under its size) reflected with it, where
/// [`reflected_start`] keeps the nominal's. For sources the linearisation
/// answers closely (not a patch's placement around the tube, which it
/// overstates). `linearised` lies on the nominal's mesh; `moved` is
/// carried onto it. None where the meshes' balloons differ in radius or
/// `linearised` is of another mesh.
pub fn second_order_start(
    nominal: &Simulation,
    moved: &Simulation,
    linearised: &[Point],
) -> Option<Simulation> {
    let x = &nominal.positions;
    if linearised.len() != x.len() {
        return None;
    }
    let carried = carried_state(&moved.mesh, &moved.positions, &nominal.mesh)?;
    let positions = (carried.iter().zip(linearised).zip(x))
        .map(|((plus, l), x0)| plus - (l - x0) * 2.0)
        .collect();
    Some(Simulation {
        positions,
        ..nominal.clone()
    })
}

#[cfg(test)]
mod tests {
    use nalgebra::{Rotation3, Vector3};

    use super::*;
    use crate::curve::Point;
    use crate::design::Design;
    use crate::fe::mesh::MeshSpec;
    use crate::fe::{SimulateOptions, simulate};

    /// A state swung rigidly about a point reflects to the swing the other
    /// way, node for node (caps included).
    #[test]
    fn a_rigid_swing_reflects_to_the_opposite_swing() {
        let options = SimulateOptions {
            mesh: MeshSpec::uniform(2.0),
            ..SimulateOptions::default()
        };
        let nominal = simulate(&Design::one_patch_test_scene(), &options).unwrap();
        let hinge = Point::new(1.0, -2.0, 40.0);
        let swing = |angle: f64| {
            let r = Rotation3::from_axis_angle(&Vector3::x_axis(), angle);
            let mut s = nominal.clone();
            for p in &mut s.positions {
                *p = r * (*p - hinge) + hinge;
            }
            s
        };
        let reflected = reflected_start(&nominal, &swing(0.05)).unwrap();
        let opposite = swing(-0.05);
        let gap = (reflected.positions.iter().zip(&opposite.positions))
            .map(|(p, q)| (p - q).norm())
            .fold(0.0, f64::max);
        assert!(gap < 1e-9, "{gap} mm");
    }
}
