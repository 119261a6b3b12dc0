//! For every material: stress from energy and tangent from stress against
//! central finite differences; stress-free reference state; small-strain
//! shear modulus; admissibility barriers.

use patchwork_core::material::Material;

fn all_materials() -> Vec<Material> {
    vec![
        Material::NeoHookean { mu_mpa: 0.5 },
        Material::MooneyRivlin {
            c10_mpa: 0.3,
            c01_mpa: 0.08,
        },
        Material::Gent {
            mu_mpa: 0.4,
            jm: 30.0,
        },
        Material::reference_balloon(),
        Material::Ogden {
            mu_mpa: vec![0.6, 0.002, -0.01],
            alpha: vec![1.3, 5.0, -2.0],
        },
    ]
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
                    material.model_name(),
                    r.gradient[k]
                );
            }
        }
    }
}

#[test]
fn tangent_is_the_derivative_of_stress() {
    let h = 1e-6;
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
                        material.model_name(),
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
        assert!(r.energy.abs() < 1e-14, "{}", material.model_name());
        for g in r.gradient {
            assert!(g.abs() < 1e-12, "{} not stress-free", material.model_name());
        }
        // Simple shear γ in the plane: W ≈ μ γ²/2 (C = [[1, γ], [γ, 1 + γ²]]).
        let gamma = 1e-4;
        let w = material.energy([1.0, 1.0 + gamma * gamma, gamma]);
        let mu = 2.0 * w / (gamma * gamma);
        assert!(
            (mu - material.shear_modulus()).abs() < 1e-4 * material.shear_modulus(),
            "{}: μ from shear {mu} vs {}",
            material.model_name(),
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
    let gent = Material::Gent {
        mu_mpa: 1.0,
        jm: 2.0,
    };
    assert_eq!(gent.energy([4.0, 1.0, 0.0]), f64::INFINITY); // past locking
}

#[test]
fn ogden_with_one_term_alpha_two_is_neo_hookean() {
    let ogden = Material::Ogden {
        mu_mpa: vec![0.7],
        alpha: vec![2.0],
    };
    let neo = Material::NeoHookean { mu_mpa: 0.7 };
    for c in states() {
        assert!((ogden.energy(c) - neo.energy(c)).abs() < 1e-12);
    }
}

#[test]
fn invalid_parameters_name_the_field() {
    let cases = [
        (Material::NeoHookean { mu_mpa: -1.0 }, "mu_mpa"),
        (
            Material::Gent {
                mu_mpa: 1.0,
                jm: f64::NAN,
            },
            "jm",
        ),
        (
            Material::ArrudaBoyce {
                mu_mpa: 1.0,
                lambda_m: 0.9,
            },
            "lambda_m",
        ),
        (
            Material::MooneyRivlin {
                c10_mpa: 0.2,
                c01_mpa: -0.1,
            },
            "c01_mpa",
        ),
        (
            Material::Ogden {
                mu_mpa: vec![1.0],
                alpha: vec![],
            },
            "alpha",
        ),
        (
            Material::Ogden {
                mu_mpa: vec![1.0],
                alpha: vec![-2.0],
            },
            "mu_mpa",
        ),
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
    assert!(matches!(m, Material::Ogden { .. }));
    assert!(serde_json::from_str::<Material>(r#"{"model": "rubber"}"#).is_err());
    assert!(serde_json::from_str::<Material>(r#"{"model": "gent", "mu_mpa": 1}"#).is_err());
}
