//! The material parameters a calibration can fit, read from and written
//! into a `Material`: the moduli together (`modulus`: every modulus of the
//! law scaled alike; its value is μ of neo-Hookean, Arruda–Boyce and Gent,
//! C₁₀ + C₀₁ of Mooney–Rivlin, μ₀ of Ogden), the law's
//! stiffening (`lambda_m` of Arruda–Boyce, `jm` of Gent), the
//! compressibility (`bulk_ratio`, K₀/μ₀) — all of the balloon's material —
//! and the patch material's moduli together (`patch_modulus`).

use serde::{Deserialize, Serialize};

use crate::material::{Compressibility, Law, Material};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Parameter {
    Modulus,
    LambdaM,
    Jm,
    BulkRatio,
    PatchModulus,
}

/// The two materials a calibration fits: the balloon's and the patches'.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Materials {
    pub balloon: Material,
    pub patch: Material,
}

impl Materials {
    /// `design` made of these materials (its geometry and patches kept).
    pub fn on(&self, design: &crate::design::Design) -> crate::design::Design {
        let mut design = design.clone();
        design.balloon.material = self.balloon.clone();
        design.patch.material = self.patch.clone();
        design
    }
}

const ALL: [Parameter; 5] = [
    Parameter::Modulus,
    Parameter::LambdaM,
    Parameter::Jm,
    Parameter::BulkRatio,
    Parameter::PatchModulus,
];

impl Parameter {
    /// What to fit when the user does not say: the modulus; the law's
    /// stiffening where the bare balloon was measured (its length and
    /// diameter over pressures tell it); the patch's modulus where built
    /// designs were.
    pub fn defaults(balloon: &Material, data: &super::data::Measurements) -> Vec<Parameter> {
        let stiffening = match balloon.law {
            Law::ArrudaBoyce { .. } => Some(Parameter::LambdaM),
            Law::Gent { .. } => Some(Parameter::Jm),
            _ => None,
        };
        let bare = !(data.inflation.is_empty() && data.pressure_volume.is_empty());
        let patch = !data.built.is_empty();
        [Some(Parameter::Modulus)]
            .into_iter()
            .chain([
                stiffening.filter(|_| bare),
                patch.then_some(Parameter::PatchModulus),
            ])
            .flatten()
            .collect()
    }

    pub fn name(self) -> &'static str {
        match self {
            Parameter::Modulus => "modulus",
            Parameter::LambdaM => "lambda_m",
            Parameter::Jm => "jm",
            Parameter::BulkRatio => "bulk_ratio",
            Parameter::PatchModulus => "patch_modulus",
        }
    }

    /// A parameter named as on the command line.
    pub fn from_name(name: &str) -> Option<Parameter> {
        ALL.into_iter().find(|p| p.name() == name)
    }

    /// Every parameter's name, for messages.
    pub fn names() -> String {
        ALL.map(Parameter::name).join(", ")
    }

    /// Whether the parameter belongs to the patch's material (which only a
    /// built design's measurement can tell).
    pub fn of_patch(self) -> bool {
        self == Parameter::PatchModulus
    }

    /// Its value in `materials`; none where the material has no such
    /// parameter.
    pub fn value(self, materials: &Materials) -> Option<f64> {
        match self {
            Parameter::PatchModulus => Some(law_modulus(&materials.patch.law, &materials.patch)),
            _ => self.get(&materials.balloon),
        }
    }

    /// `materials` with this parameter set to `value`.
    pub fn with(self, materials: &Materials, value: f64) -> Materials {
        match self {
            Parameter::PatchModulus => Materials {
                patch: Parameter::Modulus.set(&materials.patch, value),
                balloon: materials.balloon.clone(),
            },
            _ => Materials {
                balloon: self.set(&materials.balloon, value),
                patch: materials.patch.clone(),
            },
        }
    }

    /// Its value in the balloon's `material`; none where the material has
    /// no such parameter (λm of a neo-Hookean law, K₀/μ₀ of an
    /// incompressible one, the patch's modulus).
    fn get(self, material: &Material) -> Option<f64> {
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
    fn set(self, material: &Material, value: f64) -> Material {
        let mut m = material.clone();
        match self {
            Parameter::Modulus | Parameter::PatchModulus => {
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
