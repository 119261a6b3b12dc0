//! Metrics of a simulated design against the target: the shape error
//! (aligned RMS distance), the objective, and DTW of κ(s) and τ(s).

use super::input::InputReport;
use super::objective::{ObjectiveOptions, SHAPE_SAMPLES, TargetProfiles};
use super::outcome::{AsGiven, Metrics, Profiles};
use super::tuning::Tuning;
use crate::curve::{Curve, dtw, shape_error};
use crate::design::Design;
use crate::fe::mesh::MeshSpec;
use crate::fe::{SimulateError, Simulation, simulate};

/// Metrics of `design` against `target` on a model of the caller's choice —
/// to compare designs found at different fidelities on one common model
/// (`tuning` gives the rings and the objective).
pub fn assess(
    target: &Curve,
    design: &Design,
    mesh: MeshSpec,
    tuning: &Tuning,
) -> Result<Metrics, SimulateError> {
    let simulation = simulate(design, &tuning.model(mesh))?;
    let profiles = TargetProfiles::new(target, tuning.rings, &tuning.objective);
    Ok(verified(&profiles, &simulation, &tuning.objective).0)
}

/// Metrics and profiles of a verified simulation, each computed once.
pub(super) fn verified(
    target: &TargetProfiles,
    sim: &Simulation,
    options: &ObjectiveOptions,
) -> (Metrics, Profiles) {
    let (shape_error_mm, shape_error_percent) = shape_figures(&sim.centreline, &target.curve);
    let (curvature, torsion) = target.profiles_of(&sim.centreline, options);
    let metrics = Metrics {
        objective: target.mismatch(&sim.centreline, &curvature, &torsion, options)
            + target.clearance_penalty(sim),
        dtw_curvature: dtw(&curvature, &target.curvature, None).unwrap_or(f64::INFINITY),
        dtw_torsion: dtw(&torsion, &target.torsion, None).unwrap_or(f64::INFINITY),
        shape_error_mm,
        shape_error_percent,
    };
    let profiles = Profiles {
        target_curvature_per_mm: target.curvature.clone(),
        target_torsion_per_mm: target.torsion.clone(),
        curvature_per_mm: curvature,
        torsion_per_mm: torsion,
    };
    (metrics, profiles)
}

/// The verified centreline against the curve as the user gave it: the
/// metrics' own figures when the design aimed at that very curve.
pub(super) fn as_given(
    centreline: &Curve,
    given: &Curve,
    input: &InputReport,
    metrics: &Metrics,
) -> AsGiven {
    let (shape_error_mm, shape_error_percent) = match input.changed_target() {
        true => shape_figures(centreline, given),
        false => (metrics.shape_error_mm, metrics.shape_error_percent),
    };
    AsGiven {
        length_mm: given.length(),
        shape_error_mm,
        shape_error_percent,
    }
}

/// The shape error of `centreline` against `curve` (mm and % of its
/// length); infinite when it cannot be measured.
fn shape_figures(centreline: &Curve, curve: &Curve) -> (f64, f64) {
    shape_error(centreline, curve, SHAPE_SAMPLES).map_or((f64::INFINITY, f64::INFINITY), |e| {
        (e.rms_mm, e.percent_of_length)
    })
}
