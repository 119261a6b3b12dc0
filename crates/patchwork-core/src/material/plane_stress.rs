//! Plane stress of a compressible membrane: the thickness stretch from
//! σ₃₃ = 0, condensed exactly.
//!
//! At in-plane C the energy W(C, c₃₃) = W_dev(Ī₁, Ī₂) + U(J) is minimised over
//! c₃₃ = λ₃² (∂W/∂c₃₃ = ½ S₃₃ = 0, and S₃₃ = 0 ⇔ σ₃₃ = 0), by Newton's method on
//! ln J in plain arithmetic ([`thickness`]). The condensed energy W̄(C) = W(C, c₃₃(C)) then has
//!
//!   ∂W̄/∂C = ∂W/∂C                     (envelope theorem: ∂W/∂c₃₃ = 0),
//!   ∂²W̄/∂C² = W_CC − W_C3 W_3C / W_33  (differentiating ∂W/∂c₃₃ = 0).
//!
//! Both come from one evaluation on `Hyper<4>` numbers at the solution; a
//! caller's own variables (a laminate's jump) get them by the chain rule
//! through a second-order Taylor composition ([`compose`]).

use super::Law;
use super::hyper::{Hyper, Real};
use super::models::deviatoric;
use super::thickness;
use super::volumetric::Volumetric;

/// W(C, c₃₃) for a compressible material; `None` outside the domain.
fn energy<T: Real>(model: &Law, u: &Volumetric, c: [T; 3], c33: T) -> Option<T> {
    let [c11, c22, c12] = c;
    let det = c11 * c22 - c12 * c12;
    if !(det.value() > 0.0 && c33.value() > 0.0) {
        return None;
    }
    let j = (det * c33).sqrt();
    let w = deviatoric(model, c, c33, Some(j))? + u.energy(j);
    w.value().is_finite().then_some(w)
}

/// c₃₃ = λ₃² with ∂W/∂c₃₃ = 0 at in-plane C, or `None` outside the domain.
pub(super) fn thickness_c33(model: &Law, u: &Volumetric, c: [f64; 3]) -> Option<f64> {
    let (ln_j, _) = thickness::solve(model, u, c)?;
    Some(c33_of(ln_j, c))
}

/// c₃₃ = J²/det C.
fn c33_of(ln_j: f64, c: [f64; 3]) -> f64 {
    (2.0 * ln_j).exp() / (c[0] * c[1] - c[2] * c[2])
}

/// W̄(C) = W(C, c₃₃(C)) in any number type, with exact derivatives.
pub(super) fn condensed<T: Real>(model: &Law, u: &Volumetric, c: [T; 3]) -> Option<T> {
    let c0 = c.map(|x| x.value());
    let (ln_j, w) = thickness::solve(model, u, c0)?;
    if !T::CARRIES_DERIVATIVES {
        return w.is_finite().then(|| T::constant(w));
    }
    let c33 = c33_of(ln_j, c0);
    let w = energy(
        model,
        u,
        [
            Hyper::<4>::variable(c0[0], 0),
            Hyper::<4>::variable(c0[1], 1),
            Hyper::<4>::variable(c0[2], 2),
        ],
        Hyper::<4>::variable(c33, 3),
    )?;
    let w33 = w.hessian[3][3];
    if w33.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let gradient = [w.gradient[0], w.gradient[1], w.gradient[2]];
    let mut hessian = [[0.0; 3]; 3];
    for (i, row) in hessian.iter_mut().enumerate() {
        for (k, entry) in row.iter_mut().enumerate() {
            *entry = w.hessian[i][k] - w.hessian[i][3] * w.hessian[3][k] / w33;
        }
    }
    Some(compose(c, c0, w.value, gradient, hessian))
}

