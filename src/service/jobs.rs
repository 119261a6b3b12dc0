//! `/v1/jobs`: submit design jobs, list, read, cancel and delete jobs of
//! every kind (a calibration is submitted by `calibrations.rs`), and fetch
//! their iterations, result and files.

use axum::Extension;
use axum::extract::{Path, Query, State};
use axum::http::{HeaderMap, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Deserialize;
use serde_json::{Value, json};

use super::auth::Owner;
use super::balloons;
use super::job_state::{Ending, JobStatus};
use super::job_view::{JobView, files_of, kind_of};
use super::problem::{ApiJson, Problem};
use super::request::JobRequest;
use super::spec::JobSpec;
use super::state::{AppState, StopReason};
use super::store::JobRow;
use super::submit::submit;

pub async fn create(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    headers: HeaderMap,
    ApiJson(request): ApiJson<JobRequest>,
) -> Result<Response, Problem> {
    let profile = match &request.balloon_profile {
        Some(name) => Some(balloons::resolve(&state, &owner, name, "balloon_profile").await?),
        None => None,
    };
    let spec = JobSpec::Design(Box::new(
        request.spec(profile.map(|p| (p.balloon, p.patch)))?,
    ));
    let stored = serde_json::to_string(&request).map_err(Problem::internal)?;
    submit(&state, &owner, &headers, &stored, &spec).await
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ListQuery {
    status: Option<String>,
    limit: Option<i64>,
    cursor: Option<String>,
}

pub async fn list(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    query: Result<Query<ListQuery>, axum::extract::rejection::QueryRejection>,
) -> Result<Response, Problem> {
    let Query(query) = query.map_err(|e| Problem::new(StatusCode::BAD_REQUEST, e.body_text()))?;
    let status = match query.status.as_deref().map(str::parse::<JobStatus>) {
        None => None,
        Some(Ok(status)) => Some(status),
        Some(Err(_)) => {
            return Err(Problem::new(
                StatusCode::BAD_REQUEST,
                format!("status must be one of {}", JobStatus::names()),
            )
            .field("status"));
        }
    };
    if let Some(cursor) = &query.cursor
        && !is_job_id(cursor)
    {
        return Err(Problem::new(
            StatusCode::BAD_REQUEST,
            "cursor must be the next_cursor of a previous page (a job id)",
        )
        .field("cursor"));
    }
    let limit = page_limit(query.limit, 50, 500)?;
    let rows = state
        .store
        .list_jobs(owner.filter(), status, query.cursor.as_deref(), limit)
        .await?;
    let next = (rows.len() as i64 == limit)
        .then(|| rows.last().map(|r| r.id.clone()))
        .flatten();
    let jobs: Vec<JobView> = rows.iter().map(JobView::new).collect();
    Ok(axum::Json(json!({ "jobs": jobs, "next_cursor": next })).into_response())
}

/// Whether `id` has the form of a job id (a UUID); anything else is no job,
/// and never reaches the database (PostgreSQL refuses a NUL in text).
fn is_job_id(id: &str) -> bool {
    uuid::Uuid::try_parse(id).is_ok()
}

/// The job if `owner` may see it; another owner's job is a 404, and so is an
/// id that is not a job id.
pub async fn owned(state: &AppState, owner: &Owner, id: &str) -> Result<JobRow, Problem> {
    if !is_job_id(id) {
        return Err(Problem::not_found("no such job"));
    }
    state
        .store
        .job(id, owner.filter())
        .await?
        .ok_or_else(|| Problem::not_found("no such job"))
}

pub async fn get(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path(id): Path<String>,
) -> Result<Response, Problem> {
    let row = owned(&state, &owner, &id).await?;
    Ok(axum::Json(detail(&row)?).into_response())
}

/// One job as GET /v1/jobs/{id} and its cancel answer it: the job resource
/// and what was asked, the request as submitted, the search's budget in
/// evaluations (its plan's: progress against it), and the plan's stages
/// with their budgets.
fn detail(row: &JobRow) -> Result<Value, Problem> {
    let mut view = serde_json::to_value(JobView::new(row)).map_err(Problem::internal)?;
    if let Ok(request) = serde_json::from_str::<Value>(&row.request) {
        view["request"] = request;
    }
    match row.spec.as_deref().map(JobSpec::from_stored) {
        Some(Ok(JobSpec::Design(design))) => {
            let plan = design.plan();
            view["search_budget"] = json!(plan.search_budget());
            view["plan"] = json!(plan.describe());
            view["stage_budgets"] = json!(plan.describe_budgets());
        }
        Some(Ok(JobSpec::Calibrate(calibrate))) => {
            let names: Vec<&str> = calibrate.fit.iter().map(|p| p.name()).collect();
            view["fit"] = json!(names);
        }
        // A job stored before specs whose request no longer makes one, or a
        // spec of another version: the detail goes without its budget.
        Some(Err(_)) | None => {}
    }
    Ok(view)
}

pub async fn cancel(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path(id): Path<String>,
) -> Result<Response, Problem> {
    let row = owned(&state, &owner, &id).await?;
    if matches!(row.status, JobStatus::Succeeded | JobStatus::Failed) {
        return Err(Problem::new(
            StatusCode::CONFLICT,
            format!("the job has already {}", row.status),
        ));
    }
    let event = json!({"reason": "cancelled by request"});
    if row.status != JobStatus::Cancelled
        && state
            .end_job(&id, Ending::Cancelled, None, &event, None)
            .await?
    {
        if let Some(control) = state.control(&id) {
            control.stop(StopReason::Cancelled);
        }
        tracing::info!(job = %id, "job cancelled");
    }
    let row = owned(&state, &owner, &id).await?;
    Ok(axum::Json(detail(&row)?).into_response())
}

pub async fn delete(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path(id): Path<String>,
) -> Result<Response, Problem> {
    owned(&state, &owner, &id).await?;
    if let Some(control) = state.control(&id) {
        control.stop(StopReason::Cancelled);
    }
    state.store.delete(&id).await?;
    tracing::info!(job = %id, "job deleted");
    Ok(StatusCode::NO_CONTENT.into_response())
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IterationQuery {
    /// Evaluations of the last iteration of the previous page.
    after: Option<i64>,
    limit: Option<i64>,
}

pub async fn iterations(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path(id): Path<String>,
    query: Result<Query<IterationQuery>, axum::extract::rejection::QueryRejection>,
) -> Result<Response, Problem> {
    let Query(query) = query.map_err(|e| Problem::new(StatusCode::BAD_REQUEST, e.body_text()))?;
    owned(&state, &owner, &id).await?;
    let limit = page_limit(query.limit, 100, 1000)?;
    if query.after.is_some_and(|after| after < 0) {
        return Err(Problem::new(
            StatusCode::BAD_REQUEST,
            "after must be a count of evaluations (0 or more)",
        )
        .field("after"));
    }
    let rows = state
        .store
        .iterations(&id, query.after.unwrap_or(0), limit)
        .await?;
    let next = (rows.len() as i64 == limit)
        .then(|| rows.last().map(|r| r.evaluations))
        .flatten();
    Ok(axum::Json(json!({ "iterations": rows, "next_after": next })).into_response())
}

/// A page size from the `limit` query parameter.
fn page_limit(limit: Option<i64>, default: i64, max: i64) -> Result<i64, Problem> {
    let limit = limit.unwrap_or(default);
    if (1..=max).contains(&limit) {
        Ok(limit)
    } else {
        Err(Problem::new(
            StatusCode::BAD_REQUEST,
            format!("limit must be between 1 and {max}"),
        )
        .field("limit"))
    }
}

pub(super) fn not_ready(row: &JobRow) -> Problem {
    Problem::new(
        StatusCode::CONFLICT,
        if row.status.is_pending() {
            format!("the job is {}; its result is not ready", row.status)
        } else {
            format!("the job {}; it has no result", row.status)
        },
    )
}

pub async fn result(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path(id): Path<String>,
) -> Result<Response, Problem> {
    let row = owned(&state, &owner, &id).await?;
    let Some(result) = state.store.result(&id).await? else {
        return Err(not_ready(&row));
    };
    Ok(([(header::CONTENT_TYPE, "application/json")], result).into_response())
}

pub async fn file(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path((id, name)): Path<(String, String)>,
) -> Result<Response, Problem> {
    let row = owned(&state, &owner, &id).await?;
    let files = files_of(kind_of(&row));
    if !files.contains(&name.as_str()) {
        return Err(Problem::not_found(format!(
            "no such file; the job's files are {}",
            files.join(", ")
        )));
    }
    let Some((content_type, body)) = state.store.file(&id, &name).await? else {
        return Err(not_ready(&row));
    };
    let disposition = format!("attachment; filename=\"{name}\"");
    Ok((
        [
            (header::CONTENT_TYPE, content_type),
            (header::CONTENT_DISPOSITION, disposition),
        ],
        body,
    )
        .into_response())
}
