//! Cut elements as rank-one laminates.
//!
//! A triangle that a patch outline crosses holds two phases: the covered part
//! (share φ, layers A) and the bare part (1 − φ, layers B). Averaging their
//! energies at one strain (Voigt: `φ E_A(C) + (1−φ) E_B(C)`) makes the whole
//! element as stiff as the patch in every direction, so an oblique patch
//! becomes a staircase of stiff elements along the mesh lines, and its bend and
//! twist converge only at first order (docs/studies.md, "CalculiX cross-check").
//!
//! Here the phases are layers of a laminate whose interface has the unit normal
//! n (the triangle's reference plane). Their in-plane deformation gradients
//! may differ by a rank-one jump that keeps the interface intact and both
//! phases in the element's plane:
//!
//!   F_A = F (I + (1 − φ) α ⊗ n),   F_B = F (I − φ α ⊗ n),
//!
//! so φ F_A + (1 − φ) F_B = F, and with U = I + s α ⊗ n (s = 1 − φ or −φ)
//!
//!   C' = Uᵀ C U = C + s (n ⊗ v + v ⊗ n) + s² q n ⊗ n,   v = C α,  q = α·C α.
//!
//! The jump α ∈ ℝ² minimises the energy per unit reference area,
//!
//!   ψ(C) = min_α Φ(C, α),   Φ = φ E_A(C_A) + (1 − φ) E_B(C_B),
//!
//! with E = Σ_layers t W(C). Stationarity is traction continuity across the
//! interface. Along the interface the phases strain together (Voigt); across
//! it they carry the same traction (Reuss) — the exact answer for a laminate,
//! anisotropic along the patch outline rather than the mesh. Keeping the jump
//! in-plane keeps ψ a function of C alone (frame-indifferent) and leaves out
//! folding of the element about the interface, which a flat membrane
//! triangle cannot represent anyway.
//!
//! Φ is written once, generic over the number type. The inner minimisation is
//! Newton's method from α = 0 (the Voigt state) on second-order dual numbers
//! in α alone ([`Hyper`]`<2>`), shifted where ∂²Φ/∂α² is not positive definite
//! and backtracking on Φ; one evaluation on duals in z = (c₁₁, c₂₂, c₁₂, α₁,
//! α₂) at the minimum then gives every derivative the tangent needs:
//!
//!   ∂ψ/∂c = ∂Φ/∂c,   ∂²ψ/∂c² = Φ_cc − Φ_cα Φ_αα⁻¹ Φ_αc.
//!
//! Tests check ψ's derivatives against finite differences and ψ against a
//! one-dimensional laminate solved independently.

use crate::material::hyper::Real;
use crate::material::{Hyper, Kept, KeptPerMaterial, Material, Response};

/// One material layer of an element: which material, and its thickness times
/// the fraction of the element it covers (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layer {
    pub material: usize,
    pub thickness: f64,
}

/// The two phases of a cut element and their interface.
#[derive(Debug, Clone, PartialEq)]
pub struct Laminate {
    /// Share φ of the element in the covered phase, strictly in (0, 1).
    pub share: f64,
    /// Interface normal in the triangle's local frame (unit).
    pub normal: [f64; 2],
    /// Layers of the covered phase (full thicknesses, not area-weighted).
    pub covered: Vec<Layer>,
    /// Layers of the bare phase.
    pub bare: Vec<Layer>,
    /// The inner Newton's tolerance on r = ∂Φ/∂α (N/mm), from the phases'
    /// stiffness: fixed per element, so set once here.
    tolerance: f64,
    /// The covered and the bare phase's last ln J per material, where their
    /// thickness solves start (empty: from J = 1).
    kept: [KeptPerMaterial; 2],
}

/// Inner Newton iterations before the last iterate is accepted.
const MAX_ITERATIONS: usize = 40;

impl Laminate {
    pub fn new(
        share: f64,
        normal: [f64; 2],
        covered: Vec<Layer>,
        bare: Vec<Layer>,
        materials: &[Material],
    ) -> Laminate {
        // r ~ φ(1 − φ) μt × strain: converged when that strain is below 1e-12
        // (a relative test on Φ fails near the unstrained state, where Φ is
        // small against the rounding of its terms).
        let stiffness: f64 = covered
            .iter()
            .chain(&bare)
            .map(|l| l.thickness * materials[l.material].shear_modulus())
            .sum();
        Laminate {
            share,
            normal,
            covered,
            bare,
            tolerance: 1e-12 * share * (1.0 - share) * stiffness,
            kept: [Vec::new(), Vec::new()],
        }
    }

    /// Starts each phase's thickness solves from their last ln J
    /// (`material::kept`); `materials`: how many the layers refer to. The
    /// jump's minimisation always starts from the Voigt state: Φ need not be
    /// convex in α, and a start elsewhere may find another minimum.
    pub fn keep_starts(&mut self, materials: usize) {
        self.kept = [0, 1].map(|_| vec![Kept::default(); materials]);
    }

    /// ψ(C) only; +∞ outside the materials' domain.
    pub fn energy(&self, c: [f64; 3], materials: &[Material]) -> f64 {
        self.minimise(c, materials)
            .map_or(f64::INFINITY, |(_, phi)| phi.value)
    }

