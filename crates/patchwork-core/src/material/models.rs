//! The strain-energy formulas (see the variants of [`Law`] for each W).

use super::hyper::Real;
use super::{Law, MaterialError};

/// Arruda–Boyce series coefficients αᵢ (ABAQUS Theory Manual, eight-chain model).
const ARRUDA_BOYCE: [f64; 5] = [
    0.5,
    1.0 / 20.0,
    11.0 / 1050.0,
    19.0 / 7000.0,
    519.0 / 673_750.0,
];

/// Below this relative eigenvalue gap, Ogden's symmetric function of the two
/// in-plane eigenvalues is evaluated by its Taylor series: the closed form
/// divides by √q, which is singular at equal stretches (the reference state).
const OGDEN_SERIES_GAP: f64 = 1e-6;

/// W(C) of the incompressible material (c₃₃ = 1/det C, J = 1), or `None`
/// outside the physical domain.
pub(super) fn incompressible<T: Real>(model: &Law, c: [T; 3]) -> Option<T> {
    let [c11, c22, c12] = c;
    let det = c11 * c22 - c12 * c12;
    if !(det.value() > 0.0 && c11.value() > 0.0 && c22.value() > 0.0) {
        return None;
    }
    let c33 = T::constant(1.0) / det;
    deviatoric(model, c, c33, None)
}

/// W_dev at in-plane C and thickness c₃₃ = λ₃², in the deviatoric invariants
/// Ī₁ = J^(−2/3) I₁, Ī₂ = J^(−4/3) I₂ with I₁ = c₁₁ + c₂₂ + c₃₃ and
/// I₂ = det C + (c₁₁ + c₂₂) c₃₃; `j` = J, or `None` when J = 1 (incompressible,
/// where the plain invariants are the deviatoric ones). `None` outside the
/// domain (a locking limit). The caller has checked det C > 0 and c₃₃ > 0.
pub(super) fn deviatoric<T: Real>(model: &Law, c: [T; 3], c33: T, j: Option<T>) -> Option<T> {
    let [c11, c22, c12] = c;
    let trace = c11 + c22;
    let scale = |power: f64, x: T| match j {
        Some(j) => x * j.powf(power),
        None => x,
    };
    let i1 = || scale(-2.0 / 3.0, trace + c33);
    match model {
        Law::NeoHookean { .. } | Law::Gent { .. } | Law::ArrudaBoyce { .. } => {
            // W(Ī₁) and its first two derivatives in plain arithmetic
            // (i1_energy, which the thickness solve uses too), then one
            // chain-rule step: far cheaper than the series on AD numbers.
            let i1 = i1();
            let [w, dw, d2w, _] = i1_energy(model, i1.value())?;
            Some(i1.apply(w, dw, d2w))
        }
        Law::MooneyRivlin { c10_mpa, c01_mpa } => {
            let i2 = scale(-4.0 / 3.0, c11 * c22 - c12 * c12 + trace * c33);
            Some((i1() - 3.0) * *c10_mpa + (i2 - 3.0) * *c01_mpa)
        }
        Law::Ogden { mu_mpa, alpha } => {
            let half_trace = trace * 0.5;
            let half_gap = (c11 - c22) * 0.5;
            let q = half_gap * half_gap + c12 * c12;
            let mut w = T::constant(0.0);
            for (mu, a) in mu_mpa.iter().zip(alpha) {
                let p = a / 2.0;
                let sum = symmetric_power_sum(half_trace, q, p) + c33.powf(p);
                w = w + (scale(-a / 3.0, sum) - 3.0) * (mu / a);
            }
            Some(w)
        }
    }
}

/// W(Ī₁) with its first three derivatives in Ī₁ for the laws that depend on
/// Ī₁ alone (the Ī₁ part of Mooney–Rivlin too); `None` for Ogden, or past
/// Gent's lock. The third serves the thickness solve's Halley steps.
#[inline]
pub(super) fn i1_energy(model: &Law, x: f64) -> Option<[f64; 4]> {
    match model {
        Law::NeoHookean { mu_mpa } => Some([0.5 * mu_mpa * (x - 3.0), 0.5 * mu_mpa, 0.0, 0.0]),
        Law::MooneyRivlin { c10_mpa, .. } => Some([c10_mpa * (x - 3.0), *c10_mpa, 0.0, 0.0]),
        Law::Gent { mu_mpa, jm } => {
            // W = −(μ J_m/2) ln A with A = 1 − (Ī₁ − 3)/J_m: W′ = μ/(2A),
            // W″ = W′/(J_m A), W‴ = 2 W″/(J_m A).
            let argument = 1.0 - (x - 3.0) / jm;
            (argument > 0.0).then(|| {
                let dw = 0.5 * mu_mpa / argument;
                let d2w = dw / (jm * argument);
                [
                    -0.5 * mu_mpa * jm * argument.ln(),
                    dw,
                    d2w,
                    2.0 * d2w / (jm * argument),
                ]
            })
        }
        Law::ArrudaBoyce { mu_mpa, lambda_m } => {
            // W = Σᵢ cᵢ (xⁱ − 3ⁱ), cᵢ = μ αᵢ / λ_m^(2i−2), i = 1..5.
            let mut w = [0.0; 4];
            for (k, alpha) in ARRUDA_BOYCE.iter().enumerate() {
                let i = k as i32 + 1;
                let c = mu_mpa * alpha / lambda_m.powi(2 * i - 2);
                let fi = i as f64;
                w[0] += c * (x.powi(i) - 3f64.powi(i));
                w[1] += c * fi * x.powi(i - 1);
                // The factors vanish below i = 2 and 3: skip the negative powers.
                if i >= 2 {
                    w[2] += c * fi * (fi - 1.0) * x.powi(i - 2);
                }
                if i >= 3 {
                    w[3] += c * fi * (fi - 1.0) * (fi - 2.0) * x.powi(i - 3);
                }
            }
            Some(w)
        }
        Law::Ogden { .. } => None,
    }
}

