//! The least-squares problem a calibration solves: the measurements, the
//! parameters fitted (as logarithms, so that they stay positive and their
//! steps are relative), and the residuals of the FE model's predictions —
//! the bare balloon once per distinct pressure, each built design once.

use super::built::{self, Prepared};
use super::data::Measurements;
use super::error::CalibrationError;
use super::model::{self, Bare};
use super::parameters::{Materials, Parameter};
use crate::design::Balloon;

/// The model's predictions for one set of materials.
pub struct Predictions {
    /// The bare balloon at each of `Problem::pressures`.
    pub bare: Vec<Bare>,
    /// Each built design's centreline and radius.
    pub built: Vec<built::Predicted>,
}

pub struct Problem<'a> {
    /// The bare balloon's geometry (its material is the one tried).
    balloon: Balloon,
    pub start: Materials,
    pub fit: Vec<Parameter>,
    pub data: &'a Measurements,
    /// The distinct pressures the bare balloon was measured at (kPa).
    pressures: Vec<f64>,
    /// The P–V points fitted and those left out (by index).
    pub pressure_volume: (Vec<usize>, Vec<usize>),
    pub built: Vec<Prepared>,
}

/// The checks of `fit` against the data that need no solve: every
/// parameter in the materials, the patch's only with built designs, no
/// more parameters than values. Answers the P–V points fitted and left out.
pub fn check_fit(
    start: &Materials,
    data: &Measurements,
    fit: &[Parameter],
) -> Result<(Vec<usize>, Vec<usize>), CalibrationError> {
    for p in fit {
        p.value(start)
            .ok_or(CalibrationError::NoSuchParameter(p.name()))?;
        if p.of_patch() && data.built.is_empty() {
            return Err(CalibrationError::PatchWithoutBuilt);
        }
    }
    let pressure_volume = data.fitted_pressure_volume();
    if !data.pressure_volume.is_empty() && pressure_volume.0.is_empty() {
        return Err(CalibrationError::NoRisingPressureVolume);
    }
    let measured = data.count() - pressure_volume.1.len();
    if measured < fit.len() {
        return Err(CalibrationError::TooFewData {
            measured,
            parameters: fit.len(),
        });
    }
    Ok(pressure_volume)
}

impl<'a> Problem<'a> {
    pub fn new(
        balloon: &Balloon,
        start: Materials,
        data: &'a Measurements,
        fit: &[Parameter],
    ) -> Result<Problem<'a>, CalibrationError> {
        let pressure_volume = check_fit(&start, data, fit)?;
        let mut pressures: Vec<f64> = data
            .inflation
            .iter()
            .map(|d| d.pressure_kpa)
            .chain(
                pressure_volume
                    .0
                    .iter()
                    .map(|&i| data.pressure_volume[i].pressure_kpa),
            )
            .collect();
        pressures.sort_by(f64::total_cmp);
        pressures.dedup();
        let built = data
            .built
            .iter()
            .enumerate()
            .map(|(i, b)| Prepared::new(i, b, start.on(&b.design)))
            .collect::<Result<_, _>>()?;
        Ok(Problem {
            balloon: balloon.clone(),
            start,
            fit: fit.to_vec(),
            data,
            pressures,
            pressure_volume,
            built,
        })
    }

    pub fn log_start(&self) -> Vec<f64> {
        self.fit
            .iter()
            .map(|p| p.value(&self.start).unwrap_or(1.0).ln())
            .collect()
    }

    pub fn materials_at(&self, log: &[f64]) -> Materials {
        self.fit
            .iter()
            .zip(log)
            .fold(self.start.clone(), |m, (p, v)| p.with(&m, v.exp()))
    }

    /// FE solves after `evaluations` of the residuals (a built design's
    /// starting state, solved once to orient its measurement, counts too).
    pub fn solves(&self, evaluations: usize) -> usize {
        evaluations * self.solves_per_evaluation() + self.built.len()
    }

    /// FE solves per evaluation.
    pub fn solves_per_evaluation(&self) -> usize {
        self.pressures.len() + self.built.len()
    }

    /// The model's predictions; none where the materials are invalid or
    /// the model has no stable state for one of the measurements.
    pub fn predict(&self, materials: &Materials) -> Option<Predictions> {
        materials.balloon.validate().ok()?;
        materials.patch.validate().ok()?;
        let balloon = Balloon {
            material: materials.balloon.clone(),
            ..self.balloon.clone()
        };
        let bare = self
            .pressures
            .iter()
            .map(|&p| model::bare(&model::bare_state(&balloon, p, None)?))
            .collect::<Option<_>>()?;
        let built = self
            .built
            .iter()
            .map(|b| built::predict(&materials.on(&b.design), Some(&b.start)))
            .collect::<Option<_>>()?;
        Some(Predictions { bare, built })
    }

    /// The bare balloon's prediction at `pressure_kpa` (one of the data's).
    pub fn bare_at(&self, predictions: &Predictions, pressure_kpa: f64) -> Bare {
        let i = self
            .pressures
            .iter()
            .position(|&p| p == pressure_kpa)
            .expect("every measured pressure is solved");
        predictions.bare[i]
    }

    /// The relative misfits: the inflations' lengths and diameters, the
    /// fitted P–V points' volumes, then each built design's
    /// ([`Prepared::residuals`]), in the data's order.
    pub fn residuals_of(&self, predictions: &Predictions) -> Option<Vec<f64>> {
        let mut r = Vec::new();
        for d in &self.data.inflation {
            let p = self.bare_at(predictions, d.pressure_kpa);
            r.extend(d.length_mm.map(|m| p.length_mm / m - 1.0));
            r.extend(d.diameter_mm.map(|m| p.diameter_mm / m - 1.0));
        }
        for &i in &self.pressure_volume.0 {
            let d = &self.data.pressure_volume[i];
            r.push(self.bare_at(predictions, d.pressure_kpa).volume_ml / d.volume_ml - 1.0);
        }
        for (b, predicted) in self.built.iter().zip(&predictions.built) {
            r.extend(b.residuals(predicted)?);
        }
        Some(r)
    }

    pub fn residuals(&self, materials: &Materials) -> Option<Vec<f64>> {
        self.residuals_of(&self.predict(materials)?)
    }

    /// Where built design `i`'s residuals lie in the residual vector.
    pub fn built_range(&self, i: usize) -> std::ops::Range<usize> {
        let bare = self.data.inflation.iter().fold(0, |n, d| {
            n + usize::from(d.length_mm.is_some()) + usize::from(d.diameter_mm.is_some())
        }) + self.pressure_volume.0.len();
        let start = bare
            + self.built[..i]
                .iter()
                .map(Prepared::residual_count)
                .sum::<usize>();
        start..start + self.built[i].residual_count()
    }
}
