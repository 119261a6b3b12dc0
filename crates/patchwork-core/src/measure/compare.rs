//! A measured centreline against the prediction and the target.
//!
//! The shape error is the design run's own figure: RMS distance at equal
//! fractions of length after the best rigid alignment (`curve::shape_error`),
//! taken on the measured points as given. κ and τ are taken as the design's
//! objective takes them, after the noise found on the measured points is
//! smoothed away as a target's is (`inverse::input::prepare`).

use serde::{Deserialize, Serialize};

use super::error::LENGTH_FACTOR_LIMIT;
use super::regions::{PatchRegion, patch_regions};
use super::scan::ScanCentreline;
use super::{CompareError, Prediction};
use crate::curve::{AlignedSamples, Curve, CurveError, interpolate, shape_error};
use crate::inverse::Smoothing;
use crate::inverse::input::{InputReport, prepare};
use crate::inverse::objective::{ObjectiveOptions, SHAPE_SAMPLES, TargetProfiles};
use crate::ksa::KsaParams;

/// Samples of the κ and τ profiles (equal fractions of length) and of the
/// aligned measured centreline in a comparison.
pub const PROFILE_SAMPLES: usize = 400;

/// The spacing (mm) coarser curves are read through a spline at before
/// their profiles are taken.
const DENSE_SPACING_MM: f64 = 1.0;

/// How far one centreline is from a reference after the best rigid
/// alignment, at equal fractions of length.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShapeFigures {
    /// RMS distance (mm).
    pub shape_error_mm: f64,
    /// `shape_error_mm` as a percentage of the reference's length.
    pub shape_error_percent: f64,
    /// The largest distance between corresponding samples (mm)…
    pub largest_mm: f64,
    /// …and where it is, as a fraction of the length from the base.
    pub largest_at_fraction: f64,
}

/// What was read off the measurement.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MeasuredSummary {
    pub points: usize,
    /// Its length as given (mm; noise lengthens it).
    pub length_mm: f64,
    /// Its length after the noise found is smoothed away (mm): the figure
    /// held against the predicted inflated length (noise lengthens a
    /// polyline by about 3σ²/(2 × spacing) per point).
    pub smoothed_length_mm: f64,
    /// The noise found on the points and the smoothing applied, as for a
    /// target (`design.json`'s `input`).
    pub input: InputReport,
    /// Whether the points were given tip to base (they are compared base
    /// to tip, the orientation that fits the prediction better).
    pub reversed: bool,
}

/// κ and τ at equal fractions of length (`fraction`), smoothed as the
/// design's objective smooths them; τ is 0 where κ is below the
/// objective's `torsion_kappa_min` (undefined there), and the measured τ
/// is 0 throughout when the measured points lie in a plane within their
/// noise. The target's are empty when unknown.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ComparedProfiles {
    pub fraction: Vec<f64>,
    pub measured_curvature_per_mm: Vec<f64>,
    pub measured_torsion_per_mm: Vec<f64>,
    pub predicted_curvature_per_mm: Vec<f64>,
    pub predicted_torsion_per_mm: Vec<f64>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub target_curvature_per_mm: Vec<f64>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub target_torsion_per_mm: Vec<f64>,
}

/// The inflated radius measured (from a scan) against the prediction's,
/// both sampled at the same equal fractions of their lengths.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RadiusFigures {
    /// Medians along the length (mm).
    pub measured_median_mm: f64,
    pub predicted_median_mm: f64,
    /// (measured − predicted) / predicted, %.
    pub difference_percent: f64,
}

/// A built balloon's centreline against its design (`compare.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    pub measured: MeasuredSummary,
    pub predicted_length_mm: f64,
    /// Measured (smoothed) − predicted inflated length (mm, and % of the
    /// predicted).
    pub length_difference_mm: f64,
    pub length_difference_percent: f64,
    /// The measured centreline against the predicted one.
    pub against_prediction: ShapeFigures,
    /// The measured centreline against the target as given; absent when
    /// the target is unknown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub against_target: Option<ShapeFigures>,
    /// The prediction against the target as given (the design's own
    /// `as_given` figure), for scale.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prediction_against_target: Option<ShapeFigures>,
    pub profiles: ComparedProfiles,
    /// Every patch's stretch of the balloon, in the design's order.
    pub patches: Vec<PatchRegion>,
    /// The patch (1 for P1) whose stretch diverges most from the
    /// prediction (largest local error); absent for a design without
    /// patches.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub most_divergent_patch: Option<usize>,
    /// The measured centreline moved rigidly onto the prediction (the
    /// shape error's alignment), at `PROFILE_SAMPLES` equal steps (mm).
    pub measured_aligned_mm: Vec<[f64; 3]>,
    /// What the scan gave, when the centreline was taken off a scan: the
    /// centreline and radius extracted, the points used.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scan: Option<ScanCentreline>,
    /// The scan's radius against the prediction's; absent without a scan
    /// or a predicted radius (reports written before it was kept).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<RadiusFigures>,
}

