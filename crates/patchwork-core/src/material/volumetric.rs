//! The volumetric part U(J) of a compressible material, as ABAQUS defines it
//! for each model (ABAQUS Theory Manual, "Hyperelastic material behavior"):
//!
//! - polynomial forms (neo-Hookean, Mooney–Rivlin) and Ogden:
//!   U = Σᵢ (1/Dᵢ)(J − 1)^(2i), of which the first term (D₁) is taken;
//! - Arruda–Boyce (and Gent here): U = (1/D)((J² − 1)/2 − ln J).
//!
//! Both give the initial bulk modulus K₀ = 2/D₁. ABAQUS/Explicit, which cannot
//! impose incompressibility, takes D = 0 as K₀/μ₀ = 20 (Poisson's ratio
//! ν₀ = (3K₀/μ₀ − 2)/(6K₀/μ₀ + 2) = 0.475): that is the authors' balloon.

use super::hyper::Real;
use super::{Law, MaterialError, models};

/// K₀/μ₀ that ABAQUS/Explicit assumes for a hyperelastic material given D = 0.
pub const ABAQUS_EXPLICIT_BULK_RATIO: f64 = 20.0;

/// How a material resists a change of volume.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Compressibility {
    /// J = 1 exactly.
    Incompressible,
    /// K₀/μ₀, the initial bulk to shear modulus ratio (D₁ = 2/(K₀/μ₀ · μ₀)).
    BulkRatio(f64),
    /// ABAQUS's D₁ (1/MPa): K₀ = 2/D₁.
    D(f64),
}

impl Compressibility {
    /// ABAQUS/Explicit's assumption for a hyperelastic material given D = 0,
    /// K₀/μ₀ = 20: the authors' balloon and patch.
    pub fn abaqus_explicit() -> Compressibility {
        Compressibility::BulkRatio(ABAQUS_EXPLICIT_BULK_RATIO)
    }
}

impl std::fmt::Display for Compressibility {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Compressibility::Incompressible => write!(f, "incompressible"),
            Compressibility::BulkRatio(r) => write!(f, "K₀/μ₀ = {r}"),
            Compressibility::D(d) => write!(f, "D₁ = {d} /MPa"),
        }
    }
}

/// U(J) resolved for one material: its form and its D₁. Built at every
/// evaluation, so it holds plain numbers (no allocation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Volumetric {
    /// (1/D)((J² − 1)/2 − ln J) (Arruda–Boyce, Gent), else (1/D)(J − 1)².
    logarithmic: bool,
    d: f64,
}

impl Volumetric {
    /// `None` when incompressible.
    pub(super) fn of(model: &Law, compressibility: &Compressibility) -> Option<Volumetric> {
        let d = match compressibility {
            Compressibility::Incompressible => return None,
            Compressibility::BulkRatio(ratio) => 2.0 / (ratio * models::shear_modulus(model)),
            Compressibility::D(d) => *d,
        };
        let logarithmic = matches!(model, Law::ArrudaBoyce { .. } | Law::Gent { .. });
        Some(Volumetric { logarithmic, d })
    }

    /// K₀ = 2/D₁ (MPa).
    pub(super) fn bulk_modulus(&self) -> f64 {
        2.0 / self.d
    }

    /// U(J); J > 0 is the caller's.
    pub(super) fn energy<T: Real>(&self, j: T) -> T {
        if self.logarithmic {
            ((j * j - 1.0) * 0.5 - j.ln()) / self.d
        } else {
            (j - 1.0) * (j - 1.0) / self.d
        }
    }

    /// U and its first three derivatives in y = ln J, given y and J = eʸ
    /// (d/dy = J d/dJ):
    ///
    /// - logarithmic, U = ((J² − 1)/2 − y)/D: U′ = (J² − 1)/D, U″ = 2J²/D,
    ///   U‴ = 4J²/D;
    /// - polynomial, U = (J − 1)²/D: U′ = 2(J² − J)/D, U″ = (4J² − 2J)/D,
    ///   U‴ = (8J² − 2J)/D.
    pub(super) fn along_ln_j(&self, y: f64, j: f64) -> [f64; 4] {
        let (d, j2) = (self.d, j * j);
        if self.logarithmic {
            [
                ((j2 - 1.0) * 0.5 - y) / d,
                (j2 - 1.0) / d,
                2.0 * j2 / d,
                4.0 * j2 / d,
            ]
        } else {
            let x = j - 1.0;
            [
                x * x / d,
                2.0 * (j2 - j) / d,
                (4.0 * j2 - 2.0 * j) / d,
                (8.0 * j2 - 2.0 * j) / d,
            ]
        }
    }
}

pub(super) fn validate(
    model: &Law,
    compressibility: &Compressibility,
) -> Result<(), MaterialError> {
    let fail = |field, value, reason| {
        Err(MaterialError {
            model: model.name(),
            field,
            value,
            reason,
        })
    };
    match compressibility {
        Compressibility::Incompressible => Ok(()),
        Compressibility::BulkRatio(ratio) => {
            // K₀/μ₀ ≥ 1 (Poisson's ratio ≥ 0.125): rubbers lie far above it.
            if ratio.is_finite() && (1.0..=1e6).contains(ratio) {
                Ok(())
            } else {
                fail(
                    "bulk_ratio",
                    *ratio,
                    "must be within 1 to 1e6 (rubber: about 20 to 1e4; use incompressible above)",
                )
            }
        }
        Compressibility::D(d) => {
            if d.is_finite() && *d > 0.0 && *d <= 1e6 {
                Ok(())
            } else {
                fail("d", *d, "must be positive and at most 1e6 1/MPa")
            }
        }
    }
}
