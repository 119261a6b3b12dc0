//! Where a cut element's inner minimisation starts: the jump its last
//! minimisation found, while the element's strain stays near the strain of
//! its last start from the Voigt state.
//!
//! From α = 0 the inner Newton needs 7–9 evaluations of Φ (the strain jump
//! across a patch outline is of order one, and Φ stiffens along the way);
//! from a nearby jump, 1.5 on average in a design run (docs/studies.md,
//! "Cut elements: where the inner Newton starts"). But Φ(C, ·) can have
//! more than one local minimum (a bare sliver beside a stiff patch has a
//! second, bulged state at higher Φ), and ψ is the one the Newton path from
//! α = 0 reaches. A jump followed
//! through large changes of C can end on another. So a start from memory is
//! taken only while C lies within [`NEAR`] of the C at the last start from
//! α = 0, and the jump it reaches is that minimum's continuation: the same
//! minimum wherever the one reached from α = 0 changes continuously over so
//! short a distance.
//!
//! Only a solve's own copy of the sections remembers
//! ([`super::Laminate::remembering`]), so a solve's result depends on its
//! inputs alone: each element is evaluated by one thread at a time, in the
//! order of the solve's assemblies, whatever the thread count.

use std::sync::atomic::{AtomicU64, Ordering};

/// How far C may move from the last cold start's C, relative to its trace
/// c₁₁ + c₂₂ (largest component change), for a remembered start.
pub(super) const NEAR: f64 = 0.01;

/// The C of the last start from α = 0 (c₁₁, c₂₂, c₁₂) and the last jump
/// found (α₁, α₂), as bits; none where the laminate does not remember.
#[derive(Debug, Default)]
pub(super) struct Memory(Option<[AtomicU64; 5]>);

impl Memory {
    /// A memory with nothing in it yet: the first minimisation starts cold.
    pub(super) fn empty() -> Memory {
        Memory(Some(
            [f64::NAN, f64::NAN, f64::NAN, 0.0, 0.0].map(|v| AtomicU64::new(v.to_bits())),
        ))
    }

    fn values(&self) -> Option<[f64; 5]> {
        let cells = self.0.as_ref()?;
        Some(
            cells
                .each_ref()
                .map(|c| f64::from_bits(c.load(Ordering::Relaxed))),
        )
    }

    /// The remembered jump, where `c` is near the last cold start's C.
    pub(super) fn start_for(&self, c: [f64; 3]) -> Option<[f64; 2]> {
        let [r11, r22, r12, a1, a2] = self.values()?;
        let reach = NEAR * (r11 + r22);
        let near = [c[0] - r11, c[1] - r22, c[2] - r12]
            .iter()
            .all(|d| d.abs() <= reach);
        near.then_some([a1, a2])
    }

    /// Keeps the jump `alpha` found at `c`, which becomes the reference C
    /// when the minimisation started from α = 0 (`cold`).
    pub(super) fn keep(&self, c: [f64; 3], alpha: [f64; 2], cold: bool) {
        let Some(cells) = &self.0 else {
            return;
        };
        if cold {
            for (cell, v) in cells.iter().zip(c) {
                cell.store(v.to_bits(), Ordering::Relaxed);
            }
        }
        for (cell, v) in cells[3..].iter().zip(alpha) {
            cell.store(v.to_bits(), Ordering::Relaxed);
        }
    }
}

impl Clone for Memory {
    fn clone(&self) -> Memory {
        Memory(
            self.values()
                .map(|v| v.map(|x| AtomicU64::new(x.to_bits()))),
        )
    }
}

