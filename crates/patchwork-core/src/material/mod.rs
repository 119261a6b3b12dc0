//! Incompressible hyperelastic membranes (plane stress, thickness stretch
//! eliminated by incompressibility).
//!
//! The in-plane right Cauchy–Green tensor C = FᵀF (2×2, components c₁₁, c₂₂, c₁₂)
//! fixes the thickness stretch λ₃² = 1/det C, hence the 3D invariants
//!
//!   I₁ = c₁₁ + c₂₂ + 1/J,   I₂ = J + (c₁₁ + c₂₂)/J,   J = det C = c₁₁c₂₂ − c₁₂².
//!
//! Each model gives W (energy per unit *reference* volume, MPa = N/mm²) as a
//! function of C. Stress and tangent are the exact derivatives of that one
//! formula (see [`hyper`]): `gradient = ∂W/∂(c₁₁, c₂₂, c₁₂)` and its Hessian. Outside
//! the physical domain (J ≤ 0, or past a locking limit) the energy is +∞ so a
//! line search can use it as a barrier.

pub mod hyper;
mod models;

use serde::{Deserialize, Serialize};

pub use hyper::Hyper;

/// A membrane material, as written in design JSON (`{"model": ..., ...}`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
pub enum Material {
    /// W = μ/2 (I₁ − 3).
    NeoHookean { mu_mpa: f64 },
    /// W = C₁₀ (I₁ − 3) + C₀₁ (I₂ − 3).
    MooneyRivlin { c10_mpa: f64, c01_mpa: f64 },
    /// W = −μ Jm/2 · ln(1 − (I₁ − 3)/Jm); locks as I₁ − 3 → Jm (Gent 1996).
    Gent { mu_mpa: f64, jm: f64 },
    /// Arruda–Boyce eight-chain model, the usual five-term series:
    /// W = μ Σᵢ₌₁⁵ αᵢ / λm^(2i−2) · (I₁ⁱ − 3ⁱ), α = 1/2, 1/20, 11/1050, 19/7000,
    /// 519/673750 (as in ABAQUS).
    ArrudaBoyce { mu_mpa: f64, lambda_m: f64 },
    /// W = Σₚ μₚ/αₚ (λ₁^αₚ + λ₂^αₚ + λ₃^αₚ − 3) in principal stretches.
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
    /// The authors' balloon latex: Arruda–Boyce, μ = 0.317 MPa, λm = 2.3.
    pub fn reference_balloon() -> Material {
        Material::ArrudaBoyce {
            mu_mpa: 0.317,
            lambda_m: 2.3,
        }
    }

    /// The authors' patch (latex-infused spandex): neo-Hookean, C₁₀ = 0.65 MPa.
    pub fn reference_patch() -> Material {
        Material::NeoHookean { mu_mpa: 1.3 }
    }

    pub fn model_name(&self) -> &'static str {
        match self {
            Material::NeoHookean { .. } => "neo_hookean",
            Material::MooneyRivlin { .. } => "mooney_rivlin",
            Material::Gent { .. } => "gent",
            Material::ArrudaBoyce { .. } => "arruda_boyce",
            Material::Ogden { .. } => "ogden",
        }
    }

    /// Checks every parameter; the error names the field.
    pub fn validate(&self) -> Result<(), MaterialError> {
        models::validate(self)
    }

    /// Small-strain shear modulus (MPa).
    pub fn shear_modulus(&self) -> f64 {
        models::shear_modulus(self)
    }

    /// W(C) with exact derivatives.
    pub fn response(&self, c: [f64; 3]) -> Response {
        let vars = [
            Hyper::variable(c[0], 0),
            Hyper::variable(c[1], 1),
            Hyper::variable(c[2], 2),
        ];
        match models::energy(self, vars) {
            Some(w) if w.value.is_finite() => Response {
                energy: w.value,
                gradient: w.gradient,
                hessian: w.hessian,
            },
            _ => Response {
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
        models::energy(self, c).filter(|w| hyper::Real::value(w).is_finite())
    }

    /// W only, in plain `f64` arithmetic (the line search's hot path); +∞
    /// outside the domain.
    pub fn energy(&self, c: [f64; 3]) -> f64 {
        match models::energy(self, c) {
            Some(w) if w.is_finite() => w,
            _ => f64::INFINITY,
        }
    }

    /// Energy of an in-plane stretch pair (λ₁, λ₂) along the principal axes, and
    /// its derivatives ∂W/∂λ₁, ∂W/∂λ₂ — what membrane theory of tubes needs.
    pub fn principal(&self, l1: f64, l2: f64) -> (f64, f64, f64) {
        let r = self.response([l1 * l1, l2 * l2, 0.0]);
        (r.energy, 2.0 * l1 * r.gradient[0], 2.0 * l2 * r.gradient[1])
    }
}