/// The median of `radius` (one value per point of `curve`) over equal
/// steps of the curve's arc length: the tube's radius as a scan reads it,
/// whatever the spacing of the points.
pub fn median_along(curve: &Curve, radius: &[f64]) -> f64 {
    let along: Vec<f64> = curve
        .arc_length()
        .iter()
        .map(|v| v / curve.length())
        .collect();
    median_at(&along, radius)
}

/// The median of `values` (given at `fractions` of the length) over
/// `PROFILE_SAMPLES` equal fractions.
fn median_at(fractions: &[f64], values: &[f64]) -> f64 {
    let mut sampled: Vec<f64> = (0..PROFILE_SAMPLES)
        .map(|i| interpolate(fractions, values, i as f64 / (PROFILE_SAMPLES - 1) as f64))
        .collect();
    sampled.sort_by(f64::total_cmp);
    sampled[sampled.len() / 2]
}

/// Compares the centreline extracted from a scan with `prediction`: the
/// end that fits the prediction's tip is the tip, its cap cut off
/// ([`ScanCentreline::base_to_tip`]); and the scan's radius with the
/// prediction's, at the same fractions of length.
pub fn compare_scan(
    prediction: &Prediction,
    scan: &ScanCentreline,
) -> Result<Comparison, CompareError> {
    let (_, reversed) = oriented(&scan.curve()?, &prediction.centreline)?;
    let scan = scan.base_to_tip(!reversed, prediction.cap_height);
    let measured = scan.curve()?;
    let mut comparison = compare(prediction, &measured)?;
    if let Some((fractions, predicted)) = prediction.radius_profile() {
        let (m, p) = (
            median_along(&measured, &scan.radius_mm),
            median_at(&fractions, &predicted),
        );
        comparison.radius = Some(RadiusFigures {
            measured_median_mm: m,
            predicted_median_mm: p,
            difference_percent: 100.0 * (m - p) / p,
        });
    }
    comparison.scan = Some(scan);
    Ok(comparison)
}

/// Compares `measured` (base to tip or tip to base, mm) with `prediction`.
pub fn compare(prediction: &Prediction, measured: &Curve) -> Result<Comparison, CompareError> {
    let predicted = &prediction.centreline;
    let kappa_tol = KsaParams::default().kappa_tol;
    let (smoothed, input) = prepare(measured, Smoothing::Auto, kappa_tol)?;
    let factor = smoothed.length() / prediction.length();
    if !(1.0 / LENGTH_FACTOR_LIMIT..=LENGTH_FACTOR_LIMIT).contains(&factor) {
        return Err(CompareError::Length {
            measured_mm: smoothed.length(),
            predicted_mm: prediction.length(),
        });
    }
    let (oriented, reversed) = oriented(measured, predicted)?;
    let smoothed = match reversed {
        true => Curve::from_points(smoothed.points().iter().rev().copied().collect())?,
        false => smoothed,
    };
    let (aligned, against_prediction) = aligned_figures(&oriented, predicted)?;
    let target = match &prediction.target {
        Some(target) => Some((target, prepare(target, Smoothing::Auto, kappa_tol)?.0)),
        None => None,
    };
    let profiles = Profiled::new(
        &smoothed,
        predicted,
        target.as_ref().map(|t| &t.1),
        input.planar,
    )?;
    let patches = patch_regions(
        prediction,
        &smoothed,
        &profiles.measured,
        &profiles.predicted,
    );
    let most_divergent_patch = patches
        .iter()
        .max_by(|a, b| a.local_error_percent.total_cmp(&b.local_error_percent))
        .map(|r| r.patch);
    let difference = smoothed.length() - prediction.length();
    let against = |curve: &Curve| match &target {
        Some((given, _)) => aligned_figures(curve, given).map(|f| Some(f.1)),
        None => Ok(None),
    };
    Ok(Comparison {
        measured: MeasuredSummary {
            points: measured.len(),
            length_mm: measured.length(),
            smoothed_length_mm: smoothed.length(),
            input,
            reversed,
        },
        predicted_length_mm: prediction.length(),
        length_difference_mm: difference,
        length_difference_percent: 100.0 * difference / prediction.length(),
        against_prediction,
        against_target: against(&oriented)?,
        prediction_against_target: against(predicted)?,
        profiles: profiles.compared(),
        patches,
        most_divergent_patch,
        measured_aligned_mm: aligned,
        scan: None,
        radius: None,
    })
}

