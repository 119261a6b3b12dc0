//! Each patch's stretch of the inflated balloon, measured against the
//! prediction: how far it bends and twists, and how far its shape departs.
//!
//! A patch covers the uninflated balloon's axial positions y ± e (e its
//! axial half extent); the prediction's rings carry those to arc lengths
//! along the predicted centreline, and so to fractions of its length. The
//! measured centreline is taken at the same fractions. Over the stretch:
//! - bend = ∫ κ ds and twist = ∫ τ ds (degrees), from the smoothed
//!   profiles, measured and predicted;
//! - the local error: the RMS distance between the two stretches, each
//!   sampled at `LOCAL_SAMPLES` equal steps, after their own best rigid
//!   alignment (so an error upstream does not count here), as mm and as a
//!   percentage of the predicted stretch's length.

use serde::{Deserialize, Serialize};

use super::Prediction;
use crate::curve::{Curve, Point, interpolate, kabsch};
use crate::inverse::TargetProfiles;

/// Samples along a stretch for its local error and its integrals.
const LOCAL_SAMPLES: usize = 48;

/// One patch's stretch, measured against the prediction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PatchRegion {
    /// Patch number as in the tables: 1 for P1.
    pub patch: usize,
    /// The stretch, as fractions of the inflated length from the base.
    pub from_fraction: f64,
    pub to_fraction: f64,
    /// ∫ κ ds over the stretch (degrees).
    pub predicted_bend_deg: f64,
    pub measured_bend_deg: f64,
    /// ∫ τ ds over the stretch (degrees).
    pub predicted_twist_deg: f64,
    pub measured_twist_deg: f64,
    /// RMS distance after the stretches' own alignment (mm)…
    pub local_error_mm: f64,
    /// …as a percentage of the predicted stretch's length.
    pub local_error_percent: f64,
}

/// Every patch's region, in the design's order; `measured` is base to tip
/// and smoothed, the profiles at equal fractions of length.
pub(super) fn patch_regions(
    prediction: &Prediction,
    measured: &Curve,
    measured_profiles: &TargetProfiles,
    predicted_profiles: &TargetProfiles,
) -> Vec<PatchRegion> {
    let predicted = &prediction.centreline;
    let length = prediction.design.balloon.length_mm;
    // Both profiles are sampled alike: equal fractions of length.
    let fractions = grid(predicted_profiles);
    prediction
        .design
        .patches
        .iter()
        .enumerate()
        .map(|(index, patch)| {
            let e = patch.axial_half_extent();
            let fraction =
                |y: f64| prediction.arc_length_at(y.clamp(0.0, length)) / prediction.length();
            let (from, to) = (fraction(patch.y_mm - e), fraction(patch.y_mm + e));
            let integral =
                |values: &[f64], total: f64| integrate(&fractions, values, from, to) * total;
            let (local_error_mm, stretch_mm) = local_error(predicted, measured, from, to);
            PatchRegion {
                patch: index + 1,
                from_fraction: from,
                to_fraction: to,
                predicted_bend_deg: integral(&predicted_profiles.curvature, predicted.length())
                    .to_degrees(),
                measured_bend_deg: integral(&measured_profiles.curvature, measured.length())
                    .to_degrees(),
                predicted_twist_deg: integral(&predicted_profiles.torsion, predicted.length())
                    .to_degrees(),
                measured_twist_deg: integral(&measured_profiles.torsion, measured.length())
                    .to_degrees(),
                local_error_mm,
                local_error_percent: 100.0 * local_error_mm / stretch_mm.max(1e-9),
            }
        })
        .collect()
}

/// The profile's sampling: equal fractions of length from 0 to 1.
fn grid(profile: &TargetProfiles) -> Vec<f64> {
    let n = profile.curvature.len();
    (0..n).map(|i| i as f64 / (n - 1) as f64).collect()
}

/// ∫ values df over [from, to] by the trapezoid rule on `LOCAL_SAMPLES`
/// steps of the piecewise-linear profile.
fn integrate(fractions: &[f64], values: &[f64], from: f64, to: f64) -> f64 {
    let step = (to - from) / (LOCAL_SAMPLES - 1) as f64;
    let at = |k: usize| interpolate(fractions, values, from + step * k as f64);
    let inner: f64 = (1..LOCAL_SAMPLES - 1).map(at).sum();
    step * (inner + 0.5 * (at(0) + at(LOCAL_SAMPLES - 1)))
}

/// The RMS distance between the two curves' stretches over [from, to]
/// (fractions of each one's length) after their own best rigid alignment,
/// and the predicted stretch's length (mm).
fn local_error(predicted: &Curve, measured: &Curve, from: f64, to: f64) -> (f64, f64) {
    let stretch = |curve: &Curve| -> Vec<Point> {
        (0..LOCAL_SAMPLES)
            .map(|k| {
                let f = from + (to - from) * k as f64 / (LOCAL_SAMPLES - 1) as f64;
                curve.point_at(f * curve.length())
            })
            .collect()
    };
    let (p, m) = (stretch(predicted), stretch(measured));
    let (rotation, translation) = kabsch(&m, &p);
    let sum: f64 = m
        .iter()
        .zip(&p)
        .map(|(a, b)| (rotation * a + translation - b).norm_squared())
        .sum();
    let length = (to - from) * predicted.length();
    ((sum / LOCAL_SAMPLES as f64).sqrt(), length)
}