    /// ψ(C) with ∂ψ/∂c and ∂²ψ/∂c² at the minimising jump; `None` outside
    /// the domain (judged at the Voigt state α = 0, whose energy bounds ψ
    /// from above).
    pub fn response(&self, c: [f64; 3], materials: &[Material]) -> Option<Response> {
        let (alpha, _) = self.minimise(c, materials)?;
        let z = [c[0], c[1], c[2], alpha[0], alpha[1]];
        let [c11, c22, c12, a1, a2] = [0, 1, 2, 3, 4].map(|k| Hyper::<5>::variable(z[k], k));
        let phi = self.potential([c11, c22, c12], [a1, a2], materials)?;
        let h = &phi.hessian;
        let inverse = shifted_inverse([[h[3][3], h[3][4]], [h[4][3], h[4][4]]])?;
        let mut hessian = [[0.0; 3]; 3];
        for (i, row) in hessian.iter_mut().enumerate() {
            for (k, entry) in row.iter_mut().enumerate() {
                let mut condensed = 0.0;
                for a in 0..2 {
                    for b in 0..2 {
                        condensed += h[i][3 + a] * inverse[a][b] * h[3 + b][k];
                    }
                }
                *entry = h[i][k] - condensed;
            }
        }
        Some(Response {
            energy: phi.value,
            gradient: [phi.gradient[0], phi.gradient[1], phi.gradient[2]],
            hessian,
        })
    }

    /// The minimising jump α and Φ there (with its derivatives in α): Newton's
    /// method on dual numbers in α alone, C held fixed.
    fn minimise(&self, c: [f64; 3], materials: &[Material]) -> Option<([f64; 2], Hyper<2>)> {
        let at = |alpha: [f64; 2]| {
            let c = c.map(Hyper::<2>::constant);
            let alpha = [0, 1].map(|k| Hyper::<2>::variable(alpha[k], k));
            self.potential(c, alpha, materials)
        };
        let mut alpha = [0.0; 2];
        let mut phi = at(alpha)?;
        for _ in 0..MAX_ITERATIONS {
            let r = phi.gradient;
            let residual = r[0].hypot(r[1]);
            if residual <= self.tolerance {
                break;
            }
            let inverse = shifted_inverse(phi.hessian)?;
            let step = [
                -(inverse[0][0] * r[0] + inverse[0][1] * r[1]),
                -(inverse[1][0] * r[0] + inverse[1][1] * r[1]),
            ];
            let slope = r[0] * step[0] + r[1] * step[1];
            // A step is taken when Φ decreases enough (Armijo) or, close to
            // the minimum where Φ's decrease (∝ |r|²) drowns in the rounding
            // of its terms (W ∝ I₁ − 3 near the unstrained state), when the
            // residual falls.
            let mut t = 1.0;
            let mut accepted = None;
            for _ in 0..30 {
                let trial = [alpha[0] + t * step[0], alpha[1] + t * step[1]];
                if let Some(p) = at(trial) {
                    let falls = p.gradient[0].hypot(p.gradient[1]) <= (1.0 - 1e-4 * t) * residual;
                    if p.value <= phi.value + 1e-4 * t * slope || falls {
                        accepted = Some((trial, p));
                        break;
                    }
                }
                t *= 0.5;
            }
            // No progress left: α is at the minimum to rounding.
            let Some((trial, p)) = accepted else {
                break;
            };
            alpha = trial;
            phi = p;
        }
        Some((alpha, phi))
    }

    /// Φ(C, α) = φ E_A(C_A) + (1 − φ) E_B(C_B) in any number type.
    fn potential<T: Real>(&self, c: [T; 3], alpha: [T; 2], materials: &[Material]) -> Option<T> {
        let [c11, c22, c12] = c;
        let [a1, a2] = alpha;
        let [n1, n2] = self.normal;
        let v1 = c11 * a1 + c12 * a2;
        let v2 = c12 * a1 + c22 * a2;
        let q = c11 * a1 * a1 + c12 * a1 * a2 * 2.0 + c22 * a2 * a2;
        let phase = |s: f64, layers: &[Layer], kept: &[Kept<1>]| -> Option<T> {
            let shifted = [
                c11 + v1 * (2.0 * s * n1) + q * (s * s * n1 * n1),
                c22 + v2 * (2.0 * s * n2) + q * (s * s * n2 * n2),
                c12 + (v2 * n1 + v1 * n2) * s + q * (s * s * n1 * n2),
            ];
            let mut sum = T::constant(0.0);
            for layer in layers {
                let material = &materials[layer.material];
                sum = sum
                    + material.energy_in_kept(shifted, kept.get(layer.material))? * layer.thickness;
            }
            Some(sum)
        };
        let share = self.share;
        let covered = phase(1.0 - share, &self.covered, &self.kept[0])?;
        let bare = phase(-share, &self.bare, &self.kept[1])?;
        Some(covered * share + bare * (1.0 - share))
    }
}

/// (J + σI)⁻¹ for the smallest σ ≥ 0 on a ladder that makes J + σI positive
/// definite (σ = 0 whenever J already is); `None` for a J no shift mends
/// (not finite).
fn shifted_inverse(j: [[f64; 2]; 2]) -> Option<[[f64; 2]; 2]> {
    let scale = j[0][0].abs().max(j[1][1].abs()).max(f64::MIN_POSITIVE);
    let mut shift = 0.0;
    for _ in 0..40 {
        let (a, b, d) = (j[0][0] + shift, 0.5 * (j[0][1] + j[1][0]), j[1][1] + shift);
        let det = a * d - b * b;
        if a > 0.0 && det > 1e-14 * a * d {
            return Some([[d / det, -b / det], [-b / det, a / det]]);
        }
        shift = if shift == 0.0 {
            1e-10 * scale
        } else {
            10.0 * shift
        };
    }
    None
}

#[cfg(test)]
mod tests;
