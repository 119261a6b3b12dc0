//! Hyperelastic membranes in plane stress: five strain-energy models, each
//! incompressible or compressible with a volumetric part as ABAQUS defines it.
//!
//! The in-plane right Cauchy–Green tensor C = FᵀF (2×2, components c₁₁, c₂₂,
//! c₁₂) is what the membrane knows; the through-thickness stretch λ₃ (c₃₃ = λ₃²)
//! is not a degree of freedom but follows from the plane-stress condition
//! σ₃₃ = 0:
//!
//! - **incompressible**: λ₃² = 1/det C (J = 1), and the 3D invariants are
//!   I₁ = c₁₁ + c₂₂ + 1/det C, I₂ = det C + (c₁₁ + c₂₂)/det C;
//! - **compressible**: W(C, c₃₃) = W_dev(Ī₁, Ī₂) + U(J) with J = √(det C · c₃₃),
//!   Ī₁ = J^(−2/3) I₁, Ī₂ = J^(−4/3) I₂ (ABAQUS's split), and c₃₃ minimises W
//!   at every evaluation (∂W/∂c₃₃ = 0 is σ₃₃ = 0), by Newton's method on ln c₃₃
//!   ([`plane_stress`]). The condensed energy W̄(C) = W(C, c₃₃(C)) has the
//!   exact derivatives ∂W̄/∂C = ∂W/∂C (the envelope theorem) and
//!   ∂²W̄/∂C² = W_CC − W_C3 W_3C / W_33 (the Schur complement).
//!
//! Each model gives W (energy per unit *reference* volume, MPa = N/mm²) as a
//! function of C. Stress and tangent are the exact derivatives of that one
//! formula (see [`hyper`]): `gradient = ∂W/∂(c₁₁, c₂₂, c₁₂)` and its Hessian. Outside
//! the physical domain (J ≤ 0, or past a locking limit) the energy is +∞ so a
//! line search can use it as a barrier.

pub mod hyper;
mod json;
mod models;
mod plane_stress;
mod thickness;
mod volumetric;

pub use hyper::Hyper;
pub use volumetric::{ABAQUS_EXPLICIT_BULK_RATIO, Compressibility};

/// One law of each kind, with parameters of latex and patch materials (an
/// Ogden law with a term of negative exponent): what tests of every law
/// run over.
#[cfg(test)]
pub(crate) fn one_law_of_each_kind() -> Vec<Law> {
    vec![
        Law::NeoHookean { mu_mpa: 1.3 },
        Law::MooneyRivlin {
            c10_mpa: 0.3,
            c01_mpa: 0.05,
        },
        Law::Gent {
            mu_mpa: 0.4,
            jm: 40.0,
        },
        Law::ArrudaBoyce {
            mu_mpa: 0.317,
            lambda_m: 2.3,
        },
        Law::Ogden {
            mu_mpa: vec![0.63, 0.0012, -0.01],
            alpha: vec![1.3, 5.0, -2.0],
        },
    ]
}

/// A membrane material, as written in design JSON:
/// `{"model": ..., <the model's parameters>, <its compressibility>}` where the
/// compressibility is one of `"bulk_ratio": K₀/μ₀`, `"d": D₁` (ABAQUS's D₁ in
/// 1/MPa, K₀ = 2/D₁) or `"incompressible": true`. None given means the
/// authors' setting: their ABAQUS/Explicit model has D = 0, which
/// ABAQUS/Explicit, unable to impose incompressibility, takes as K₀/μ₀ = 20
/// (`"bulk_ratio": 20`, [`Compressibility::abaqus_explicit`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub law: Law,
    pub compressibility: Compressibility,
}

