//! What holds a running job, whatever its kind: its control among the
//! running jobs, the time limit's timer, and the lease's renewals.

use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use crate::service::state::{AppState, JobControl, StopReason};
use crate::service::store::{Lease, Renewal};

/// What holds a run while it computes: its control among the running jobs
/// (cancel and delete stop it through it), the time limit's timer, and the
/// lease's renewals.
pub(super) struct Holding {
    pub(super) control: Arc<JobControl>,
    timer: tokio::task::JoinHandle<()>,
    renewals: tokio::task::JoinHandle<()>,
    started: Instant,
}

impl Holding {
    /// Holds the run of `lease`'s job, which already ran for `earlier`.
    pub(super) fn start(state: &AppState, lease: &Lease, earlier: Duration) -> Holding {
        let control = Arc::new(JobControl::default());
        if let Ok(mut running) = state.running.lock() {
            running.insert(lease.id.clone(), control.clone());
        }
        let limit = state.config.job_time_limit.saturating_sub(earlier);
        let timer = {
            let control = control.clone();
            tokio::spawn(async move {
                tokio::time::sleep(limit).await;
                control.stop(StopReason::TimeLimit);
            })
        };
        let renewals = tokio::spawn(hold(state.clone(), lease.clone(), control.clone()));
        Holding {
            control,
            timer,
            renewals,
            started: Instant::now(),
        }
    }

    /// The computation is over: no longer running, nor timed. Renewals go
    /// on until [`Holding::release`], after the ending is stored, however
    /// long the database takes to answer.
    pub(super) fn computed(&self, state: &AppState, lease: &Lease) {
        self.timer.abort();
        if let Ok(mut running) = state.running.lock() {
            running.remove(&lease.id);
        }
        state.counters.jobs.record(self.started.elapsed());
    }

    pub(super) fn release(self) {
        self.renewals.abort();
    }
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
