//! `POST /v1/calibrations`: a calibration job — the material fitted to a
//! lab's measurements on the FE model (the core's `calibrate`), run by the
//! workers like a design and read through the job routes (status, events,
//! result: calibration.json; files: calibration.json and options.json).
//! Everything a run would fail late on is checked here, naming the field.

use axum::Extension;
use axum::extract::State;
use axum::http::HeaderMap;
use axum::response::Response;
use patchwork_core::calibrate::{
    Built, CalibrationError, Inflation, Measurements, Parameter, PressureVolume, check,
};
use patchwork_core::curve::Units;
use patchwork_core::design::{Balloon, PatchSpec};
use patchwork_core::measure::Prediction;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::auth::Owner;
use super::balloons::{check_name, resolve};
use super::jobs::{not_ready, owned};
use super::problem::{ApiJson, Problem};
use super::profile::Profile;
use super::request::CurveSpec;
use super::spec::{CalibrateSpec, JobSpec};
use super::state::AppState;
use super::submit::submit;

/// Most built balloons one calibration takes.
const MAX_BUILT: usize = 20;
/// Most inflation or P–V points one calibration takes.
const MAX_POINTS: usize = 200;

/// `POST /v1/calibrations`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrationRequest {
    /// The bare balloon and the material to start from (a design's
    /// `balloon`) [default: the profile's, else the first built design's,
    /// else the reference latex balloon].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balloon: Option<Balloon>,
    /// The patch to start from (a design's `patch`) [same defaults].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub patch: Option<PatchSpec>,
    /// A balloon profile of this key to start from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balloon_profile: Option<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub inflation: Vec<Inflation>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pressure_volume: Vec<PressureVolume>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub built: Vec<BuiltRequest>,
    /// Units of the built balloons' measured centrelines.
    #[serde(default)]
    pub units: Units,
    /// The parameters to fit [default: the modulus; the law's stiffening
    /// with bare-balloon data; the patch's modulus with built designs].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<Vec<Parameter>>,
    /// Save the calibrated balloon and patch as this key's balloon profile.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub save_as: Option<String>,
}

/// A balloon built from a design and measured inflated: the design by its
/// design.json or by the job that designed it.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BuiltRequest {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub design: Option<Value>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub job: Option<String>,
    /// The measured centreline, base to tip or tip to base, in any frame.
    pub measured: CurveSpec,
    /// The inflated tube's median radius, where measured (mm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_mm: Option<f64>,
}

pub async fn create(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    headers: HeaderMap,
    ApiJson(request): ApiJson<CalibrationRequest>,
) -> Result<Response, Problem> {
    let spec = resolve_spec(&state, &owner, &request).await?;
    let stored = serde_json::to_string(&request).map_err(Problem::internal)?;
    submit(
        &state,
        &owner,
        &headers,
        &stored,
        &JobSpec::Calibrate(Box::new(spec)),
    )
    .await
}

/// The request made a calibration spec: the profile and the built
/// designs' jobs read, the defaults applied, the data and the fit checked.
async fn resolve_spec(
    state: &AppState,
    owner: &Owner,
    request: &CalibrationRequest,
) -> Result<CalibrateSpec, Problem> {
    if request.built.len() > MAX_BUILT {
        return Err(Problem::invalid(
            "built",
            format!("at most {MAX_BUILT} built balloons"),
        ));
    }
    for (field, n) in [
        ("inflation", request.inflation.len()),
        ("pressure_volume", request.pressure_volume.len()),
    ] {
        if n > MAX_POINTS {
            return Err(Problem::invalid(
                field,
                format!("at most {MAX_POINTS} points"),
            ));
        }
    }
    if let Some(name) = &request.save_as {
        check_name(name, "save_as")?;
    }
    let profile = match &request.balloon_profile {
        Some(name) => Some(resolve(state, owner, name, "balloon_profile").await?),
        None => None,
    };
    let mut measurements = Measurements {
        inflation: request.inflation.clone(),
        pressure_volume: request.pressure_volume.clone(),
        built: Vec::new(),
    };
    for (i, built) in request.built.iter().enumerate() {
        measurements
            .built
            .push(built_of(state, owner, built, request.units, i).await?);
    }
    let (balloon, patch) = starting(request, profile, &measurements)?;
    let fit = (request.fit.clone())
        .unwrap_or_else(|| Parameter::defaults(&balloon.material, &measurements));
    check(&balloon.material, &patch.material, &measurements, &fit).map_err(refusal)?;
    Ok(CalibrateSpec {
        balloon,
        patch,
        measurements,
        fit,
        save_as: request.save_as.clone(),
    })
}

/// The balloon and patch to start from: given, the profile's, the first
/// built design's, or the reference scene's — never two of the first two.
fn starting(
    request: &CalibrationRequest,
    profile: Option<Profile>,
    data: &Measurements,
) -> Result<(Balloon, PatchSpec), Problem> {
    let given = request.balloon.is_some() || request.patch.is_some();
    if given && profile.is_some() {
        return Err(Problem::invalid(
            "balloon_profile",
            "give the starting balloon either by `balloon`/`patch` or by `balloon_profile`",
        ));
    }
    let first = data.built.first().map(|b| &b.design);
    let (balloon, patch) = match profile {
        Some(p) => (p.balloon, p.patch),
        None => (
            (request.balloon.clone())
                .unwrap_or_else(|| first.map_or_else(Balloon::default, |d| d.balloon.clone())),
            (request.patch.clone())
                .unwrap_or_else(|| first.map_or_else(PatchSpec::default, |d| d.patch.clone())),
        ),
    };
    for (field, material) in [("balloon", &balloon.material), ("patch", &patch.material)] {
        material
            .validate()
            .map_err(|e| Problem::invalid(format!("{field}.material"), e.to_string()))?;
    }
    Ok((balloon, patch))
}

/// One built balloon: its design (given, or its job's result) and its
/// measured centreline.
async fn built_of(
    state: &AppState,
    owner: &Owner,
    built: &BuiltRequest,
    units: Units,
    i: usize,
) -> Result<Built, Problem> {
    let field = format!("built[{i}]");
    let design_json = match (&built.design, &built.job) {
        (Some(design), None) => design.to_string(),
        (None, Some(id)) => {
            let row = (owned(state, owner, id).await)
                .map_err(|_| Problem::invalid(format!("{field}.job"), "no such job"))?;
            let Some(result) = state.store.result(id).await? else {
                let reason = not_ready(&row).detail;
                return Err(Problem::invalid(format!("{field}.job"), reason));
            };
            result
        }
        _ => {
            return Err(Problem::invalid(
                field,
                "give exactly one of `design` (a design.json) or `job` (the design job's id)",
            ));
        }
    };
    let design_field = if built.job.is_some() { "job" } else { "design" };
    let prediction = Prediction::from_design_json(&design_json)
        .map_err(|e| Problem::invalid(format!("{field}.{design_field}"), e.to_string()))?;
    let measured = built.measured.load(units, &format!("{field}.measured"))?;
    Ok(Built {
        design: prediction.design,
        centreline_mm: measured.points().iter().map(|p| [p.x, p.y, p.z]).collect(),
        radius_mm: built.radius_mm,
    })
}

/// A calibration's refusal, naming the request's field.
fn refusal(error: CalibrationError) -> Problem {
    let field = match &error {
        CalibrationError::Datum { kind, index, .. } => format!("{kind}[{index}]"),
        CalibrationError::Empty => "inflation".into(),
        CalibrationError::NoRisingPressureVolume => "pressure_volume".into(),
        _ => "fit".into(),
    };
    Problem::invalid(field, error.to_string())
}
