//! The worker pool: each worker claims the oldest claimable job (queued, or
//! running under a lease that ran out), holds its lease while it runs the
//! job on a blocking thread (never on the async runtime), streams its
//! progress into the store (`progress.rs`) and stores how it ended
//! (`ending.rs`). A design resumes from its checkpoint; a calibration
//! (`calibration.rs`) starts again.

mod calibration;
mod ending;
mod holding;
mod progress;

use std::sync::atomic::Ordering;
use std::time::Duration;

use patchwork_core::inverse::{DesignCheckpoint, design_resumable};
use tokio::sync::mpsc;
use tracing::Instrument;

use super::spec::{DesignSpec, JobSpec};
use super::state::{AppState, StopReason};
use super::store::Claim;
use ending::fail;
use holding::Holding;
use progress::ChannelObserver;

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

/// A job stored without its spec (every job gets one when it is submitted,
/// and jobs stored before specs get theirs at the next start).
const MISSING_SPEC: &str = "the job was stored without a job spec; submit it again";

async fn run_job(state: &AppState, claim: Claim) {
    let spec = match claim.job.spec.as_deref().map(JobSpec::from_stored) {
        Some(Ok(spec)) => spec,
        Some(Err(e)) => return fail(state, &claim.lease, &e.to_string()).await,
        None => return fail(state, &claim.lease, MISSING_SPEC).await,
    };
    // Each kind of job runs its own way.
    match spec {
        JobSpec::Design(design) => run_design(state, claim, *design).await,
        JobSpec::Calibrate(calibrate) => calibration::run(state, claim, *calibrate).await,
    }
}

async fn run_design(state: &AppState, claim: Claim, spec: DesignSpec) {
    let Claim {
        checkpoint, lease, ..
    } = claim;
    let resume = checkpoint.and_then(|text| readable_checkpoint(&text));
    let earlier = resume.as_ref().map_or(0.0, |c| c.elapsed_s);
    let resumed_evaluations = resume.as_ref().map_or(0, |c| c.evaluations);
    if let Some(c) = &resume {
        tracing::info!(evaluations = c.evaluations, "resuming from checkpoint");
    } else {
        tracing::info!("starting");
    }
    let holding = Holding::start(state, &lease, Duration::from_secs_f64(earlier));
    let (tx, rx) = mpsc::unbounded_channel();
    let seed = spec.plan().settings().seed;
    let span = tracing::Span::current();
    let caches = state.caches.clone();
    let compute = {
        let control = holding.control.clone();
        tokio::task::spawn_blocking(move || {
            let _entered = span.enter();
            design_resumable(
                spec.target(),
                spec.plan(),
                resume,
                &caches,
                &control.cancel,
                &mut ChannelObserver(tx),
            )
        })
    };
    progress::record_all(state, &lease, rx, resumed_evaluations).await;
    let outcome = compute.await;
    holding.computed(state, &lease);
    let ran = ending::design_ran(outcome, seed);
    if let Some(report) = ending::unless_done(state, &lease, ran, holding.control.reason()).await {
        ending::succeed(state, &lease, &report).await;
    }
    holding.release();
}

/// A stored checkpoint, or `None` (start again) when it cannot be read.
fn readable_checkpoint(text: &str) -> Option<DesignCheckpoint> {
    serde_json::from_str(text)
        .inspect_err(|e| tracing::warn!("checkpoint unreadable, starting again: {e}"))
        .ok()
}

/// Stops every running job for shutdown; they return to the queue.
pub fn stop_all(state: &AppState) {
    if let Ok(running) = state.running.lock() {
        for control in running.values() {
            control.stop(StopReason::Shutdown);
        }
    }
}