/// e₁ᵖ + e₂ᵖ for the eigenvalues e = m ± √q of a symmetric 2×2 matrix, smooth
/// through q = 0: there f(m+d) + f(m−d) = 2f(m) + f″(m) q + f⁗(m) q²/12 + O(q³).
pub(super) fn symmetric_power_sum<T: Real>(m: T, q: T, p: f64) -> T {
    if q.value() > OGDEN_SERIES_GAP * OGDEN_SERIES_GAP * m.value() * m.value() {
        let d = q.sqrt();
        (m + d).powf(p) + (m - d).powf(p)
    } else {
        let f2 = p * (p - 1.0);
        let f4 = f2 * (p - 2.0) * (p - 3.0);
        m.powf(p) * 2.0 + m.powf(p - 2.0) * q * f2 + m.powf(p - 4.0) * q * q * (f4 / 12.0)
    }
}

pub(super) fn shear_modulus(model: &Law) -> f64 {
    match model {
        Law::NeoHookean { mu_mpa } => *mu_mpa,
        Law::MooneyRivlin { c10_mpa, c01_mpa } => 2.0 * (c10_mpa + c01_mpa),
        Law::Gent { mu_mpa, .. } => *mu_mpa,
        Law::ArrudaBoyce { mu_mpa, lambda_m } => {
            // μ₀ = 2 ∂W/∂I₁ at I₁ = 3.
            let series: f64 = ARRUDA_BOYCE
                .iter()
                .enumerate()
                .map(|(k, a)| {
                    let i = k as i32 + 1;
                    a * i as f64 * 3f64.powi(i - 1) / lambda_m.powi(2 * i - 2)
                })
                .sum();
            2.0 * mu_mpa * series
        }
        Law::Ogden { mu_mpa, alpha } => {
            0.5 * mu_mpa.iter().zip(alpha).map(|(m, a)| m * a).sum::<f64>()
        }
    }
}

pub(super) fn validate(material: &Law) -> Result<(), MaterialError> {
    let model = material.name();
    let fail = |field, value, reason| {
        Err(MaterialError {
            model,
            field,
            value,
            reason,
        })
    };
    let positive = |field: &'static str, value: f64| {
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            fail(field, value, "must be finite and positive")
        }
    };
    match material {
        Law::NeoHookean { mu_mpa } => positive("mu_mpa", *mu_mpa),
        Law::MooneyRivlin { c10_mpa, c01_mpa } => {
            positive("c10_mpa", *c10_mpa)?;
            if !(c01_mpa.is_finite() && *c01_mpa >= 0.0) {
                return fail("c01_mpa", *c01_mpa, "must be finite and non-negative");
            }
            Ok(())
        }
        Law::Gent { mu_mpa, jm } => {
            positive("mu_mpa", *mu_mpa)?;
            positive("jm", *jm)
        }
        Law::ArrudaBoyce { mu_mpa, lambda_m } => {
            positive("mu_mpa", *mu_mpa)?;
            if !(lambda_m.is_finite() && *lambda_m > 1.0) {
                return fail("lambda_m", *lambda_m, "must be finite and greater than 1");
            }
            Ok(())
        }
        Law::Ogden { mu_mpa, alpha } => {
            if mu_mpa.is_empty() || mu_mpa.len() != alpha.len() || mu_mpa.len() > 6 {
                return fail(
                    "alpha",
                    alpha.len() as f64,
                    "mu_mpa and alpha need the same number (1 to 6) of terms",
                );
            }
            for (m, a) in mu_mpa.iter().zip(alpha) {
                if !m.is_finite() || *m == 0.0 {
                    return fail("mu_mpa", *m, "each term must be finite and non-zero");
                }
                if !a.is_finite() || *a == 0.0 {
                    return fail("alpha", *a, "each term must be finite and non-zero");
                }
                if m * a <= 0.0 {
                    return fail("mu_mpa", *m, "each μₚαₚ must be positive (stability)");
                }
            }
            Ok(())
        }
    }
}
