//! How far a simulated centreline is from the target: the mismatch of the
//! curvature and torsion profiles on normalised arc length.
//!
//! f = (‖κ − κ*‖₂ + ‖τ − τ*‖₂) / (‖κ*‖₂ + ‖τ*‖₂), the authors' form normalised
//! by the target so that f = 1 means "as far as a straight tube". Torsion is
//! compared only where the target bends (κ* > `torsion_kappa_min`): where a
//! curve is nearly straight its torsion is undefined and its estimate is noise.
//! `squared` uses squared norms instead (the paper's other form); an optional
//! shape-error term adds the aligned RMS distance as a fraction of the length,
//! and a design kept clear of itself the tube's overlaps with itself
//! (`TargetProfiles::keep_clear`).

use serde::{Deserialize, Serialize};

use crate::curve::{AnalysisOptions, Curve, Point, analyse, interpolate, shape_error};
use crate::fe::Simulation;
use crate::fe::contact::clearance_overlaps;

/// The shape-error weight of the default objective.
pub const DEFAULT_SHAPE_WEIGHT: f64 = 10.0;

/// Samples along both curves at which the shape error is taken.
pub const SHAPE_SAMPLES: usize = 200;

/// Objective options.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ObjectiveOptions {
    pub squared: bool,
    /// Weight of the shape error (aligned RMS distance / length); 0 leaves it
    /// out. Default 10, so that a 1 % shape error weighs about as much as a
    /// typical κ/τ mismatch: the profiles alone leave position errors that
    /// integrate along the curve unseen (ten round trips without the refine,
    /// `round_trips -- refine=0 shape=0` against `refine=0`: median shape
    /// error 1.07 % without the term, 0.55 % with weight 10).
    pub shape_weight: f64,
    pub torsion_kappa_min: f64,
    /// Both centrelines are smoothed with σ = this fraction of their length (but
    /// at least 2.5 sample spacings) before κ and τ are taken: τ is a third
    /// derivative of ring centres from circle fits, and unsmoothed it is mostly
    /// noise.
    pub smooth_fraction: f64,
}

impl Default for ObjectiveOptions {
    fn default() -> Self {
        ObjectiveOptions {
            squared: false,
            shape_weight: DEFAULT_SHAPE_WEIGHT,
            torsion_kappa_min: 0.005,
            smooth_fraction: 0.01,
        }
    }
}

impl ObjectiveOptions {
    /// Checks every option, naming the field (`shape_weight`, …) and why.
    pub fn validate(&self) -> Result<(), (&'static str, String)> {
        let check = |field, value: f64, low: f64, high: f64| {
            if value.is_finite() && (low..=high).contains(&value) {
                Ok(())
            } else {
                Err((
                    field,
                    format!("must be between {low} and {high}, got {value}"),
                ))
            }
        };
        check("shape_weight", self.shape_weight, 0.0, 1e3)?;
        check("torsion_kappa_min", self.torsion_kappa_min, 0.0, 1e3)?;
        check("smooth_fraction", self.smooth_fraction, 0.0, 0.25)
    }
}

/// The target's profiles, sampled once at the simulation's ring positions
/// (equal steps of normalised arc length).
#[derive(Debug, Clone, PartialEq)]
pub struct TargetProfiles {
    pub curve: Curve,
    /// The target resampled to the shape error's `SHAPE_SAMPLES` points,
    /// once (the refine aligns every centreline onto them).
    pub shape_samples: Curve,
    pub curvature: Vec<f64>,
    pub torsion: Vec<f64>,
    pub torsion_mask: Vec<bool>,
    norm: f64,
    /// Keep the inflated tube clear of itself: the objective and the
    /// refine's residuals gain, for every segment of the centreline, how far
    /// the tube (each ring's own radius) comes within
    /// [`CLEARANCE_MARGIN_MM`] of another stretch of itself
    /// ([`clearance_overlaps`]), times [`CLEARANCE_WEIGHT`]. The margin
    /// leaves the surfaces apart where the penalty balances the shape's
    /// pull; the weight makes 0.1 mm inside the margin cost as much as 1 %
    /// of shape error.
    pub keep_clear: bool,
}

/// How far apart (mm) a clear design keeps its surfaces.
pub const CLEARANCE_MARGIN_MM: f64 = 0.5;
/// Clearance residual per mm of overlap, in percent of shape error.
pub const CLEARANCE_WEIGHT: f64 = 10.0;

impl TargetProfiles {
    /// Samples the target at `samples` equal fractions of its length.
    pub fn new(target: &Curve, samples: usize, options: &ObjectiveOptions) -> TargetProfiles {
        let (curvature, torsion) = smoothed_profiles(
            target,
            samples,
            (target.len() * 4).clamp(400, 20_000),
            options,
        );
        let torsion_mask: Vec<bool> = curvature
            .iter()
            .map(|&k| k > options.torsion_kappa_min)
            .collect();
        let norm = l2(&curvature) + l2(&masked(&torsion, &torsion_mask));
        TargetProfiles {
            curve: target.clone(),
            shape_samples: target
                .resample(SHAPE_SAMPLES)
                .unwrap_or_else(|_| target.clone()),
            curvature,
            torsion,
            torsion_mask,
            norm: norm.max(1e-12),
            keep_clear: false,
        }
    }

