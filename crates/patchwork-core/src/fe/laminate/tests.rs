//! The laminate's derivatives against finite differences, against the area
//! average and a one-dimensional laminate, its domain limits, and its kept
//! thickness starts.

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

/// A laminate whose phases keep their last thickness answers as a cold
/// one does, whether its last state was near (a Newton step away) or far.
#[test]
fn kept_thickness_starts_change_the_start_not_the_answer() {
    let m = materials();
    for (share, angle, covered, bare) in [(0.3, 30.0, 1, 0), (0.97, 10.0, 3, 2)] {
        let cold = laminate(share, angle, covered, bare);
        let mut warm = cold.clone();
        warm.keep_starts(m.len());
        for (before, c) in [(STATES[1], STATES[0]), ([2.61, 1.69, 0.31], STATES[0])] {
            warm.response(before, &m).unwrap();
            assert!(warm.kept.iter().flatten().any(|k| k.get() != [0.0]));
            let (a, b) = (cold.response(c, &m).unwrap(), warm.response(c, &m).unwrap());
            let close = |x: f64, y: f64, scale: f64| (x - y).abs() <= 1e-9 * scale;
            assert!(close(a.energy, b.energy, a.energy.abs()), "{a:?} vs {b:?}");
            let g = a.gradient.iter().map(|g| g.abs()).sum::<f64>();
            assert!(
                (0..3).all(|k| close(a.gradient[k], b.gradient[k], g)),
                "{a:?} vs {b:?}"
            );
            let h = a.hessian.iter().flatten().map(|h| h.abs()).sum::<f64>();
            let hessians = a.hessian.iter().flatten().zip(b.hessian.iter().flatten());
            assert!(
                hessians.into_iter().all(|(x, y)| close(*x, *y, h)),
                "{a:?} vs {b:?}"
            );
            assert!(close(
                cold.energy(c, &m),
                warm.energy(c, &m),
                a.energy.abs()
            ));
        }
    }
}

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
