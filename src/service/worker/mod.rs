//! The worker pool: each worker claims the oldest claimable job (queued, or
//! running under a lease that ran out), holds its lease while it runs the
//! design pipeline on a blocking thread (never on the async runtime), streams
//! its progress into the store (`progress.rs`) and stores how it ended
//! (`ending.rs`). A claimed job with a checkpoint resumes from it.

mod ending;
mod progress;

use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use patchwork_core::inverse::{DesignCheckpoint, design_resumable};
use tokio::sync::mpsc;
use tracing::Instrument;

use super::spec::JobSpec;
use super::state::{AppState, JobControl, StopReason};
use super::store::{Claim, Lease, Renewal};
use ending::fail;
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
    let Claim {
        job,
        checkpoint,
        lease,
        ..
    } = claim;
    let id = job.id.clone();
    let spec = match job.spec.as_deref().map(JobSpec::from_stored) {
        // Each kind of job runs its own way; a design is the only kind.
        Some(Ok(JobSpec::Design(design))) => design,
        Some(Err(e)) => return fail(state, &lease, &e.to_string()).await,
        None => return fail(state, &lease, MISSING_SPEC).await,
    };
    let resume = checkpoint.and_then(|text| readable_checkpoint(&text));
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
    let (tx, rx) = mpsc::unbounded_channel();
    let seed = spec.plan().settings().seed;
    let span = tracing::Span::current();
    let caches = state.caches.clone();
    let compute = {
        let control = control.clone();
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
    let started = Instant::now();
    progress::record_all(state, &lease, rx, resumed_evaluations).await;
    let outcome = compute.await;
    timer.abort();
    if let Ok(mut running) = state.running.lock() {
        running.remove(&id);
    }
    state.counters.jobs.record(started.elapsed());
    // Renewals go on until the ending is stored, however long the database
    // takes to answer.
    ending::conclude(state, &lease, outcome, control.reason(), seed).await;
    renewals.abort();
}

/// A stored checkpoint, or `None` (start again) when it cannot be read.
fn readable_checkpoint(text: &str) -> Option<DesignCheckpoint> {
    serde_json::from_str(text)
        .inspect_err(|e| tracing::warn!("checkpoint unreadable, starting again: {e}"))
        .ok()
}

/// Renews the job's lease while it runs, and stops the run when the job was
/// cancelled (through any node) or claimed by another worker. A cancel on
/// another node is announced and stops the run at once (relay.rs); the
/// renewals (a tenth of the lease, at most a second apart) catch one whose
/// announcement was lost.
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

/// Stops every running job for shutdown; they return to the queue.
pub fn stop_all(state: &AppState) {
    if let Ok(running) = state.running.lock() {
        for control in running.values() {
            control.stop(StopReason::Shutdown);
        }
    }
}
