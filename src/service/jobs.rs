//! `/v1/jobs`: submit design jobs, list, read, cancel and delete jobs of
//! every kind (a calibration is submitted by `calibrations.rs`), and fetch
//! their iterations, result and files.

use axum::Extension;
use axum::extract::{Path, Query, State};
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use super::auth::Owner;
use super::balloons;
use super::job_state::{Ending, EventKind, JobStatus};
use super::problem::{ApiJson, Problem};
use super::request::JobRequest;
use super::spec::{JobKind, JobSpec};
use super::state::{AppState, StopReason};
use super::store::JobRow;

/// The files of a finished design job.
pub const FILES: [&str; 6] = [
    "patches.dxf",
    "template.dxf",
    "template.svg",
    "profiles.svg",
    "design.json",
    "design.csv",
];

/// The files of a finished calibration job.
pub const CALIBRATION_FILES: [&str; 2] = ["calibration.json", "options.json"];

/// The files a job of `kind` ends with.
fn files_of(kind: JobKind) -> &'static [&'static str] {
    match kind {
        JobKind::Design => &FILES,
        JobKind::Calibrate => &CALIBRATION_FILES,
    }
}

/// A stored job's kind (a job stored before specs is a design).
pub fn kind_of(row: &JobRow) -> JobKind {
    (row.spec.as_deref())
        .and_then(JobSpec::stored_kind)
        .unwrap_or(JobKind::Design)
}

/// The job resource.
#[derive(Debug, Serialize)]
pub struct JobView {
    pub id: String,
    pub kind: JobKind,
    pub status: JobStatus,
    pub created_at: String,
    pub updated_at: String,
    pub progress: Value,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    pub links: Value,
}

impl JobView {
    pub fn new(row: &JobRow) -> JobView {
        let base = format!("/v1/jobs/{}", row.id);
        let kind = kind_of(row);
        let files: serde_json::Map<String, Value> = files_of(kind)
            .iter()
            .map(|name| (name.to_string(), json!(format!("{base}/files/{name}"))))
            .collect();
        JobView {
            id: row.id.clone(),
            kind,
            status: row.status,
            created_at: row.created_at.clone(),
            updated_at: row.updated_at.clone(),
            progress: row
                .progress
                .as_deref()
                .and_then(|p| serde_json::from_str(p).ok())
                .unwrap_or(Value::Null),
            error: row.error.clone(),
            links: json!({
                "self": base,
                "events": format!("{base}/events"),
                "iterations": format!("{base}/iterations"),
                "result": format!("{base}/result"),
                "cancel": format!("{base}/cancel"),
                "files": files,
            }),
        }
    }
}

fn accepted(row: &JobRow) -> Response {
    let location = format!("/v1/jobs/{}", row.id);
    let mut response = (StatusCode::ACCEPTED, axum::Json(JobView::new(row))).into_response();
    if let Ok(value) = HeaderValue::from_str(&location) {
        response.headers_mut().insert(header::LOCATION, value);
    }
    response
}

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

/// Queues a job of any kind: `request` as the client sent it (an
/// idempotent replay compares it), `spec` as the worker runs it. Answers
/// 202 with the job, or the earlier job of the same `Idempotency-Key`.
pub async fn submit(
    state: &AppState,
    owner: &Owner,
    headers: &HeaderMap,
    stored: &str,
    spec: &JobSpec,
) -> Result<Response, Problem> {
    if state
        .shutting_down
        .load(std::sync::atomic::Ordering::Relaxed)
    {
        let mut p = Problem::new(
            StatusCode::SERVICE_UNAVAILABLE,
            "the server is shutting down",
        );
        p.retry_after_s = Some(5);
        return Err(p);
    }
    let key = idempotency_key(headers)?;
    let spec = spec.to_stored();
    if let Some(key) = &key
        && let Some(existing) = state
            .store
            .job_by_idempotency_key(owner.stored(), key)
            .await?
    {
        return replay(&existing, stored);
    }
    room_in_queue(state).await?;
    let id = uuid::Uuid::now_v7().to_string();
    let queued = json!({"stage": "queued"}).to_string();
    let inserted = state
        .store
        .insert_job(
            &id,
            owner.stored(),
            stored,
            &spec,
            key.as_deref(),
            (EventKind::Stage, &queued),
        )
        .await?;
    let row = match inserted {
        Some((row, event)) => {
            state.hub.publish(&row.id, event);
            row
        }
        // A concurrent request with the same key won the race.
        None => {
            let existing = state
                .store
                .job_by_idempotency_key(owner.stored(), key.as_deref().unwrap_or_default())
                .await?
                .ok_or_else(|| Problem::internal("insert conflict without an existing job"))?;
            return replay(&existing, stored);
        }
    };
    tracing::info!(job = %row.id, "job queued");
    state.wake.notify_one();
    Ok(accepted(&row))
}

/// The `Idempotency-Key` header, if given: 1–255 visible ASCII characters.
fn idempotency_key(headers: &HeaderMap) -> Result<Option<String>, Problem> {
    let Some(value) = headers.get("Idempotency-Key") else {
        return Ok(None);
    };
    let key = value
        .to_str()
        .ok()
        .filter(|k| !k.is_empty() && k.len() <= 255)
        .ok_or_else(|| {
            Problem::new(
                StatusCode::BAD_REQUEST,
                "must be 1–255 visible ASCII characters",
            )
            .field("Idempotency-Key")
        })?;
    Ok(Some(key.to_string()))
}

/// A 503 with `Retry-After` when the queue holds `queue_capacity` jobs.
async fn room_in_queue(state: &AppState) -> Result<(), Problem> {
    let capacity = state.config.queue_capacity;
    if state.store.queued_count().await? < capacity as i64 {
        return Ok(());
    }
    let mut p = Problem::new(
        StatusCode::SERVICE_UNAVAILABLE,
        format!("the queue is full ({capacity} jobs waiting)"),
    );
    p.retry_after_s = Some(30);
    Err(p)
}

/// Same key, same body: the same job. Same key, another body: a conflict
/// with the earlier request (the body itself may be valid).
fn replay(existing: &JobRow, stored: &str) -> Result<Response, Problem> {
    if existing.request == stored {
        Ok(accepted(existing))
    } else {
        Err(Problem::new(
            StatusCode::CONFLICT,
            "this Idempotency-Key was used for a different request",
        )
        .field("Idempotency-Key"))
    }
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
