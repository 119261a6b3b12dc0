//! `POST /v1/compare`, `POST /v1/jobs/{id}/compare` and
//! `POST /v1/jobs/{id}/compare/scan`: a built balloon's measured centreline,
//! or a 3D scan of it, against a design's prediction (the core's
//! `measure::compare`, `measure::scan`), on a blocking thread.

use axum::Extension;
use axum::Json;
use axum::body::Body;
use axum::extract::{Path, State};
use axum::http::{StatusCode, Uri};
use patchwork_core::curve::Units;
use patchwork_core::measure::scan::centreline_from_scan;
use patchwork_core::measure::scan::read::{ScanFormat, read_scan};
use patchwork_core::measure::{CompareError, Comparison, Prediction, compare, compare_scan};
use serde::Deserialize;
use serde_json::Value;

use super::auth::Owner;
use super::job_view::kind_of;
use super::jobs::{not_ready, owned};
use super::problem::{ApiJson, Problem};
use super::request::CurveSpec;
use super::spec::JobKind;
use super::state::AppState;

/// `POST /v1/compare`: a design.json (as a job's result or `patchwork
/// design` writes it) and the measured centreline.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CompareRequest {
    design: Value,
    measured: CurveSpec,
    /// Units of `measured` (and `target`).
    #[serde(default)]
    units: Units,
    /// The target to measure against instead of design.json's `target_mm`.
    #[serde(default)]
    target: Option<CurveSpec>,
}

/// `POST /v1/jobs/{id}/compare`: the measured centreline of the balloon
/// built from the job's design.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JobCompareRequest {
    measured: CurveSpec,
    #[serde(default)]
    units: Units,
}

pub async fn compare_route(
    ApiJson(body): ApiJson<CompareRequest>,
) -> Result<Json<Comparison>, Problem> {
    let mut prediction =
        Prediction::from_design_json(&body.design.to_string()).map_err(|e| problem(e, "design"))?;
    if let Some(target) = &body.target {
        prediction = prediction.with_target(target.load(body.units, "target")?);
    }
    let measured = body.measured.load(body.units, "measured")?;
    run(prediction, measured).await
}

pub async fn job_compare_route(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path(id): Path<String>,
    ApiJson(body): ApiJson<JobCompareRequest>,
) -> Result<Json<Comparison>, Problem> {
    let prediction = job_prediction(&state, &owner, &id).await?;
    let measured = body.measured.load(body.units, "measured")?;
    run(prediction, measured).await
}

/// The design job's prediction, once it has one; a calibration job has no
/// design to compare with.
async fn job_prediction(state: &AppState, owner: &Owner, id: &str) -> Result<Prediction, Problem> {
    let row = owned(state, owner, id).await?;
    if kind_of(&row) != JobKind::Design {
        return Err(Problem::new(
            StatusCode::CONFLICT,
            "the job is a calibration: it has no design to compare with",
        ));
    }
    let Some(result) = state.store.result(id).await? else {
        return Err(not_ready(&row));
    };
    Prediction::from_design_json(&result).map_err(Problem::internal)
}

async fn run(
    prediction: Prediction,
    measured: patchwork_core::Curve,
) -> Result<Json<Comparison>, Problem> {
    tokio::task::spawn_blocking(move || compare(&prediction, &measured))
        .await
        .map_err(Problem::internal)?
        .map(Json)
        .map_err(|e| problem(e, "design"))
}

/// A refusal naming the request's field: the measured centreline's
/// problems (its points, its length against the prediction's) are
/// `measured`'s, the design's are `design_field`'s.
fn problem(error: CompareError, design_field: &str) -> Problem {
    let field = match error {
        CompareError::Design(_) => design_field,
        CompareError::Measured(_) | CompareError::Length { .. } if design_field == "scan" => "scan",
        CompareError::Measured(_) | CompareError::Length { .. } => "measured",
    };
    Problem::invalid(field, error.to_string())
}

/// `POST /v1/jobs/{id}/compare/scan?format=ply&units=mm`: the body is the
/// scan file itself (PLY, OBJ, STL, XYZ), up to the server's
/// `scan_limit_bytes`.
pub async fn job_scan_route(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path(id): Path<String>,
    uri: Uri,
    body: Body,
) -> Result<Json<Comparison>, Problem> {
    // The body is read before anything is answered: a refusal sent while
    // the client is still uploading would be lost to the connection's reset.
    let limit = state.config.scan_limit_bytes;
    let bytes = axum::body::to_bytes(body, limit).await.map_err(|_| {
        Problem::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            format!("the scan is over the limit of {limit} bytes"),
        )
    })?;
    let (format, units) = scan_query(uri.query().unwrap_or(""))?;
    let prediction = job_prediction(&state, &owner, &id).await?;
    tokio::task::spawn_blocking(move || {
        let points = read_scan(&bytes, format, units)
            .map_err(|e| Problem::invalid("scan", e.to_string()))?;
        let scan =
            centreline_from_scan(&points).map_err(|e| Problem::invalid("scan", e.to_string()))?;
        compare_scan(&prediction, &scan).map_err(|e| problem(e, "scan"))
    })
    .await
    .map_err(Problem::internal)?
    .map(Json)
}

/// The scan route's query: `format` (ply, obj, stl, xyz or pts) and
/// optional `units`; anything else is refused naming it.
fn scan_query(query: &str) -> Result<(ScanFormat, Units), Problem> {
    let (mut format, mut units) = (None, Units::Mm);
    for pair in query.split('&').filter(|p| !p.is_empty()) {
        let (key, value) = pair.split_once('=').unwrap_or((pair, ""));
        match key {
            "format" => {
                format = Some(
                    ScanFormat::from_name(&format!("scan.{value}")).ok_or_else(|| {
                        Problem::invalid("format", "format must be ply, obj, stl, xyz or pts")
                    })?,
                )
            }
            "units" => {
                units = value.parse().map_err(|e: patchwork_core::CurveError| {
                    Problem::invalid("units", e.to_string())
                })?
            }
            other => {
                return Err(Problem::invalid(
                    other,
                    format!("unknown query parameter `{other}`"),
                ));
            }
        }
    }
    let format = format.ok_or_else(|| {
        Problem::invalid("format", "format is required: ply, obj, stl, xyz or pts")
    })?;
    Ok((format, units))
}
