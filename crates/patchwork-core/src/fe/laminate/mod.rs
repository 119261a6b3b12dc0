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
//! Newton's method on second-order dual numbers in α alone
//! ([`Hyper`]`<2>`), shifted where ∂²Φ/∂α² is not positive definite and
//! backtracking on Φ, from α = 0 (the Voigt state) or, in a solve's own copy
//! of the sections ([`Laminate::remembering`]) while C stays near, from the
//! jump the element's previous minimisation found ([`memory`]). One
//! evaluation on duals in z = (c₁₁, c₂₂, c₁₂, α₁, α₂) at the minimum then
//! gives every derivative the tangent needs:
//!
//!   ∂ψ/∂c = ∂Φ/∂c,   ∂²ψ/∂c² = Φ_cc − Φ_cα Φ_αα⁻¹ Φ_αc.
//!
//! Tests check ψ's derivatives against finite differences and ψ against a
//! one-dimensional laminate solved independently.

mod memory;

use memory::Memory;

use crate::material::hyper::Real;
use crate::material::{Hyper, Material, Response};

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
    /// The last minimising jump, where this laminate remembers it.
    memory: Memory,
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
            memory: Memory::default(),
        }
    }

    /// A copy that starts a minimisation from the jump its previous one
    /// found while C stays near the C of its last start from α = 0
    /// ([`memory`]), for one solve's own sections.
    pub fn remembering(&self) -> Laminate {
        Laminate {
            memory: Memory::empty(),
            ..self.clone()
        }
    }

    /// ψ(C) only; +∞ outside the materials' domain.
    pub fn energy(&self, c: [f64; 3], materials: &[Material]) -> f64 {
        self.minimise(c, materials)
            .map_or(f64::INFINITY, |(_, phi)| phi.value)
    }

    /// ψ(C) with ∂ψ/∂c and ∂²ψ/∂c² at the minimising jump; `None` outside
    /// the domain (judged at the start, the remembered jump or else the
    /// Voigt state α = 0, whose energy bounds ψ from above).
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
    /// method on dual numbers in α alone, C held fixed, from the remembered
    /// jump where C is near and that jump is inside the domain, else from
    /// α = 0.
    fn minimise(&self, c: [f64; 3], materials: &[Material]) -> Option<([f64; 2], Hyper<2>)> {
        let at = |alpha: [f64; 2]| {
            let c = c.map(Hyper::<2>::constant);
            let alpha = [0, 1].map(|k| Hyper::<2>::variable(alpha[k], k));
            self.potential(c, alpha, materials)
        };
        let remembered = (self.memory.start_for(c)).and_then(|a| Some((a, at(a)?)));
        let cold = remembered.is_none();
        let (mut alpha, mut phi) = match remembered {
            Some(start) => start,
            None => ([0.0; 2], at([0.0; 2])?),
        };
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
        self.memory.keep(c, alpha, cold);
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
        let phase = |s: f64, layers: &[Layer]| -> Option<T> {
            let shifted = [
                c11 + v1 * (2.0 * s * n1) + q * (s * s * n1 * n1),
                c22 + v2 * (2.0 * s * n2) + q * (s * s * n2 * n2),
                c12 + (v2 * n1 + v1 * n2) * s + q * (s * s * n1 * n2),
            ];
            let mut sum = T::constant(0.0);
            for layer in layers {
                sum = sum + materials[layer.material].energy_in(shifted)? * layer.thickness;
            }
            Some(sum)
        };
        let share = self.share;
        let covered = phase(1.0 - share, &self.covered)?;
        let bare = phase(-share, &self.bare)?;
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
mod tests {
    use super::*;
    use crate::material::{Compressibility, Law};

    fn materials() -> Vec<Material> {
        vec![
            Material::reference_balloon(),
            Material::compressible(
                Law::NeoHookean { mu_mpa: 1.3 },
                Compressibility::abaqus_explicit(),
            ),
            Material::incompressible(Law::Gent {
                mu_mpa: 0.5,
                jm: 30.0,
            }),
            Material::compressible(
                Law::Ogden {
                    mu_mpa: vec![0.6, 0.01],
                    alpha: vec![1.3, 5.0],
                },
                Compressibility::BulkRatio(5.0),
            ),
        ]
    }

    fn laminate(share: f64, angle_deg: f64, covered: usize, bare: usize) -> Laminate {
        let (s, c) = angle_deg.to_radians().sin_cos();
        let layer = |material, thickness| {
            vec![Layer {
                material,
                thickness,
            }]
        };
        Laminate::new(
            share,
            [c, s],
            layer(covered, 0.49),
            layer(bare, 0.2),
            &materials(),
        )
    }

    /// C of an inflated, sheared state, and of a compressed one.
    const STATES: [[f64; 3]; 2] = [[2.6, 1.7, 0.3], [0.8, 1.2, -0.1]];

    #[test]
    fn gradient_and_tangent_match_finite_differences() {
        let m = materials();
        let cases = [
            (0.3, 30.0, 1, 0),
            (0.7, -65.0, 1, 0),
            (0.5, 0.0, 2, 0),
            (0.02, 90.0, 1, 3),
            (0.97, 10.0, 3, 2),
        ];
        for (share, angle, covered, bare) in cases {
            let lam = laminate(share, angle, covered, bare);
            for c in STATES {
                let r = lam.response(c, &m).unwrap();
                let h = 1e-6;
                for k in 0..3 {
                    let (mut plus, mut minus) = (c, c);
                    plus[k] += h;
                    minus[k] -= h;
                    let (rp, rm) = (
                        lam.response(plus, &m).unwrap(),
                        lam.response(minus, &m).unwrap(),
                    );
                    let de = (rp.energy - rm.energy) / (2.0 * h);
                    let scale = r.gradient.iter().map(|g| g.abs()).sum::<f64>();
                    assert!(
                        (de - r.gradient[k]).abs() < 1e-7 * scale,
                        "φ {share} angle {angle} C {c:?} k {k}: {de} vs {}",
                        r.gradient[k]
                    );
                    let scale = r.hessian.iter().flatten().map(|g| g.abs()).sum::<f64>();
                    for i in 0..3 {
                        let dg = (rp.gradient[i] - rm.gradient[i]) / (2.0 * h);
                        assert!(
                            (dg - r.hessian[i][k]).abs() < 1e-6 * scale,
                            "φ {share} angle {angle} C {c:?} H[{i}][{k}]: {dg} vs {}",
                            r.hessian[i][k]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn laminate_is_softer_than_the_average_and_equal_without_contrast() {
        let m = materials();
        let c = STATES[0];
        let average = |lam: &Laminate| {
            let e = |layers: &[Layer]| -> f64 {
                layers
                    .iter()
                    .map(|l| l.thickness * m[l.material].energy(c))
                    .sum()
            };
            lam.share * e(&lam.covered) + (1.0 - lam.share) * e(&lam.bare)
        };
        let stiff = laminate(0.4, 20.0, 1, 0);
        assert!(stiff.energy(c, &m) < average(&stiff) * (1.0 - 1e-3));
        // Identical phases: no jump, the average exactly.
        let stiff_layers = stiff.covered.clone();
        let same = Laminate::new(0.4, stiff.normal, stiff_layers.clone(), stiff_layers, &m);
        assert!((same.energy(c, &m) - average(&same)).abs() < 1e-12 * average(&same));
    }

    /// Two incompressible neo-Hookean phases stretched across the interface (λ along n, 1
    /// along the interface): ψ is the 1-D laminate, min over the phase
    /// stretches with φλ_A + (1 − φ)λ_B = λ, found here by bisection on the
    /// traction balance t_A μ_A (λ_A − λ_A⁻³) = t_B μ_B (λ_B − λ_B⁻³).
    #[test]
    fn stretch_across_the_interface_matches_the_one_dimensional_laminate() {
        let m = vec![
            Material::incompressible(Law::NeoHookean { mu_mpa: 0.4 }),
            Material::incompressible(Law::NeoHookean { mu_mpa: 3.0 }),
        ];
        let (phi, ta, tb) = (0.35, 0.5, 0.2);
        let layer = |material, thickness| {
            vec![Layer {
                material,
                thickness,
            }]
        };
        let lam = Laminate::new(phi, [1.0, 0.0], layer(1, ta), layer(0, tb), &m);
        // Membrane neo-Hooke with in-plane stretches (λ, 1): W = μ/2 (λ² + 1/λ² − 2).
        let w = |mu: f64, l: f64| 0.5 * mu * (l * l + 1.0 / (l * l) - 2.0);
        let traction = |mu: f64, t: f64, l: f64| t * mu * (l - 1.0 / l.powi(3));
        for lambda in [0.9, 1.3, 2.2] {
            let lb_of = |la: f64| (lambda - phi * la) / (1.0 - phi);
            let (mut lo, mut hi) = (0.2_f64, lambda / phi - 1e-9);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                let lb = lb_of(mid);
                let balance = if lb <= 0.0 {
                    1.0
                } else {
                    traction(3.0, ta, mid) - traction(0.4, tb, lb)
                };
                if balance > 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let la = 0.5 * (lo + hi);
            let expected = phi * ta * w(3.0, la) + (1.0 - phi) * tb * w(0.4, lb_of(la));
            let got = lam.energy([lambda * lambda, 1.0, 0.0], &m);
            assert!(
                (got - expected).abs() < 1e-10 * expected,
                "λ {lambda}: {got} vs {expected}"
            );
        }
    }

    #[test]
    fn domain_limits_are_reported_not_hidden() {
        let lam = laminate(0.5, 0.0, 1, 0);
        let m = materials();
        // det C = 0: outside the domain.
        assert!(lam.response([1.0, 1.0, 1.0], &m).is_none());
        assert!(lam.energy([1.0, 1.0, 1.0], &m).is_infinite());
    }
}
