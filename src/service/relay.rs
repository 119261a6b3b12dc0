//! Events written by other nodes, relayed to this node's event streams.
//! With PostgreSQL every stored event is announced (`LISTEN
//! patchwork_events`, "<job id> <seq>", see migrations/postgres); for a job
//! someone here watches, the event is read from the store and published on
//! the local hub, where streams drop what they have already sent. A
//! notification lost while the connection was down leaves a gap that the
//! stream notices by its ids and fills from the store.

use std::time::Duration;

use sqlx::postgres::PgListener;

use super::state::AppState;

pub fn start(state: &AppState) -> Option<tokio::task::JoinHandle<()>> {
    let pool = state.store.postgres()?.clone();
    let state = state.clone();
    Some(tokio::spawn(async move {
        loop {
            match PgListener::connect_with(&pool).await {
                Ok(mut listener) => {
                    if let Err(e) = listener.listen("patchwork_events").await {
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

/// Publishes each announced event of a watched job until the connection fails.
async fn relay(state: &AppState, listener: &mut PgListener) {
    loop {
        let notification = match listener.recv().await {
            Ok(n) => n,
            Err(e) => return tracing::warn!("receiving events: {e}"),
        };
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