/// The κ, τ profiles of the measured, predicted and target centrelines, as
/// the objective takes them (sparse curves read through a spline first).
struct Profiled {
    measured: TargetProfiles,
    predicted: TargetProfiles,
    target: Option<TargetProfiles>,
}

impl Profiled {
    /// `planar`: the measured points lie in a plane within their noise, and
    /// what torsion its samples show is noise.
    fn new(
        measured: &Curve,
        predicted: &Curve,
        target: Option<&Curve>,
        planar: bool,
    ) -> Result<Profiled, CurveError> {
        let options = ObjectiveOptions::default();
        let profile = |curve: &Curve| -> Result<TargetProfiles, CurveError> {
            let profiles = TargetProfiles::new(&dense(curve)?, PROFILE_SAMPLES, &options);
            Ok(defined_torsion(profiles, options.torsion_kappa_min))
        };
        let mut measured = profile(measured)?;
        if planar {
            measured.torsion.fill(0.0);
        }
        Ok(Profiled {
            measured,
            predicted: profile(predicted)?,
            target: target.map(profile).transpose()?,
        })
    }

    fn compared(self) -> ComparedProfiles {
        let (target_curvature_per_mm, target_torsion_per_mm) = match self.target {
            Some(t) => (t.curvature, t.torsion),
            None => (Vec::new(), Vec::new()),
        };
        ComparedProfiles {
            fraction: (0..PROFILE_SAMPLES)
                .map(|i| i as f64 / (PROFILE_SAMPLES - 1) as f64)
                .collect(),
            measured_curvature_per_mm: self.measured.curvature,
            measured_torsion_per_mm: self.measured.torsion,
            predicted_curvature_per_mm: self.predicted.curvature,
            predicted_torsion_per_mm: self.predicted.torsion,
            target_curvature_per_mm,
            target_torsion_per_mm,
        }
    }
}

/// `curve` read through a cubic spline at `DENSE_SPACING_MM` steps when
/// its points are further apart: the profiles' smoothing (at least 2.5
/// sample spacings) would flatten the bends of a 72-ring centreline, 4 mm
/// or more apart.
fn dense(curve: &Curve) -> Result<Curve, CurveError> {
    let spacing = curve.length() / (curve.len() - 1) as f64;
    if spacing <= DENSE_SPACING_MM {
        return Ok(curve.clone());
    }
    let samples = ((curve.length() / DENSE_SPACING_MM).ceil() as usize + 1)
        .clamp(curve.len(), Curve::MAX_POINTS);
    Curve::through(curve.points(), samples)
}

/// The profiles with τ set to 0 where κ ≤ `kappa_min`: where a curve is
/// nearly straight its torsion is undefined and its estimate noise (as the
/// design's objective compares it only there).
fn defined_torsion(mut profiles: TargetProfiles, kappa_min: f64) -> TargetProfiles {
    for (tau, kappa) in profiles.torsion.iter_mut().zip(&profiles.curvature) {
        if *kappa <= kappa_min {
            *tau = 0.0;
        }
    }
    profiles
}

/// `measured` base to tip: as given, or reversed when that fits
/// `predicted` better.
pub(crate) fn oriented(measured: &Curve, predicted: &Curve) -> Result<(Curve, bool), CurveError> {
    let mut points = measured.points().to_vec();
    points.reverse();
    let reversed = Curve::from_points(points)?;
    let error = |c: &Curve| shape_error(c, predicted, SHAPE_SAMPLES).map(|e| e.rms_mm);
    match error(&reversed)? < error(measured)? {
        true => Ok((reversed, true)),
        false => Ok((measured.clone(), false)),
    }
}

/// `curve` against `reference` ([`ShapeFigures`]), and `curve` moved onto
/// it at `PROFILE_SAMPLES` points.
fn aligned_figures(
    curve: &Curve,
    reference: &Curve,
) -> Result<(Vec<[f64; 3]>, ShapeFigures), CurveError> {
    let aligned = AlignedSamples::new(curve, &reference.resample(SHAPE_SAMPLES)?)?;
    let distances: Vec<f64> = aligned.residuals.iter().map(|r| r.norm()).collect();
    let rms = (distances.iter().map(|d| d * d).sum::<f64>() / distances.len() as f64).sqrt();
    let (largest_index, largest) = distances
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0, 0.0));
    let moved = curve
        .resample(PROFILE_SAMPLES)?
        .transformed(&aligned.rotation, &aligned.translation);
    let figures = ShapeFigures {
        shape_error_mm: rms,
        shape_error_percent: 100.0 * rms / reference.length(),
        largest_mm: largest,
        largest_at_fraction: largest_index as f64 / (distances.len() - 1) as f64,
    };
    let points = moved.points().iter().map(|p| [p.x, p.y, p.z]).collect();
    Ok((points, figures))
}