/// What a laminate remembers is where its next minimisation starts, not
/// what the laminate is: two laminates equal in everything else have the
/// same ψ.
impl PartialEq for Memory {
    fn eq(&self, _: &Memory) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Laminate, Layer};
    use super::*;
    use crate::design::Design;
    use crate::fe::mesh::{MeshSpec, TubeMesh};
    use crate::fe::model::Model;
    use crate::fe::section::CutElements;
    use crate::material::{Law, Material};

    fn gap(a: [f64; 2], b: [f64; 2]) -> f64 {
        (a[0] - b[0]).hypot(a[1] - b[1])
    }

    /// Along a path of nearby states a remembering laminate starts each
    /// minimisation from the last jump, and its ψ, ∂ψ/∂c and ∂²ψ/∂c² are a
    /// fresh laminate's to the inner tolerance (checked to 1e-9 relative).
    #[test]
    fn a_remembering_laminate_gives_a_fresh_ones_response() {
        let m = vec![
            Material::reference_balloon(),
            Material::incompressible(Law::NeoHookean { mu_mpa: 3.0 }),
        ];
        let layer = |material, thickness| {
            vec![Layer {
                material,
                thickness,
            }]
        };
        let (s, c) = 25f64.to_radians().sin_cos();
        let lam = Laminate::new(0.4, [c, s], layer(1, 0.5), layer(0, 0.2), &m);
        let remembering = lam.remembering();
        for k in 0..6 {
            let t = k as f64 * 0.002;
            let state = [2.6 + t, 1.7 - t, 0.3 + 0.5 * t];
            if k > 0 {
                assert!(remembering.memory.start_for(state).is_some(), "step {k}");
            }
            let fresh = lam.response(state, &m).unwrap();
            let kept = remembering.response(state, &m).unwrap();
            let scale = fresh.gradient.iter().fold(0.0_f64, |a, g| a.max(g.abs()));
            assert!((kept.energy - fresh.energy).abs() < 1e-9 * fresh.energy.abs());
            for i in 0..3 {
                assert!((kept.gradient[i] - fresh.gradient[i]).abs() < 1e-9 * scale);
                for j in 0..3 {
                    let h = fresh.hessian[i][j];
                    assert!((kept.hessian[i][j] - h).abs() < 1e-7 * (1.0 + h.abs()));
                }
            }
        }
    }

    /// Φ(C, ·) of a cut element of the one-patch scene has two local minima
    /// at an inflated C; ψ is the one reached from α = 0. A remembered jump
    /// on the other is followed only while C stays within NEAR of the last
    /// cold start's C: from farther off the minimisation starts from α = 0
    /// and finds ψ again.
    #[test]
    fn a_remembered_jump_is_a_start_only_near_the_last_cold_start() {
        let design = Design::one_patch_test_scene();
        let mesh = TubeMesh::for_design(&design, MeshSpec::uniform(2.0));
        let model = Model::new(&design, mesh, CutElements::Laminate);
        let m = &model.materials;
        let c = [4.33, 2.2, -1.1];
        let (lam, cold, other) = (model.sections.iter())
            .filter_map(|s| s.laminate.as_ref().map(|(l, _)| l))
            .find_map(|l| {
                let (cold, at_cold) = l.minimise(c, m)?;
                let moved = l.remembering();
                moved.memory.keep(c, [-2.6, 0.0], true);
                let (other, at_other) = moved.minimise(c, m)?;
                (gap(other, cold) > 0.5 && at_other.value > at_cold.value)
                    .then_some((l, cold, other))
            })
            .expect("a cut element with a second, higher minimum");
        let reach = NEAR * (c[0] + c[1]);
        for (shift, follows) in [(0.5 * reach, true), (2.0 * reach, false)] {
            let state = [c[0] + shift, c[1], c[2]];
            let remembering = lam.remembering();
            remembering.memory.keep(c, other, true);
            let (got, _) = remembering.minimise(state, m).unwrap();
            let (fresh, _) = lam.minimise(state, m).unwrap();
            assert_eq!(gap(got, fresh) > 0.5, follows, "{got:?} {fresh:?}");
            assert!(gap(fresh, cold) < 0.2, "{fresh:?} {cold:?}");
        }
    }
}
