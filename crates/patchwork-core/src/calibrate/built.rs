//! A built design's measured centreline as calibration data: the design
//! simulated with the materials tried, its centreline rigidly aligned onto
//! the measured one at equal fractions of length (Kabsch), and the
//! distances of the samples, each coordinate relative to the measured
//! length, are the residuals — so that their RMS × √3 is the shape error
//! (as a fraction of the length) of the model against the built balloon.
//!
//! A measured radius (the tube's median along its length) adds one more:
//! the model's median ring radius at equal steps of its length over it,
//! less one.
//!
//! A noisy measurement is smoothed as a target is (σ from the noise found
//! on it); the model's centreline is then smoothed with the same σ before
//! the comparison, so that the bends both lose to it cancel instead of
//! reading as a shorter, straighter balloon (on a 0.3 mm-noisy helix
//! centreline, σ = 6 mm shortened the measurement by 0.4 %).

use super::data::{Built, SAMPLES};
use super::error::CalibrationError;
use crate::curve::{AlignedSamples, Curve, Point};
use crate::design::Design;
use crate::fe::{Simulation, simulate_from};
use crate::inverse::Smoothing;
use crate::inverse::input::prepare;
use crate::ksa::KsaParams;
use crate::measure::{median_along, oriented};

/// A measured length this many times the predicted (or its inverse) is
/// refused: its units are wrong, or it is of another balloon.
const LENGTH_FACTOR_LIMIT: f64 = 2.0;

/// A built design ready to be fitted: the design, and its measured
/// centreline (noise smoothed away, oriented clamp to tip) at `SAMPLES`
/// equal fractions.
pub struct Prepared {
    pub design: Design,
    samples: Curve,
    length_mm: f64,
    /// The design's state with the starting materials: every later solve's
    /// warm start.
    pub start: Simulation,
    /// The σ the measurement was smoothed with (mm; 0: not smoothed).
    sigma_mm: f64,
    /// The measured median radius (mm), when known.
    pub radius_mm: Option<f64>,
}

/// What the model predicts of a built design.
pub struct Predicted {
    /// Ring centres, clamp to tip.
    pub centreline: Curve,
    /// The rings' median radius along the length (mm).
    pub radius_mm: f64,
}

/// The model's prediction for `design`, warm-started from `previous` (the
/// same design with other materials).
pub fn predict(design: &Design, previous: Option<&Simulation>) -> Option<Predicted> {
    let sim = simulate_from(design, &super::model::options(), previous).ok()?;
    let radius: Vec<f64> = sim.rings.iter().map(|r| r.radius).collect();
    Some(Predicted {
        radius_mm: median_along(&sim.centreline, &radius),
        centreline: sim.centreline,
    })
}

impl Prepared {
    /// `built` with `design` (its own, with the starting materials): the
    /// measured centreline smoothed as a target is, and turned to run from
    /// the clamp to the tip (the direction that fits the start's
    /// prediction better).
    pub fn new(index: usize, built: &Built, design: Design) -> Result<Prepared, CalibrationError> {
        let bad = |reason: String| CalibrationError::Datum {
            kind: "built",
            index,
            reason,
        };
        let points: Vec<Point> = built
            .centreline_mm
            .iter()
            .map(|p| Point::new(p[0], p[1], p[2]))
            .collect();
        let measured =
            Curve::from_points(points).map_err(|e| bad(format!("centreline_mm: {e}")))?;
        let (smoothed, report) =
            prepare(&measured, Smoothing::Auto, KsaParams::default().kappa_tol)
                .map_err(|e| bad(format!("centreline_mm: {e}")))?;
        let start = simulate_from(&design, &super::model::options(), None).map_err(|e| {
            bad(format!(
                "the model cannot inflate this design from the starting materials: {e}"
            ))
        })?;
        let predicted = &start.centreline;
        let factor = smoothed.length() / predicted.length();
        if !(1.0 / LENGTH_FACTOR_LIMIT..=LENGTH_FACTOR_LIMIT).contains(&factor) {
            return Err(bad(format!(
                "the measured centreline is {:.0} mm long, the design's predicted {:.0} mm: are its units right?",
                smoothed.length(),
                predicted.length()
            )));
        }
        let (oriented, _) =
            oriented(&smoothed, predicted).map_err(|e| bad(format!("centreline_mm: {e}")))?;
        Ok(Prepared {
            design,
            samples: oriented
                .resample(SAMPLES)
                .map_err(|e| bad(format!("centreline_mm: {e}")))?,
            length_mm: oriented.length(),
            sigma_mm: report.smoothing_mm,
            radius_mm: built.radius_mm,
            start,
        })
    }

    /// The residuals of `predicted` against the measurement: (R pᵢ + t −
    /// mᵢ) / L for every coordinate of every sample, then the radius's.
    pub fn residuals(&self, predicted: &Predicted) -> Option<Vec<f64>> {
        let mut r = self.shape_residuals(&predicted.centreline)?;
        r.extend(self.radius_mm.map(|m| predicted.radius_mm / m - 1.0));
        Some(r)
    }

    /// How many residuals it has.
    pub fn residual_count(&self) -> usize {
        3 * SAMPLES + usize::from(self.radius_mm.is_some())
    }

    fn shape_residuals(&self, predicted: &Curve) -> Option<Vec<f64>> {
        let smoothed;
        let predicted = match self.sigma_mm > 0.0 {
            true => {
                let sigma = Smoothing::Sigma(self.sigma_mm);
                smoothed = prepare(predicted, sigma, KsaParams::default().kappa_tol)
                    .ok()?
                    .0;
                &smoothed
            }
            false => predicted,
        };
        let aligned = AlignedSamples::new(predicted, &self.samples).ok()?;
        Some(
            aligned
                .residuals
                .iter()
                .flat_map(|r| [r.x, r.y, r.z])
                .map(|v| v / self.length_mm)
                .collect(),
        )
    }

    /// The measured (smoothed) length (mm).
    pub fn length_mm(&self) -> f64 {
        self.length_mm
    }
}

/// The shape error (% of the measured length) its residuals amount to
/// (the radius's, if any, left out).
pub fn shape_error_percent(residuals: &[f64]) -> f64 {
    let residuals = &residuals[..residuals.len().min(3 * SAMPLES)];
    let samples = residuals.len() / 3;
    100.0 * (residuals.iter().map(|r| r * r).sum::<f64>() / samples.max(1) as f64).sqrt()
}