/// A function of C known by its value, gradient and Hessian at C₀, composed
/// with C(v) for the caller's variables v: W₀ + g·δ + ½ δᵀHδ with δ = C − C₀.
/// δ is zero at v, so the result's value, gradient and Hessian in v are
/// exactly the chain rule's to second order.
fn compose<T: Real>(
    c: [T; 3],
    c0: [f64; 3],
    value: f64,
    gradient: [f64; 3],
    hessian: [[f64; 3]; 3],
) -> T {
    let delta = [c[0] - c0[0], c[1] - c0[1], c[2] - c0[2]];
    let mut out = T::constant(value);
    for i in 0..3 {
        let mut row = delta[i] * (0.5 * hessian[i][i]);
        for k in (i + 1)..3 {
            row = row + delta[k] * hessian[i][k];
        }
        out = out + delta[i] * gradient[i] + delta[i] * row;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Compressibility, Material};

    fn compressible_neo_hookean() -> (Law, Volumetric) {
        let model = Law::NeoHookean { mu_mpa: 1.0 };
        let u = Volumetric::of(&model, &Compressibility::BulkRatio(20.0)).unwrap();
        (model, u)
    }

    #[test]
    fn the_thickness_makes_the_normal_stress_vanish() {
        let (model, u) = compressible_neo_hookean();
        for c in [
            [1.0, 1.0, 0.0],
            [4.0, 2.0, 0.5],
            [27.0, 13.5, 0.0],
            [0.6, 1.3, 0.1],
        ] {
            let c33 = thickness_c33(&model, &u, c).unwrap();
            let h = 1e-6 * c33;
            let fd = (energy(&model, &u, c, c33 + h).unwrap()
                - energy(&model, &u, c, c33 - h).unwrap())
                / (2.0 * h);
            assert!(
                fd.abs() < 1e-7 * (1.0 + energy(&model, &u, c, c33).unwrap()),
                "C {c:?}: ∂W/∂c33 = {fd}"
            );
        }
        assert!((thickness_c33(&model, &u, [1.0, 1.0, 0.0]).unwrap() - 1.0).abs() < 1e-12);
    }

    /// Compressible neo-Hookean: the Cauchy stress is (μ/J) dev(J^(−2/3) b)
    /// plus U′(J) I with U′ = K(J − 1), K = 2/D₁, so σ₃₃ = 0 reads
    /// μ J^(−2/3)(c₃₃ − I₁/3) + K(J − 1)J = 0 (μ = 1 here).
    #[test]
    fn neo_hookean_thickness_matches_the_cauchy_stress_condition() {
        let (model, u) = compressible_neo_hookean();
        let k = u.bulk_modulus();
        for c in [[4.0, 2.0, 0.0], [9.0, 4.0, 1.0], [2.0, 0.5, 0.2]] {
            let c33 = thickness_c33(&model, &u, c).unwrap();
            let det = c[0] * c[1] - c[2] * c[2];
            let j = (det * c33).sqrt();
            let i1 = c[0] + c[1] + c33;
            let sigma_j = j.powf(-2.0 / 3.0) * (c33 - i1 / 3.0) + k * (j - 1.0) * j;
            assert!(sigma_j.abs() < 1e-10, "C {c:?}: σ33 J = {sigma_j}");
        }
    }

    #[test]
    fn a_large_bulk_ratio_approaches_the_incompressible_material() {
        let model = Law::ArrudaBoyce {
            mu_mpa: 0.317,
            lambda_m: 2.3,
        };
        let stiff = Material::compressible(model.clone(), Compressibility::BulkRatio(1e5));
        let exact = Material::incompressible(model);
        for c in [[2.0, 1.5, 0.2], [9.0, 4.0, 0.0]] {
            let (a, b) = (stiff.response(c), exact.response(c));
            assert!(
                (a.energy - b.energy).abs() < 1e-4 * b.energy,
                "{a:?} vs {b:?}"
            );
            for k in 0..3 {
                assert!(
                    (a.gradient[k] - b.gradient[k]).abs() < 1e-3 * b.gradient[k].abs().max(0.1)
                );
            }
        }
    }
}
