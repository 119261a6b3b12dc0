//! Calibration against synthetic truth: a balloon of known material
//! inflated by the FE model, its measurements given 0.5 % of noise, fitted
//! back from the reference latex.

use super::*;
use crate::cmaes::SeededRng;
use crate::material::{Compressibility, Law};

fn truth() -> Balloon {
    Balloon {
        material: Material::compressible(
            Law::ArrudaBoyce {
                mu_mpa: 0.36,
                lambda_m: 2.6,
            },
            Compressibility::BulkRatio(20.0),
        ),
        ..Balloon::default()
    }
}

/// Length and diameter at each pressure, with `noise` (relative, seeded).
fn measured(pressures: &[f64], noise: f64) -> Vec<Inflation> {
    let base: Vec<Inflation> = pressures
        .iter()
        .map(|&pressure_kpa| Inflation {
            pressure_kpa,
            length_mm: Some(1.0),
            diameter_mm: Some(1.0),
        })
        .collect();
    let exact = model::predict(&truth(), &base).unwrap();
    let mut rng = SeededRng::new(9);
    base.iter()
        .zip(exact)
        .map(|(d, p)| Inflation {
            length_mm: Some(p.length_mm * (1.0 + noise * rng.normal())),
            diameter_mm: Some(p.diameter_mm * (1.0 + noise * rng.normal())),
            ..*d
        })
        .collect()
}

#[test]
fn the_modulus_and_stiffening_come_back_within_their_intervals() {
    let data = measured(&[18.0, 20.0, 22.0, 25.0], 0.005);
    let start = Balloon::default();
    let c = calibrate(&start, &data, &[Parameter::Modulus, Parameter::LambdaM]).unwrap();
    for (fitted, truth) in c.parameters.iter().zip([0.36, 2.6]) {
        let [lo, hi] = fitted.interval95.unwrap();
        assert!(lo <= truth && truth <= hi, "{fitted:?} against {truth}");
        assert!(
            (fitted.value / truth - 1.0).abs() < 0.05,
            "{fitted:?} against {truth}"
        );
    }
    assert!(c.rms_percent < 1.0, "{}", c.rms_percent);
    assert_eq!(c.residuals.len(), 8);
}

#[test]
fn too_little_data_is_refused_and_an_exact_fit_says_so() {
    let data = measured(&[20.0], 0.0);
    let one = [Inflation {
        diameter_mm: None,
        ..data[0]
    }];
    let error = calibrate(
        &Balloon::default(),
        &one,
        &[Parameter::Modulus, Parameter::LambdaM],
    )
    .unwrap_err();
    assert_eq!(
        error,
        CalibrationError::TooFewData {
            measured: 1,
            parameters: 2
        }
    );
    let exact = calibrate(&Balloon::default(), &one, &[Parameter::Modulus]).unwrap();
    assert!(exact.parameters[0].interval95.is_none());
    assert!(
        exact.warnings[0].contains("no intervals"),
        "{:?}",
        exact.warnings
    );
    let bad = [Inflation {
        pressure_kpa: -3.0,
        ..data[0]
    }];
    assert!(matches!(
        calibrate(&Balloon::default(), &bad, &[Parameter::Modulus]),
        Err(CalibrationError::Datum { index: 0, .. })
    ));
    let error = calibrate(&Balloon::default(), &data, &[Parameter::Jm]).unwrap_err();
    assert_eq!(error, CalibrationError::NoSuchParameter("jm"));
}
