//! What a lab measures to calibrate with, and the checks every measured
//! value passes before a solve: the bare balloon's inflation (length and
//! diameter at pressures), its pressure–volume curve, and the centrelines
//! of balloons built from designs.

use serde::{Deserialize, Serialize};

use super::error::CalibrationError;
use crate::design::Design;

/// The bare balloon measured at one pressure: its length from the clamp to
/// the tip, its diameter across the middle (mid-wall), or both (mm).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Inflation {
    pub pressure_kpa: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_mm: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diameter_mm: Option<f64>,
}

/// One point of the bare balloon's pressure–volume curve: the volume
/// inside the balloon (enclosed by the wall's mid-surface, clamp to tip:
/// what was pumped in plus the uninflated balloon's own) at a pressure.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PressureVolume {
    pub pressure_kpa: f64,
    pub volume_ml: f64,
}

/// A balloon built from a design and measured inflated: the design (its
/// balloon, patches and pressure; the materials are the calibration's),
/// the measured centreline from the clamp to the tip (mm; either direction,
/// in any frame), and where known the tube's median radius along its
/// length (mm; a scan measures it): what tells the balloon's stiffness
/// apart from the patch's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Built {
    pub design: Design,
    pub centreline_mm: Vec<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_mm: Option<f64>,
}

/// Everything measured; any mix of the three kinds.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Measurements {
    #[serde(default)]
    pub inflation: Vec<Inflation>,
    #[serde(default)]
    pub pressure_volume: Vec<PressureVolume>,
    #[serde(default)]
    pub built: Vec<Built>,
}

/// Samples of a measured centreline compared: 32 at equal fractions (a
/// patch's stretch is ≥ 1/40 of a balloon's length for designs of up to a
/// dozen patches; more samples add residuals, not information, and weigh
/// one built balloon above the bare balloon's handful of values).
pub const SAMPLES: usize = 32;

/// A P–V point is fitted only where a larger volume never comes back to
/// its pressure (more than this relative volume further on): the states a
/// pressure-controlled inflation reaches. Below it, two points are taken
/// as one volume measured with its noise.
const SAME_VOLUME: f64 = 0.03;

/// A length or diameter this much smaller at a higher pressure, or two
/// measurements at one pressure this far apart, contradict each other
/// beyond a lab's noise: a balloon on its stable states grows as the
/// pressure rises.
const SHRINKS: f64 = 0.02;
const SAME_PRESSURE_SPREAD: f64 = 0.05;

impl Measurements {
    /// How many values a calibration fits to (a built design's centreline
    /// as its samples' coordinates).
    pub fn count(&self) -> usize {
        self.inflation
            .iter()
            .map(|d| usize::from(d.length_mm.is_some()) + usize::from(d.diameter_mm.is_some()))
            .sum::<usize>()
            + self.pressure_volume.len()
            + self
                .built
                .iter()
                .map(|b| 3 * SAMPLES + usize::from(b.radius_mm.is_some()))
                .sum::<usize>()
    }

    /// Every value checked; the first that is wrong is named.
    pub fn check(&self) -> Result<(), CalibrationError> {
        if self.count() == 0 {
            return Err(CalibrationError::Empty);
        }
        for (index, d) in self.inflation.iter().enumerate() {
            let bad = |reason: &str| datum("inflation", index, reason);
            check_pressure(d.pressure_kpa).map_err(bad)?;
            for value in [d.length_mm, d.diameter_mm].into_iter().flatten() {
                if !(value.is_finite() && value > 0.0 && value < 1e5) {
                    return Err(bad("lengths and diameters must be positive (mm)"));
                }
            }
            if d.length_mm.is_none() && d.diameter_mm.is_none() {
                return Err(bad("measures neither the length nor the diameter"));
            }
        }
        for (index, d) in self.pressure_volume.iter().enumerate() {
            let bad = |reason: &str| datum("pressure_volume", index, reason);
            check_pressure(d.pressure_kpa).map_err(bad)?;
            if !(d.volume_ml.is_finite() && d.volume_ml > 0.0 && d.volume_ml < 1e6) {
                return Err(bad("volume_ml must be positive"));
            }
        }
        contradiction(&self.inflation)?;
        if self.pressure_volume.len() == 1 {
            return Err(datum(
                "pressure_volume",
                0,
                "a pressure–volume curve needs two points or more",
            ));
        }
        for (index, b) in self.built.iter().enumerate() {
            let bad = |reason: String| datum("built", index, &reason);
            b.design
                .validate()
                .map_err(|e| bad(format!("design: {e}")))?;
            if b.centreline_mm.iter().flatten().any(|v| !v.is_finite()) {
                return Err(bad(
                    "centreline_mm: every coordinate must be a number".into()
                ));
            }
        }
        Ok(())
    }

    /// The P–V points a pressure-controlled model can be fitted to, by
    /// index, and those left out: sorted by volume, a point is left out
    /// where a point of larger volume (by more than `SAME_VOLUME`) lies at
    /// its pressure or below — past the pressure's peak, where the balloon
    /// bulges and the bulge runs along it, or on the first rise at a
    /// pressure the bulged balloon holds again.
    pub fn fitted_pressure_volume(&self) -> (Vec<usize>, Vec<usize>) {
        let points = &self.pressure_volume;
        (0..points.len()).partition(|&i| {
            !points.iter().any(|q| {
                q.volume_ml > points[i].volume_ml * (1.0 + SAME_VOLUME)
                    && q.pressure_kpa <= points[i].pressure_kpa
            })
        })
    }
}

/// The first pair of inflations that contradict each other (`SHRINKS`,
/// `SAME_PRESSURE_SPREAD`), named by the later one's index.
fn contradiction(inflation: &[Inflation]) -> Result<(), CalibrationError> {
    for (j, b) in inflation.iter().enumerate() {
        for a in &inflation[..j] {
            let pairs = [
                ("length_mm", a.length_mm, b.length_mm),
                ("diameter_mm", a.diameter_mm, b.diameter_mm),
            ];
            for (name, x, y) in pairs {
                let (Some(x), Some(y)) = (x, y) else { continue };
                let reason = if a.pressure_kpa == b.pressure_kpa {
                    ((y / x - 1.0).abs() > SAME_PRESSURE_SPREAD).then(|| {
                        format!(
                            "{name} {y} at {} kPa, and {x} at the same pressure before: more than 5 % apart",
                            b.pressure_kpa
                        )
                    })
                } else {
                    let ((lo_p, lo), (hi_p, hi)) = match a.pressure_kpa < b.pressure_kpa {
                        true => ((a.pressure_kpa, x), (b.pressure_kpa, y)),
                        false => ((b.pressure_kpa, y), (a.pressure_kpa, x)),
                    };
                    (hi < lo * (1.0 - SHRINKS)).then(|| {
                        format!(
                            "{name} {hi} at {hi_p} kPa is below {lo} at {lo_p} kPa: a balloon grows as the pressure rises"
                        )
                    })
                };
                if let Some(reason) = reason {
                    return Err(datum("inflation", j, &reason));
                }
            }
        }
    }
    Ok(())
}

fn check_pressure(pressure_kpa: f64) -> Result<(), &'static str> {
    match pressure_kpa.is_finite() && pressure_kpa > 0.0 && pressure_kpa <= 1000.0 {
        true => Ok(()),
        false => Err("pressure_kpa must be above 0 and at most 1000"),
    }
}

fn datum(kind: &'static str, index: usize, reason: &str) -> CalibrationError {
    CalibrationError::Datum {
        kind,
        index,
        reason: reason.into(),
    }
}
