//! The material parameters a calibration can fit, read from and written
//! into a `Material`: the moduli together (`modulus`: every modulus of the
//! law scaled alike; its value is μ of neo-Hookean, Arruda–Boyce and Gent,
//! C₁₀ + C₀₁ of Mooney–Rivlin, μ₀ of Ogden), the law's
//! stiffening (`lambda_m` of Arruda–Boyce, `jm` of Gent) and the
//! compressibility (`bulk_ratio`, K₀/μ₀).

use serde::{Deserialize, Serialize};

use crate::material::{Compressibility, Law, Material};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Parameter {
    Modulus,
    LambdaM,
    Jm,
    BulkRatio,
}

impl Parameter {
    pub fn name(self) -> &'static str {
        match self {
            Parameter::Modulus => "modulus",
            Parameter::LambdaM => "lambda_m",
            Parameter::Jm => "jm",
            Parameter::BulkRatio => "bulk_ratio",
        }
    }

    /// A parameter named as on the command line.
    pub fn from_name(name: &str) -> Option<Parameter> {
        [
            Parameter::Modulus,
            Parameter::LambdaM,
            Parameter::Jm,
            Parameter::BulkRatio,
        ]
        .into_iter()
        .find(|p| p.name() == name)
    }

    /// Its value in `material`; none where the material has no such
    /// parameter (λm of a neo-Hookean law, K₀/μ₀ of an incompressible one).
    pub fn get(self, material: &Material) -> Option<f64> {
        match (self, &material.law, &material.compressibility) {
            (Parameter::Modulus, law, _) => Some(law_modulus(law, material)),
            (Parameter::LambdaM, Law::ArrudaBoyce { lambda_m, .. }, _) => Some(*lambda_m),
            (Parameter::Jm, Law::Gent { jm, .. }, _) => Some(*jm),
            (Parameter::BulkRatio, _, Compressibility::BulkRatio(k)) => Some(*k),
            (Parameter::BulkRatio, _, Compressibility::D(d)) => {
                Some(2.0 / (d * material.shear_modulus()))
            }
            _ => None,
        }
    }

    /// `material` with this parameter set to `value` (the modulus by
    /// scaling every modulus of the law; K₀/μ₀ kept when it scales).
    pub fn set(self, material: &Material, value: f64) -> Material {
        let mut m = material.clone();
        match self {
            Parameter::Modulus => {
                let factor = value / law_modulus(&material.law, material);
                m.law = scaled(&m.law, factor);
                if let Compressibility::D(d) = m.compressibility {
                    m.compressibility = Compressibility::D(d / factor);
                }
            }
            Parameter::LambdaM => {
                if let Law::ArrudaBoyce { lambda_m, .. } = &mut m.law {
                    *lambda_m = value;
                }
            }
            Parameter::Jm => {
                if let Law::Gent { jm, .. } = &mut m.law {
                    *jm = value;
                }
            }
            Parameter::BulkRatio => m.compressibility = Compressibility::BulkRatio(value),
        }
        m
    }
}

/// The law's own modulus: μ of neo-Hookean, Gent and Arruda–Boyce (not the
/// small-strain μ₀, which Arruda–Boyce's λm also sets), C₁₀ + C₀₁ of
/// Mooney–Rivlin, μ₀ = ½ Σ μₚαₚ of Ogden.
fn law_modulus(law: &Law, material: &Material) -> f64 {
    match law {
        Law::NeoHookean { mu_mpa } | Law::Gent { mu_mpa, .. } | Law::ArrudaBoyce { mu_mpa, .. } => {
            *mu_mpa
        }
        Law::MooneyRivlin { c10_mpa, c01_mpa } => c10_mpa + c01_mpa,
        Law::Ogden { .. } => material.shear_modulus(),
    }
}

/// Every modulus of `law` times `factor`.
fn scaled(law: &Law, factor: f64) -> Law {
    match law {
        Law::NeoHookean { mu_mpa } => Law::NeoHookean {
            mu_mpa: mu_mpa * factor,
        },
        Law::MooneyRivlin { c10_mpa, c01_mpa } => Law::MooneyRivlin {
            c10_mpa: c10_mpa * factor,
            c01_mpa: c01_mpa * factor,
        },
        Law::Gent { mu_mpa, jm } => Law::Gent {
            mu_mpa: mu_mpa * factor,
            jm: *jm,
        },
        Law::ArrudaBoyce { mu_mpa, lambda_m } => Law::ArrudaBoyce {
            mu_mpa: mu_mpa * factor,
            lambda_m: *lambda_m,
        },
        Law::Ogden { mu_mpa, alpha } => Law::Ogden {
            mu_mpa: mu_mpa.iter().map(|m| m * factor).collect(),
            alpha: alpha.clone(),
        },
    }
}
