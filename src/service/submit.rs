//! Submitting a job of any kind (`jobs.rs` submits designs,
//! `calibrations.rs` calibrations): refused while the server shuts down or
//! the queue is full, replayed for a repeated `Idempotency-Key`, else
//! stored queued with its first event and a worker woken.

use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde_json::json;

use super::auth::Owner;
use super::job_state::EventKind;
use super::job_view::JobView;
use super::problem::Problem;
use super::spec::JobSpec;
use super::state::AppState;
use super::store::JobRow;

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

fn accepted(row: &JobRow) -> Response {
    let location = format!("/v1/jobs/{}", row.id);
    let mut response = (StatusCode::ACCEPTED, axum::Json(JobView::new(row))).into_response();
    if let Ok(value) = HeaderValue::from_str(&location) {
        response.headers_mut().insert(header::LOCATION, value);
    }
    response
}
