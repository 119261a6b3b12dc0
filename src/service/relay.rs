//! What other nodes announce, relayed to this node (PostgreSQL only; see
//! migrations/postgres). Every stored event is announced on
//! `patchwork_events` as "<job id> <seq>": for a job someone here watches,
//! the event is read from the store and published on the local hub, where
//! streams drop what they have already sent. A notification lost while the
//! connection was down leaves a gap that the stream notices by its ids and
//! fills from the store. Every queued job is announced on `patchwork_jobs`:
//! an idle worker here wakes to claim it (a lost one is found at the
//! workers' next poll, within 2 s). Every cancelled or deleted job is
//! announced on `patchwork_stops`: if it runs here, its run stops (a lost
//! one is noticed at the worker's next lease renewal, within a second).

use std::time::Duration;

use sqlx::postgres::PgListener;

use super::state::{AppState, StopReason};

pub fn start(state: &AppState) -> Option<tokio::task::JoinHandle<()>> {
    let pool = state.store.postgres()?.clone();
    let state = state.clone();
    Some(tokio::spawn(async move {
        loop {
            match PgListener::connect_with(&pool).await {
                Ok(mut listener) => {
                    let channels = ["patchwork_events", "patchwork_jobs", "patchwork_stops"];
                    if let Err(e) = listener.listen_all(channels).await {
                        tracing::warn!("listening for events: {e}");
                    } else {
                        relay(&state, &mut listener).await;
                    }
                }
                Err(e) => tracing::warn!("connecting to listen for events: {e}"),
            }
            tokio::time::sleep(Duration::from_secs(1)).await;
        }
    }))
}

/// Wakes a worker for each queued job, stops the runs of cancelled jobs and
/// publishes each announced event of a watched job, until the connection
/// fails.
async fn relay(state: &AppState, listener: &mut PgListener) {
    loop {
        let notification = match listener.recv().await {
            Ok(n) => n,
            Err(e) => return tracing::warn!("receiving events: {e}"),
        };
        match notification.channel() {
            "patchwork_jobs" => {
                state.wake.notify_one();
                continue;
            }
            "patchwork_stops" => {
                if let Some(control) = state.control(notification.payload()) {
                    control.stop(StopReason::Cancelled);
                }
                continue;
            }
            _ => {}
        }
        let Some((job, seq)) = notification.payload().split_once(' ') else {
            continue;
        };
        let Ok(seq) = seq.parse::<i64>() else {
            continue;
        };
        if !state.hub.watched(job) {
            continue;
        }
        match state.store.events_after(job, seq - 1).await {
            Ok(events) => {
                if let Some(event) = events.into_iter().find(|e| e.seq == seq) {
                    state.hub.publish(job, event);
                }
            }
            Err(e) => tracing::warn!(job, "reading a relayed event: {e}"),
        }
    }
}
