//! `POST /v1/compare` and `POST /v1/jobs/{id}/compare`: a built balloon's
//! measured centreline against a design's prediction (the core's
//! `measure::compare`), on a blocking thread.

use axum::Extension;
use axum::Json;
use axum::extract::{Path, State};
use patchwork_core::curve::Units;
use patchwork_core::measure::{CompareError, Comparison, Prediction, compare};
use serde::Deserialize;
use serde_json::Value;

use super::auth::Owner;
use super::jobs::{not_ready, owned};
use super::problem::{ApiJson, Problem};
use super::request::CurveSpec;
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
    let row = owned(&state, &owner, &id).await?;
    let Some(result) = state.store.result(&id).await? else {
        return Err(not_ready(&row));
    };
    let prediction = Prediction::from_design_json(&result).map_err(Problem::internal)?;
    let measured = body.measured.load(body.units, "measured")?;
    run(prediction, measured).await
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
        CompareError::Measured(_) | CompareError::Length { .. } => "measured",
    };
    Problem::invalid(field, error.to_string())
}
