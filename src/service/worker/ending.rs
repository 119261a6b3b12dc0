//! How a run ends in the store: the result stored and the job succeeded
//! (a design's here, a calibration's in `calibration.rs`),
//! the job failed, or (shutdown) queued again. These writes are what a user
//! waits for, so while the database does not answer (a restart, a network
//! failure) they are tried again until it does; the attempt fences them, so
//! a write that lands after another worker took the job over is dropped.

use std::future::Future;
use std::sync::atomic::Ordering;
use std::time::Duration;

use patchwork_core::fabrication::{OutputFile, design_files, design_json};
use patchwork_core::inverse::{DesignOutcome, DesignReport, DesignRunError};
use serde_json::json;

use crate::service::job_state::Ending;
use crate::service::state::{AppState, StopReason};
use crate::service::store::{self, Lease};

/// What the blocking design run returned (or how its thread failed).
pub(super) type Outcome = Result<Result<DesignOutcome, DesignRunError>, tokio::task::JoinError>;

/// How a run came out, whatever its kind: `T` is a finished run's answer.
pub(super) enum Ran<T> {
    Done(T),
    /// Stopped through its control: why is the control's reason.
    Stopped,
    Failed(String),
}

/// A design run's outcome as a [`Ran`].
pub(super) fn design_ran(outcome: Outcome, seed: u64) -> Ran<DesignReport> {
    match outcome {
        Ok(Ok(outcome)) => Ran::Done(DesignReport::new(&outcome, seed)),
        Ok(Err(DesignRunError::Cancelled)) => Ran::Stopped,
        Ok(Err(e)) => Ran::Failed(e.to_string()),
        Err(e) => Ran::Failed(format!("internal error: {e}")),
    }
}

/// Stores how a run that did not finish ended (`stopped` is why it was
/// stopped, if it was); a finished run's answer is given back, for its
/// kind's ending to store.
pub(super) async fn unless_done<T>(
    state: &AppState,
    lease: &Lease,
    ran: Ran<T>,
    stopped: Option<StopReason>,
) -> Option<T> {
    match ran {
        Ran::Done(answer) => return Some(answer),
        Ran::Stopped => match stopped {
            Some(StopReason::Shutdown) => {
                // Back to the queue: the next start (or another node) resumes
                // a design from its checkpoint. Tried once: the process is
                // leaving, and a lease that runs out comes back to the queue
                // as well.
                if let Err(e) = state.store.requeue(lease).await {
                    tracing::error!("re-queueing: {e}");
                }
                tracing::info!("interrupted by shutdown; queued to resume");
            }
            Some(StopReason::TimeLimit) => {
                let limit = state.config.job_time_limit.as_secs();
                fail(state, lease, &format!("time limit of {limit} s exceeded")).await
            }
            Some(StopReason::LeaseLost) => {
                tracing::warn!("lease lost: another worker holds the job; stopped without writing")
            }
            _ => tracing::info!("stopped: cancelled"),
        },
        Ran::Failed(error) => fail(state, lease, &error).await,
    }
    None
}

/// Stores the result, its files and the `done` event, and marks the job
/// succeeded.
pub(super) async fn succeed(state: &AppState, lease: &Lease, report: &DesignReport) {
    let written = design_json(report).and_then(|json| Ok((json, design_files(report)?)));
    let (result, files) = match written {
        Ok(written) => written,
        Err(e) => return fail(state, lease, &format!("writing the result files: {e}")).await,
    };
    let m = &report.metrics;
    let done = json!({
        "result": format!("/v1/jobs/{}/result", lease.id),
        "shape_error_percent": finite(m.shape_error_percent),
        "as_given_shape_error_percent": report.as_given.and_then(|g| finite(g.shape_error_percent)),
        "objective": finite(m.objective),
        "evaluations": report.evaluations,
        "elapsed_s": report.elapsed_s,
    })
    .to_string();
    if finish(state, lease, &result, &files, &done).await {
        tracing::info!(
            evaluations = report.evaluations,
            shape_error_percent = m.shape_error_percent,
            "succeeded"
        );
    }
}

/// Stores a finished run's result, files and `done` event (retried while
/// the database does not answer) and publishes the event; `true` when it
/// was stored, `false` when the job had ended or was taken over meanwhile
/// (or the store refused: logged).
pub(super) async fn finish(
    state: &AppState,
    lease: &Lease,
    result: &str,
    files: &[OutputFile],
    done: &str,
) -> bool {
    let stored = until_stored(state, "storing the result", || {
        state.store.finish(lease, result, files, done)
    });
    match stored.await {
        Ok(Some(event)) => {
            state.hub.publish(&lease.id, event);
            true
        }
        Ok(None) => {
            tracing::info!("finished after it was cancelled or taken over; result dropped");
            false
        }
        Err(e) => {
            tracing::error!("storing the result: {e}");
            false
        }
    }
}

/// Marks the job failed with `error`, and stores the `failed` event.
pub(super) async fn fail(state: &AppState, lease: &Lease, error: &str) {
    tracing::warn!("failed: {error}");
    let event = json!({ "error": error });
    let fence = Some(lease.attempt);
    let ended = until_stored(state, "marking failed", || {
        state.end_job(&lease.id, Ending::Failed, Some(error), &event, fence)
    });
    if let Err(e) = ended.await {
        tracing::error!("marking failed: {e}");
    }
}

/// Runs `write` until the database takes it: while the database is
/// unavailable (see [`store::unavailable`]) it is tried again, after
/// 0.25 s, 0.5 s, 1 s and then every 2 s, unless the node is shutting down.
/// Any other error is returned at once.
pub(super) async fn until_stored<T, F, W>(
    state: &AppState,
    what: &str,
    mut write: W,
) -> Result<T, sqlx::Error>
where
    W: FnMut() -> F,
    F: Future<Output = Result<T, sqlx::Error>>,
{
    let mut wait = Duration::from_millis(250);
    loop {
        match write().await {
            Err(e) if store::unavailable(&e) && !state.shutting_down.load(Ordering::Relaxed) => {
                tracing::warn!("{what}: {e}; trying again in {wait:?}");
                tokio::time::sleep(wait).await;
                wait = (wait * 2).min(Duration::from_secs(2));
            }
            other => return other,
        }
    }
}

/// NaN and infinities have no JSON form: report them as null.
pub(super) fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}
