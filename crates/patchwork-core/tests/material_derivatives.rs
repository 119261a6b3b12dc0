//! For every material, incompressible and compressible: stress from energy
//! and tangent from stress against central finite differences; stress-free
//! reference state; small-strain shear and bulk moduli; admissibility barriers.

use patchwork_core::material::{Compressibility, Law, Material};

fn models() -> Vec<Law> {
    vec![
        Law::NeoHookean { mu_mpa: 0.5 },
        Law::MooneyRivlin {
            c10_mpa: 0.3,
            c01_mpa: 0.08,
        },
        Law::Gent {
            mu_mpa: 0.4,
            jm: 30.0,
        },
        Law::ArrudaBoyce {
            mu_mpa: 0.317,
            lambda_m: 2.3,
        },
        Law::Ogden {
            mu_mpa: vec![0.6, 0.002, -0.01],
            alpha: vec![1.3, 5.0, -2.0],
        },
    ]
}

/// Each model incompressible, at ABAQUS/Explicit's K₀/μ₀ = 20, nearly
/// incompressible (K₀/μ₀ = 1000) and quite compressible (K₀/μ₀ = 3, which
/// thins a membrane little under tension); Ogden also with D₁ given.
fn all_materials() -> Vec<Material> {
    let mut all = Vec::new();
    for model in models() {
        all.push(Material::incompressible(model.clone()));
        for ratio in [20.0, 1000.0, 3.0] {
            all.push(Material::compressible(
                model.clone(),
                Compressibility::BulkRatio(ratio),
            ));
        }
    }
    all.push(Material::compressible(
        Law::Ogden {
            mu_mpa: vec![0.6, 0.002, -0.01],
            alpha: vec![1.3, 5.0, -2.0],
        },
        Compressibility::D(0.2),
    ));
    all
}

fn name(material: &Material) -> String {
    format!("{} {:?}", material.model_name(), material.compressibility)
}

/// In-plane C states: stretched, sheared, compressed, near-equibiaxial (Ogden's
/// series branch), and the reference state.
fn states() -> Vec<[f64; 3]> {
    vec![
        [1.0, 1.0, 0.0],
        [2.3, 1.4, 0.3],
        [0.7, 3.1, -0.4],
        [1.9, 1.9 + 1e-9, 0.0],
        [4.0, 1.1, 0.9],
    ]
}

/// Tolerances: central differences with step h = 1e-6 leave errors of order
/// h²·W‴ ≈ 1e-12 plus rounding ≈ 1e-16/h ≈ 1e-10; we demand 1e-6 relative.
#[test]
fn stress_is_the_derivative_of_energy() {
    let h = 1e-6;
    for material in all_materials() {
        for c in states() {
            let r = material.response(c);
            assert!(r.is_admissible());
            for k in 0..3 {
                let (mut plus, mut minus) = (c, c);
                plus[k] += h;
                minus[k] -= h;
                let fd = (material.energy(plus) - material.energy(minus)) / (2.0 * h);
                let scale = 1.0 + r.gradient[k].abs();
                assert!(
                    (fd - r.gradient[k]).abs() < 1e-6 * scale,
                    "{} at {c:?}: ∂W/∂c{k} = {} vs FD {fd}",
                    name(&material),
                    r.gradient[k]
                );
            }
        }
    }
}

#[test]
fn tangent_is_the_derivative_of_stress() {
    // 1e-5, not 1e-6: a nearly incompressible material's stress carries the
    // thickness solve's rounding (≈ 1e-11 at K₀/μ₀ = 1000), which a smaller
    // step would amplify past the tolerance; truncation stays ≈ 1e-10.
    let h = 1e-5;
    for material in all_materials() {
        for c in states() {
            let r = material.response(c);
            for k in 0..3 {
                let (mut plus, mut minus) = (c, c);
                plus[k] += h;
                minus[k] -= h;
                let (gp, gm) = (
                    material.response(plus).gradient,
                    material.response(minus).gradient,
                );
                for i in 0..3 {
                    let fd = (gp[i] - gm[i]) / (2.0 * h);
                    let scale = 1.0 + r.hessian[i][k].abs();
                    assert!(
                        (fd - r.hessian[i][k]).abs() < 1e-5 * scale,
                        "{} at {c:?}: ∂²W/∂c{i}∂c{k} = {} vs FD {fd}",
                        name(&material),
                        r.hessian[i][k]
                    );
                }
            }
        }
    }
}

#[test]
fn reference_state_is_stress_free_with_the_stated_shear_modulus() {
    for material in all_materials() {
        let r = material.response([1.0, 1.0, 0.0]);
        assert!(r.energy.abs() < 1e-14, "{}", name(&material));
        for g in r.gradient {
            assert!(g.abs() < 1e-12, "{} not stress-free", name(&material));
        }
        // Simple shear γ in the plane: W ≈ μ γ²/2 (C = [[1, γ], [γ, 1 + γ²]]).
        let gamma = 1e-4;
        let w = material.energy([1.0, 1.0 + gamma * gamma, gamma]);
        let mu = 2.0 * w / (gamma * gamma);
        assert!(
            (mu - material.shear_modulus()).abs() < 1e-4 * material.shear_modulus(),
            "{}: μ from shear {mu} vs {}",
            name(&material),
            material.shear_modulus()
        );
    }
}