    /// Every segment's clearance residual (% of shape error, see
    /// `keep_clear`) of the tube along `centres` with `radii_mm`; empty when
    /// the tube need not keep clear.
    pub fn clearance_residuals(&self, centres: &[Point], radii_mm: &[f64]) -> Vec<f64> {
        if !self.keep_clear {
            return Vec::new();
        }
        (clearance_overlaps(centres, radii_mm, CLEARANCE_MARGIN_MM).iter())
            .map(|d| d * CLEARANCE_WEIGHT)
            .collect()
    }

    /// What keeping clear adds to the objective of `simulation`: its
    /// clearance residuals' norm, weighed as the default objective weighs
    /// shape error; 0 when the tube need not keep clear.
    pub fn clearance_penalty(&self, simulation: &Simulation) -> f64 {
        if !self.keep_clear {
            return 0.0;
        }
        self.clearance_penalty_of(simulation.centreline.points(), &simulation.radii())
    }

    /// The same for a tube along `centres` with `radii_mm`.
    fn clearance_penalty_of(&self, centres: &[Point], radii_mm: &[f64]) -> f64 {
        if !self.keep_clear {
            return 0.0;
        }
        DEFAULT_SHAPE_WEIGHT * l2(&self.clearance_residuals(centres, radii_mm)) / 100.0
    }

    /// The objective of a simulated design: its centreline's, and its
    /// clearance penalty when the tube must keep clear of itself.
    pub fn objective_of(&self, simulation: &Simulation, options: &ObjectiveOptions) -> f64 {
        self.objective(&simulation.centreline, options) + self.clearance_penalty(simulation)
    }

    /// The objective of a rod's centreline, the tube around it of
    /// `radius_mm` throughout.
    pub fn objective_of_rod(
        &self,
        centreline: &Curve,
        radius_mm: f64,
        options: &ObjectiveOptions,
    ) -> f64 {
        let shape = self.objective(centreline, options);
        if !self.keep_clear {
            return shape;
        }
        let radii = vec![radius_mm; centreline.len()];
        shape + self.clearance_penalty_of(centreline.points(), &radii)
    }

    /// κ and τ of a simulated centreline, smoothed like the target, at the same
    /// fractions of length as the target's samples.
    pub fn profiles_of(
        &self,
        centreline: &Curve,
        options: &ObjectiveOptions,
    ) -> (Vec<f64>, Vec<f64>) {
        let n = self.curvature.len();
        smoothed_profiles(centreline, n, (n * 8).clamp(200, 20_000), options)
    }

    /// The objective for a simulated centreline.
    pub fn objective(&self, centreline: &Curve, options: &ObjectiveOptions) -> f64 {
        let (curvature, torsion) = self.profiles_of(centreline, options);
        self.mismatch(centreline, &curvature, &torsion, options)
    }

    /// The objective for given profiles (same sampling as the target's).
    pub fn mismatch(
        &self,
        centreline: &Curve,
        curvature: &[f64],
        torsion: &[f64],
        options: &ObjectiveOptions,
    ) -> f64 {
        let dk: Vec<f64> = curvature
            .iter()
            .zip(&self.curvature)
            .map(|(a, b)| a - b)
            .collect();
        let dt: Vec<f64> = torsion
            .iter()
            .zip(&self.torsion)
            .map(|(a, b)| a - b)
            .collect();
        let dt = masked(&dt, &self.torsion_mask);
        let mut f = if options.squared {
            (l2(&dk).powi(2) + l2(&dt).powi(2)) / self.norm.powi(2)
        } else {
            (l2(&dk) + l2(&dt)) / self.norm
        };
        if options.shape_weight > 0.0
            && let Ok(e) = shape_error(centreline, &self.curve, SHAPE_SAMPLES)
        {
            f += options.shape_weight * e.percent_of_length / 100.0;
        }
        if f.is_finite() { f } else { f64::INFINITY }
    }
}

/// κ and τ at `samples` equal fractions of the curve's length, after resampling
/// to `resolution` points and smoothing with σ = `smooth_fraction` of the length.
fn smoothed_profiles(
    curve: &Curve,
    samples: usize,
    resolution: usize,
    options: &ObjectiveOptions,
) -> (Vec<f64>, Vec<f64>) {
    // σ never below 2.5 of the curve's own sample spacings: a fraction of the
    // length alone can be smaller than the gap between ring centres, and then
    // smooths nothing.
    let spacing = curve.length() / (curve.len() - 1) as f64;
    let sigma = (options.smooth_fraction * curve.length()).max(2.5 * spacing);
    let fine = curve.resample(resolution).unwrap_or_else(|_| curve.clone());
    let fine = fine.convolved(sigma).unwrap_or(fine);
    let analysis = analyse(&fine, &AnalysisOptions::default());
    let length = fine.length();
    let at = |values: &[f64], i: usize| {
        interpolate(
            &analysis.s,
            values,
            length * i as f64 / (samples - 1) as f64,
        )
    };
    (
        (0..samples).map(|i| at(&analysis.curvature, i)).collect(),
        (0..samples).map(|i| at(&analysis.torsion, i)).collect(),
    )
}

fn masked(values: &[f64], mask: &[bool]) -> Vec<f64> {
    values
        .iter()
        .zip(mask)
        .map(|(v, m)| if *m { *v } else { 0.0 })
        .collect()
}

fn l2(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}
