//! `GET /v1/jobs/{id}/events`: server-sent events. A client first gets what it
//! missed (every event after `Last-Event-ID`, from the store), then live events;
//! the stream ends after `done`, `failed` or `cancelled`. Keep-alive comments
//! every 15 s hold idle connections open through proxies.

use std::convert::Infallible;
use std::time::Duration;

use axum::Extension;
use axum::extract::{Path, State};
use axum::http::{HeaderMap, StatusCode};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use tokio::sync::broadcast::error::RecvError;

use super::auth::Owner;
use super::jobs::owned;
use super::problem::Problem;
use super::state::AppState;
use super::store::StoredEvent;

/// Event kinds after which a job sends nothing more.
const FINAL: [&str; 3] = ["done", "failed", "cancelled"];

fn to_sse(event: &StoredEvent) -> Event {
    Event::default()
        .id(event.seq.to_string())
        .event(&event.kind)
        .data(&event.data)
}

pub async fn stream(
    State(state): State<AppState>,
    Extension(owner): Extension<Owner>,
    Path(id): Path<String>,
    headers: HeaderMap,
) -> Result<Response, Problem> {
    let row = owned(&state, &owner, &id).await?;
    let last_seen = match headers.get("Last-Event-ID") {
        Some(v) => v
            .to_str()
            .ok()
            .and_then(|s| s.trim().parse::<i64>().ok())
            .filter(|&n| n >= 0)
            .ok_or_else(|| {
                Problem::new(StatusCode::BAD_REQUEST, "must be a non-negative event id")
                    .field("Last-Event-ID")
            })?,
        None => 0,
    };
    // Subscribe before reading the store, so nothing falls between the two.
    let mut live = state.hub.subscribe(&id);
    let ended_job = matches!(row.status.as_str(), "succeeded" | "failed" | "cancelled");
    let stream = async_stream::stream! {
        let mut last = last_seen;
        let mut finished = false;
        let mut backlog = match state.store.events_after(&id, last).await {
            Ok(events) => events,
            Err(e) => { tracing::error!(job = %id, "events: {e}"); return; }
        };
        loop {
            for event in backlog.drain(..) {
                if event.seq <= last { continue; }
                last = event.seq;
                finished |= FINAL.contains(&event.kind.as_str());
                yield Ok::<Event, Infallible>(to_sse(&event));
            }
            if finished || (ended_job && last >= last_seen_final(&state, &id).await) {
                break;
            }
            match live.recv().await {
                Ok(event) => backlog.push(event),
                // Fell behind or the channel went: catch up from the store.
                Err(RecvError::Lagged(_)) | Err(RecvError::Closed) => {
                    match state.store.events_after(&id, last).await {
                        Ok(events) if !events.is_empty() => backlog = events,
                        Ok(_) => {
                            tokio::time::sleep(Duration::from_millis(200)).await;
                            live = state.hub.subscribe(&id);
                        }
                        Err(_) => break,
                    }
                }
            }
        }
    };
    Ok(Sse::new(stream)
        .keep_alive(KeepAlive::new().interval(Duration::from_secs(15)))
        .into_response())
}

/// The id of a job's last stored event (0 when it has none).
async fn last_seen_final(state: &AppState, id: &str) -> i64 {
    state
        .store
        .events_after(id, 0)
        .await
        .ok()
        .and_then(|e| e.last().map(|e| e.seq))
        .unwrap_or(0)
}