/// The strain-energy model (the deviatoric part when compressible), in the
/// deviatoric invariants Ī₁, Ī₂ (equal to I₁, I₂ when incompressible).
#[derive(Debug, Clone, PartialEq)]
pub enum Law {
    /// W = μ/2 (Ī₁ − 3); U = Σ (1/Dᵢ)(J − 1)^(2i) (one term).
    NeoHookean { mu_mpa: f64 },
    /// W = C₁₀ (Ī₁ − 3) + C₀₁ (Ī₂ − 3); U = (1/D₁)(J − 1)².
    MooneyRivlin { c10_mpa: f64, c01_mpa: f64 },
    /// W = −μ Jm/2 · ln(1 − (Ī₁ − 3)/Jm); locks as Ī₁ − 3 → Jm (Gent 1996).
    /// ABAQUS has no built-in Gent model; its volumetric part here is
    /// Arruda–Boyce's, U = (1/D)((J² − 1)/2 − ln J), which stays finite
    /// and convex for every J > 0.
    Gent { mu_mpa: f64, jm: f64 },
    /// Arruda–Boyce eight-chain model, the usual five-term series:
    /// W = μ Σᵢ₌₁⁵ αᵢ / λm^(2i−2) · (Ī₁ⁱ − 3ⁱ), α = 1/2, 1/20, 11/1050, 19/7000,
    /// 519/673750; U = (1/D)((J² − 1)/2 − ln J) (as in ABAQUS).
    ArrudaBoyce { mu_mpa: f64, lambda_m: f64 },
    /// W = Σₚ μₚ/αₚ (λ̄₁^αₚ + λ̄₂^αₚ + λ̄₃^αₚ − 3) in the deviatoric principal
    /// stretches λ̄ᵢ = J^(−1/3) λᵢ; U = Σᵢ (1/Dᵢ)(J − 1)^(2i). (ABAQUS writes
    /// the first sum with 2μₚ/αₚ²; here μ₀ = ½ Σ μₚαₚ.)
    Ogden { mu_mpa: Vec<f64>, alpha: Vec<f64> },
}

/// A material parameter outside its domain.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("material {model}: {field} = {value}: {reason}")]
pub struct MaterialError {
    pub model: &'static str,
    pub field: &'static str,
    pub value: f64,
    pub reason: &'static str,
}

/// Energy and its first and second derivatives with respect to (c₁₁, c₂₂, c₁₂).
/// `energy` is +∞ (and derivatives meaningless) outside the domain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Response {
    pub energy: f64,
    pub gradient: [f64; 3],
    pub hessian: [[f64; 3]; 3],
}

impl Response {
    pub fn is_admissible(&self) -> bool {
        self.energy.is_finite()
    }
}

impl Material {
    /// A material with the given compressibility.
    pub fn compressible(law: Law, compressibility: Compressibility) -> Material {
        Material {
            law,
            compressibility,
        }
    }

    /// An incompressible material (J = 1).
    pub fn incompressible(law: Law) -> Material {
        Material {
            law,
            compressibility: Compressibility::Incompressible,
        }
    }

    /// The same model with another compressibility.
    pub fn with_compressibility(mut self, compressibility: Compressibility) -> Material {
        self.compressibility = compressibility;
        self
    }

    /// The authors' balloon latex (their `Run.py`): Arruda–Boyce, μ = 0.317
    /// MPa, λm = 2.3, with D = 0, which ABAQUS/Explicit (their solver) takes
    /// as K₀/μ₀ = 20 (Poisson's ratio 0.475). Inflated to 20 kPa the bare
    /// tube stretches 5.19 round and 3.67 along, as in their output; the
    /// incompressible model is `.with_compressibility(Compressibility::Incompressible)`.
    pub fn reference_balloon() -> Material {
        Material::compressible(
            Law::ArrudaBoyce {
                mu_mpa: 0.317,
                lambda_m: 2.3,
            },
            Compressibility::abaqus_explicit(),
        )
    }