#[test]
fn inadmissible_states_have_infinite_energy() {
    for material in all_materials() {
        assert_eq!(material.energy([1.0, 1.0, 1.0]), f64::INFINITY); // det C = 0
        assert_eq!(material.energy([-1.0, 1.0, 0.0]), f64::INFINITY);
        assert_eq!(material.energy([f64::NAN, 1.0, 0.0]), f64::INFINITY);
    }
    let gent = Law::Gent {
        mu_mpa: 1.0,
        jm: 2.0,
    };
    for gent in [
        Material::incompressible(gent.clone()),
        Material::compressible(gent, Compressibility::abaqus_explicit()),
    ] {
        assert_eq!(gent.energy([4.0, 1.0, 0.0]), f64::INFINITY); // past locking
    }
}

/// Small equibiaxial strain ε in the plane, plane stress: a linear solid
/// thins by ε₃ = −2ν/(1 − ν) ε with ν = (3K₀ − 2μ₀)/(2(3K₀ + μ₀)), so the
/// thickness stretch checks K₀ = 2/D₁ against μ₀ (ν = ½: ε₃ = −2ε).
#[test]
fn small_strain_thinning_follows_the_stated_bulk_modulus() {
    let eps = 1e-5;
    for material in all_materials() {
        let (k, mu) = (material.bulk_modulus(), material.shear_modulus());
        let nu = if k.is_finite() {
            (3.0 * k - 2.0 * mu) / (2.0 * (3.0 * k + mu))
        } else {
            0.5
        };
        let c = 1.0 + 2.0 * eps;
        let l3 = material.thickness_stretch([c, c, 0.0]).unwrap();
        let expected = -2.0 * nu / (1.0 - nu) * eps;
        assert!(
            ((l3 - 1.0) - expected).abs() < 1e-3 * expected.abs(),
            "{}: ε₃ {} vs {expected}",
            name(&material),
            l3 - 1.0
        );
    }
    // ABAQUS/Explicit's default: Poisson's ratio 0.475.
    let m = Material::reference_balloon().with_compressibility(Compressibility::abaqus_explicit());
    let ratio = m.bulk_modulus() / m.shear_modulus();
    assert!((ratio - 20.0).abs() < 1e-12);
}

#[test]
fn ogden_with_one_term_alpha_two_is_neo_hookean() {
    let ogden = Law::Ogden {
        mu_mpa: vec![0.7],
        alpha: vec![2.0],
    };
    let neo = Law::NeoHookean { mu_mpa: 0.7 };
    for compressibility in [
        Compressibility::Incompressible,
        Compressibility::BulkRatio(20.0),
    ] {
        let ogden = Material::compressible(ogden.clone(), compressibility);
        let neo = Material::compressible(neo.clone(), compressibility);
        for c in states() {
            assert!((ogden.energy(c) - neo.energy(c)).abs() < 1e-12);
        }
    }
}

#[test]
fn invalid_parameters_name_the_field() {
    let incompressible = |model| Material::incompressible(model);
    let neo = Law::NeoHookean { mu_mpa: 1.0 };
    let with = |c| Material::compressible(neo.clone(), c);
    let cases = [
        (incompressible(Law::NeoHookean { mu_mpa: -1.0 }), "mu_mpa"),
        (
            incompressible(Law::Gent {
                mu_mpa: 1.0,
                jm: f64::NAN,
            }),
            "jm",
        ),
        (
            incompressible(Law::ArrudaBoyce {
                mu_mpa: 1.0,
                lambda_m: 0.9,
            }),
            "lambda_m",
        ),
        (
            incompressible(Law::MooneyRivlin {
                c10_mpa: 0.2,
                c01_mpa: -0.1,
            }),
            "c01_mpa",
        ),
        (
            incompressible(Law::Ogden {
                mu_mpa: vec![1.0],
                alpha: vec![],
            }),
            "alpha",
        ),
        (
            incompressible(Law::Ogden {
                mu_mpa: vec![1.0],
                alpha: vec![-2.0],
            }),
            "mu_mpa",
        ),
        (with(Compressibility::BulkRatio(0.5)), "bulk_ratio"),
        (
            with(Compressibility::BulkRatio(f64::INFINITY)),
            "bulk_ratio",
        ),
        (with(Compressibility::D(-0.1)), "d"),
        (with(Compressibility::D(f64::NAN)), "d"),
    ];
    for (material, field) in cases {
        assert_eq!(material.validate().unwrap_err().field, field);
    }
    for m in all_materials() {
        m.validate().unwrap();
    }
}

#[test]
fn json_schema_matches_the_contract() {
    let m: Material =
        serde_json::from_str(r#"{"model": "arruda_boyce", "mu_mpa": 0.317, "lambda_m": 2.3}"#)
            .unwrap();
    assert_eq!(m, Material::reference_balloon());
    let m: Material =
        serde_json::from_str(r#"{"model": "ogden", "mu_mpa": [0.5], "alpha": [2]}"#).unwrap();
    assert!(matches!(m.law, Law::Ogden { .. }));
    assert!(serde_json::from_str::<Material>(r#"{"model": "rubber"}"#).is_err());
    assert!(serde_json::from_str::<Material>(r#"{"model": "gent", "mu_mpa": 1}"#).is_err());
}
