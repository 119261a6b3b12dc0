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

fn to_sse(event: &StoredEvent) -> Event {
    Event::default()
        .id(event.seq.to_string())
        .event(event.kind.as_str())
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
            .map(str::trim)
            // Event ids are decimal digits; 18 of them always fit an i64.
            .filter(|s| (1..=18).contains(&s.len()) && s.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|s| s.parse::<i64>().ok())
            .ok_or_else(|| {
                Problem::new(
                    StatusCode::BAD_REQUEST,
                    "must be an event id: 1 to 18 decimal digits",
                )
                .field("Last-Event-ID")
            })?,
        None => 0,
    };
    // An ended job's final event is already stored (it is written with the
    // status): the store alone has everything. Otherwise subscribe before
    // reading the store, so nothing falls between the two.
    let ended = row.status.is_terminal();
    let mut live = (!ended).then(|| state.hub.subscribe(&id));
    let stream = async_stream::stream! {
        let mut last = last_seen;
        let mut backlog = match state.store.events_after(&id, last).await {
            Ok(events) => events,
            Err(e) => { tracing::error!(job = %id, "events: {e}"); return; }
        };
        loop {
            let mut finished = false;
            for event in backlog.drain(..) {
                if event.seq <= last { continue; }
                last = event.seq;
                finished |= event.kind.is_final();
                yield Ok::<Event, Infallible>(to_sse(&event));
            }
            let Some(receiver) = live.as_mut().filter(|_| !finished) else {
                break;
            };
            // The next event is sent as it comes. Otherwise catch up from the
            // store: an event further on (another node's announcement was
            // lost), a lag, or the job's end.
            match receiver.recv().await {
                Ok(event) if event.seq <= last + 1 => { backlog.push(event); continue; }
                Ok(_) => {}
                Err(RecvError::Closed) => live = None,
                Err(RecvError::Lagged(_)) => {}
            }
            match state.store.events_after(&id, last).await {
                Ok(events) => backlog = events,
                Err(e) => { tracing::error!(job = %id, "events: {e}"); break; }
            }
        }
        drop(live);
        state.hub.forget_if_unused(&id);
    };
    Ok(Sse::new(stream)
        .keep_alive(KeepAlive::new().interval(Duration::from_secs(15)))
        .into_response())
}