    /// The authors' patch (latex-infused spandex): neo-Hookean, C₁₀ = 0.65 MPa,
    /// D₁ = 0 in their model: K₀/μ₀ = 20 in ABAQUS/Explicit, as the balloon.
    pub fn reference_patch() -> Material {
        Material::compressible(
            Law::NeoHookean { mu_mpa: 1.3 },
            Compressibility::abaqus_explicit(),
        )
    }

    pub fn model_name(&self) -> &'static str {
        self.law.name()
    }

    /// Checks every parameter; the error names the field.
    pub fn validate(&self) -> Result<(), MaterialError> {
        models::validate(&self.law)?;
        volumetric::validate(&self.law, &self.compressibility)
    }

    /// Small-strain shear modulus μ₀ (MPa).
    pub fn shear_modulus(&self) -> f64 {
        models::shear_modulus(&self.law)
    }

    /// Small-strain bulk modulus K₀ = 2/D₁ (MPa); +∞ when incompressible.
    pub fn bulk_modulus(&self) -> f64 {
        match self.volumetric() {
            Some(u) => u.bulk_modulus(),
            None => f64::INFINITY,
        }
    }

    /// The volumetric part, `None` when incompressible.
    fn volumetric(&self) -> Option<volumetric::Volumetric> {
        volumetric::Volumetric::of(&self.law, &self.compressibility)
    }

    /// W(C) with exact derivatives.
    pub fn response(&self, c: [f64; 3]) -> Response {
        let vars = [
            Hyper::variable(c[0], 0),
            Hyper::variable(c[1], 1),
            Hyper::variable(c[2], 2),
        ];
        match self.energy_in(vars) {
            Some(w) => Response {
                energy: w.value,
                gradient: w.gradient,
                hessian: w.hessian,
            },
            None => Response {
                energy: f64::INFINITY,
                gradient: [0.0; 3],
                hessian: [[0.0; 3]; 3],
            },
        }
    }

    /// W in any [`hyper::Real`] number type: a caller composing C from other
    /// variables (a laminate's phases) gets W's derivatives in those variables.
    /// `None` outside the domain.
    pub fn energy_in<T: hyper::Real>(&self, c: [T; 3]) -> Option<T> {
        let w = match self.volumetric() {
            None => models::incompressible(&self.law, c),
            Some(u) => plane_stress::condensed(&self.law, &u, c),
        };
        w.filter(|w| hyper::Real::value(w).is_finite())
    }

    /// W only, in plain `f64` arithmetic (the line search's hot path); +∞
    /// outside the domain.
    pub fn energy(&self, c: [f64; 3]) -> f64 {
        self.energy_in(c).unwrap_or(f64::INFINITY)
    }

    /// The thickness stretch λ₃ at in-plane C (from σ₃₃ = 0), `None` outside
    /// the domain.
    pub fn thickness_stretch(&self, c: [f64; 3]) -> Option<f64> {
        let det = c[0] * c[1] - c[2] * c[2];
        match self.volumetric() {
            None => (det > 0.0).then(|| det.powf(-0.5)),
            Some(u) => plane_stress::thickness_c33(&self.law, &u, c).map(f64::sqrt),
        }
    }

    /// Energy of an in-plane stretch pair (λ₁, λ₂) along the principal axes, and
    /// its derivatives ∂W/∂λ₁, ∂W/∂λ₂ — what membrane theory of tubes needs.
    pub fn principal(&self, l1: f64, l2: f64) -> (f64, f64, f64) {
        let r = self.response([l1 * l1, l2 * l2, 0.0]);
        (r.energy, 2.0 * l1 * r.gradient[0], 2.0 * l2 * r.gradient[1])
    }
}

impl Law {
    pub fn name(&self) -> &'static str {
        match self {
            Law::NeoHookean { .. } => "neo_hookean",
            Law::MooneyRivlin { .. } => "mooney_rivlin",
            Law::Gent { .. } => "gent",
            Law::ArrudaBoyce { .. } => "arruda_boyce",
            Law::Ogden { .. } => "ogden",
        }
    }
}
