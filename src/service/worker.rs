//! The worker pool: each worker takes the oldest queued job, runs the design
//! pipeline on a blocking thread (never on the async runtime), and streams its
//! progress, iterations and checkpoints into the store as it goes. A job found
//! `running` at start-up was interrupted: it is queued again and resumes from
//! its last checkpoint.

use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use patchwork_core::inverse::reach::ReachReport;
use patchwork_core::inverse::{
    DesignCheckpoint, DesignProgress, DesignReport, DesignRunError, Observer, Stage,
    design_resumable,
};
use serde_json::json;
use tokio::sync::mpsc;
use tracing::Instrument;

use super::request::JobRequest;
use super::state::{AppState, JobControl, StopReason};
use super::store::{Claim, Iteration, Lease, Renewal};
use patchwork_core::fabrication::design_files;

/// What the blocking pipeline tells the async side, in order.
enum Message {
    Progress(DesignProgress),
    /// A checkpoint, as JSON, and the evaluations it was taken after.
    Checkpoint(String, usize),
    /// The reach report, as JSON.
    Reach(serde_json::Value),
}

/// The run's observer: every progress report, checkpoint and the reach
/// report go to the async side, which records them in order.
struct ChannelObserver(mpsc::UnboundedSender<Message>);

impl Observer for ChannelObserver {
    fn progress(&mut self, progress: &DesignProgress) {
        let _ = self.0.send(Message::Progress(*progress));
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

pub fn start(state: &AppState) -> Vec<tokio::task::JoinHandle<()>> {
    (0..state.config.workers)
        .map(|n| {
            let state = state.clone();
            tokio::spawn(async move { worker(state, n).await })
        })
        .collect()
}

async fn worker(state: AppState, n: usize) {
    loop {
        if state.shutting_down.load(Ordering::Relaxed) {
            return;
        }
        match state
            .store
            .claim_next(&state.config.node, state.config.lease)
            .await
        {
            Ok(Some(claim)) => {
                state.counters.claims.fetch_add(1, Ordering::Relaxed);
                if claim.taken_over {
                    state.counters.takeovers.fetch_add(1, Ordering::Relaxed);
                }
                let span = tracing::info_span!("job", id = %claim.job.id, worker = n,
                    attempt = claim.lease.attempt);
                run_job(&state, claim).instrument(span).await;
            }
            Ok(None) => {
                // Sleep until a job is queued; poll now and then regardless.
                let _ = tokio::time::timeout(Duration::from_secs(2), state.wake.notified()).await;
            }
            Err(e) => {
                tracing::error!("claiming a job: {e}");
                tokio::time::sleep(Duration::from_secs(1)).await;
            }
        }
    }
}

async fn run_job(state: &AppState, claim: Claim) {
    let Claim {
        job,
        checkpoint,
        lease,
        ..
    } = claim;
    let id = job.id.clone();
    let request: JobRequest = match serde_json::from_str(&job.request) {
        Ok(r) => r,
        Err(e) => return fail(state, &lease, &format!("stored request unreadable: {e}")).await,
    };
    let prepared = match request.prepare() {
        Ok(p) => p,
        Err(p) => return fail(state, &lease, &p.detail).await,
    };
    let resume: Option<DesignCheckpoint> =
        checkpoint.and_then(|c| match serde_json::from_str(&c) {
            Ok(checkpoint) => Some(checkpoint),
            Err(e) => {
                tracing::warn!("checkpoint unreadable, starting again: {e}");
                None
            }
        });
    let earlier = resume.as_ref().map_or(0.0, |c| c.elapsed_s);
    let resumed_evaluations = resume.as_ref().map_or(0, |c| c.evaluations);
    if let Some(c) = &resume {
        tracing::info!(evaluations = c.evaluations, "resuming from checkpoint");
    } else {
        tracing::info!("starting");
    }
    let control = Arc::new(JobControl::default());
    if let Ok(mut running) = state.running.lock() {
        running.insert(id.clone(), control.clone());
    }
    let limit = state
        .config
        .job_time_limit
        .saturating_sub(Duration::from_secs_f64(earlier));
    let timer = {
        let control = control.clone();
        tokio::spawn(async move {
            tokio::time::sleep(limit).await;
            control.stop(StopReason::TimeLimit);
        })
    };
    let renewals = tokio::spawn(hold(state.clone(), lease.clone(), control.clone()));
    let (tx, mut rx) = mpsc::unbounded_channel();
    let seed = prepared.plan.settings().seed;
    let span = tracing::Span::current();
    let caches = state.caches.clone();
    let compute = {
        let control = control.clone();
        tokio::task::spawn_blocking(move || {
            let _entered = span.enter();
            design_resumable(
                &prepared.target,
                &prepared.plan,
                resume,
                &caches,
                &control.cancel,
                &mut ChannelObserver(tx),
            )
        })
    };
    let started = Instant::now();
    let mut last_stage = None;
    // Evaluations already counted in /metrics (a resumed job's earlier ones were).
    let mut last_evaluations = resumed_evaluations;
    while let Some(message) = rx.recv().await {
        if let Err(e) = record(
            state,
            &lease,
            message,
            &mut last_stage,
            &mut last_evaluations,
        )
        .await
        {
            tracing::error!("recording progress: {e}");
        }
    }
    let outcome = compute.await;
    timer.abort();
    renewals.abort();
    if let Ok(mut running) = state.running.lock() {
        running.remove(&id);
    }
    state.counters.jobs.record(started.elapsed());
    match outcome {
        Ok(Ok(outcome)) => {
            let report = DesignReport::new(&outcome, seed);
            let files = match design_files(&report) {
                Ok(files) => files,
                Err(e) => {
                    return fail(state, &lease, &format!("writing the result files: {e}")).await;
                }
            };
            let result = files
                .iter()
                .find(|f| f.name == "design.json")
                .map(|f| String::from_utf8_lossy(&f.body).into_owned())
                .unwrap_or_default();
            let m = &report.metrics;
            let done = json!({
                "result": format!("/v1/jobs/{id}/result"),
                "shape_error_percent": finite(m.shape_error_percent),
                "objective": finite(m.objective),
                "evaluations": report.evaluations,
                "elapsed_s": report.elapsed_s,
            });
            match state
                .store
                .finish(&lease, &result, &files, &done.to_string())
                .await
            {
                Ok(Some(event)) => {
                    state.hub.publish(&id, event);
                    tracing::info!(
                        evaluations = report.evaluations,
                        shape_error_percent = m.shape_error_percent,
                        "succeeded"
                    );
                }
                Ok(None) => {
                    tracing::info!("finished after it was cancelled or taken over; result dropped")
                }
                Err(e) => tracing::error!("storing the result: {e}"),
            }
        }
        Ok(Err(DesignRunError::Cancelled)) => match control.reason() {
            Some(StopReason::Shutdown) => {
                // Back to the queue: the next start resumes from the checkpoint.
                if let Err(e) = state.store.requeue(&lease).await {
                    tracing::error!("re-queueing: {e}");
                }
                tracing::info!("interrupted by shutdown; queued to resume");
            }
            Some(StopReason::TimeLimit) => {
                let limit = state.config.job_time_limit.as_secs();
                fail(state, &lease, &format!("time limit of {limit} s exceeded")).await
            }
            Some(StopReason::LeaseLost) => {
                tracing::warn!("lease lost: another worker holds the job; stopped without writing")
            }
            _ => tracing::info!("stopped: cancelled"),
        },
        Ok(Err(e)) => fail(state, &lease, &e.to_string()).await,
        Err(e) => fail(state, &lease, &format!("internal error: {e}")).await,
    }
}

/// NaN and infinities have no JSON form: report them as null.
fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// Renews the job's lease while it runs, and stops the run when the job was
/// cancelled (through any node) or claimed by another worker. Renewals come
/// often enough (a tenth of the lease, at most a second apart) that a
/// cancel on another node stops the run within about a second.
async fn hold(state: AppState, lease: Lease, control: Arc<JobControl>) {
    let every = (state.config.lease / 10).min(Duration::from_secs(1));
    loop {
        tokio::time::sleep(every).await;
        match state.store.renew(&lease, state.config.lease).await {
            Ok(Renewal::Held) => {}
            Ok(Renewal::Cancelled) => return control.stop(StopReason::Cancelled),
            Ok(Renewal::Lost) => {
                state.counters.leases_lost.fetch_add(1, Ordering::Relaxed);
                return control.stop(StopReason::LeaseLost);
            }
            Err(e) => tracing::warn!("renewing the lease: {e}"),
        }
    }
}

async fn record(
    state: &AppState,
    lease: &Lease,
    message: Message,
    last_stage: &mut Option<Stage>,
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
        Message::Reach(report) => state.emit(id, "reach", &report, fence).await,
        Message::Progress(p) => {
            if *last_stage != Some(p.stage) {
                *last_stage = Some(p.stage);
                state
                    .emit(id, "stage", &json!({"stage": p.stage}), fence)
                    .await?;
            }
            // A NaN objective (before the seed is evaluated) serialises as null.
            let progress = serde_json::to_value(p).unwrap_or_default();
            let iteration = (p.stage == Stage::Search).then_some(Iteration {
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
            if p.stage == Stage::Search {
                state.emit(id, "progress", &progress, fence).await?;
            }
            Ok(())
        }
    }
}

async fn fail(state: &AppState, lease: &Lease, error: &str) {
    tracing::warn!("failed: {error}");
    let event = json!({ "error": error });
    let fence = Some(lease.attempt);
    if let Err(e) = state
        .end_job(&lease.id, "failed", Some(error), &event, fence)
        .await
    {
        tracing::error!("marking failed: {e}");
    }
}

/// Stops every running job for shutdown; they return to the queue.
pub fn stop_all(state: &AppState) {
    if let Ok(running) = state.running.lock() {
        for control in running.values() {
            control.stop(StopReason::Shutdown);
        }
    }
}
