//! What a running design reports, carried from its blocking thread to the
//! async side in order, and written there: progress (with the generation's
//! row), the stages as they begin, checkpoints and the reach report, each fenced by the
//! worker's attempt. A write the database refuses is logged and skipped: the
//! run goes on, and the next progress or checkpoint replaces it.

use std::sync::atomic::Ordering;

use patchwork_core::inverse::reach::ReachReport;
use patchwork_core::inverse::{DesignCheckpoint, DesignProgress, Observer, StageName};
use serde_json::json;
use tokio::sync::mpsc;

use crate::service::job_state::EventKind;
use crate::service::state::AppState;
use crate::service::store::{Iteration, Lease};

/// What the blocking pipeline tells the async side, in order.
pub(super) enum Message {
    /// A stage begins.
    Stage(DesignProgress),
    Progress(DesignProgress),
    /// A checkpoint, as JSON, and the evaluations it was taken after.
    Checkpoint(String, usize),
    /// The reach report, as JSON.
    Reach(serde_json::Value),
}

/// The run's observer: every progress report, checkpoint and the reach
/// report go to the async side, which records them in order.
pub(super) struct ChannelObserver(pub(super) mpsc::UnboundedSender<Message>);

impl Observer for ChannelObserver {
    fn progress(&mut self, progress: &DesignProgress) {
        let _ = self.0.send(Message::Progress(*progress));
    }

    fn stage(&mut self, progress: &DesignProgress) {
        let _ = self.0.send(Message::Stage(*progress));
    }

    fn checkpoint(&mut self, checkpoint: &DesignCheckpoint) {
        if let Ok(text) = serde_json::to_string(checkpoint) {
            let _ = self
                .0
                .send(Message::Checkpoint(text, checkpoint.evaluations));
        }
    }

    fn reach(&mut self, report: &ReachReport) {
        if let Ok(value) = serde_json::to_value(report) {
            let _ = self.0.send(Message::Reach(value));
        }
    }
}

/// Writes every message of the run, in order, until the run ends;
/// `resumed_evaluations` were counted in /metrics by an earlier attempt.
pub(super) async fn record_all(
    state: &AppState,
    lease: &Lease,
    mut messages: mpsc::UnboundedReceiver<Message>,
    resumed_evaluations: usize,
) {
    let mut last_evaluations = resumed_evaluations;
    while let Some(message) = messages.recv().await {
        let recorded = record(state, lease, message, &mut last_evaluations);
        if let Err(e) = recorded.await {
            tracing::error!("recording progress: {e}");
        }
    }
}

async fn record(
    state: &AppState,
    lease: &Lease,
    message: Message,
    last_evaluations: &mut usize,
) -> Result<(), sqlx::Error> {
    let (id, fence) = (lease.id.as_str(), Some(lease.attempt));
    match message {
        Message::Checkpoint(text, evaluations) => {
            state
                .store
                .save_checkpoint(lease, &text, evaluations as i64)
                .await
        }
        Message::Reach(report) => state.emit(id, EventKind::Reach, &report, fence).await,
        // The stage's event, and the job's progress at its start.
        Message::Stage(p) => {
            state
                .emit(id, EventKind::Stage, &json!({"stage": p.stage}), fence)
                .await?;
            let progress = serde_json::to_value(p).unwrap_or_default();
            state
                .store
                .record_progress(lease, &progress.to_string(), None)
                .await
        }
        Message::Progress(p) => {
            // A NaN objective (before the seed is evaluated) serialises as null.
            let progress = serde_json::to_value(p).unwrap_or_default();
            let iteration = (p.stage == StageName::Search).then_some(Iteration {
                evaluations: p.evaluations as i64,
                generation: p.generation as i64,
                best_objective: p.best_objective,
                sigma: p.sigma,
                elapsed_s: p.elapsed_s,
            });
            state.counters.forward_solves.fetch_add(
                p.evaluations.saturating_sub(*last_evaluations) as u64,
                Ordering::Relaxed,
            );
            *last_evaluations = p.evaluations;
            state
                .store
                .record_progress(lease, &progress.to_string(), iteration.as_ref())
                .await?;
            if p.stage == StageName::Search {
                state
                    .emit(id, EventKind::Progress, &progress, fence)
                    .await?;
            }
            Ok(())
        }
    }
}
