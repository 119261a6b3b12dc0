//! What every handler and worker shares: the store, the live event hub, the
//! controls of running jobs, the settings and the counters.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use tokio::sync::{Notify, broadcast};

use patchwork_core::inverse::Caches;

use super::config::Config;
use super::job_state::{Ending, EventKind};
use super::store::{Store, StoredEvent};

pub type AppState = Arc<Shared>;

pub struct Shared {
    pub store: Store,
    pub config: Config,
    pub hub: Hub,
    /// Running jobs, by id.
    pub running: Mutex<HashMap<String, Arc<JobControl>>>,
    /// Rung when a job is queued (and at shutdown).
    pub wake: Notify,
    pub shutting_down: AtomicBool,
    pub counters: Counters,
    /// Solves the design jobs share: a job run again finds its cold solves,
    /// and jobs on one mesh topology its tangent pattern.
    pub caches: Arc<Caches>,
}

/// Why a running job is being stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    Cancelled,
    TimeLimit,
    /// The server is shutting down: the job goes back to the queue and
    /// resumes from its checkpoint at the next start.
    Shutdown,
    /// Another worker claimed the job (this one's lease ran out): stop
    /// without writing.
    LeaseLost,
}

/// The handle on one running job.
#[derive(Default)]
pub struct JobControl {
    pub cancel: AtomicBool,
    reason: Mutex<Option<StopReason>>,
}

impl JobControl {
    /// Stops the job; the first reason given is the one that counts.
    pub fn stop(&self, reason: StopReason) {
        if let Ok(mut r) = self.reason.lock() {
            r.get_or_insert(reason);
        }
        self.cancel.store(true, Ordering::Relaxed);
    }

    pub fn reason(&self) -> Option<StopReason> {
        self.reason.lock().ok().and_then(|r| *r)
    }
}

/// Live events, one broadcast channel per job with listeners. Events are
/// written to the store first and then published, so a listener that misses
/// one (lag) finds it in the store.
#[derive(Default)]
pub struct Hub {
    channels: Mutex<HashMap<String, broadcast::Sender<StoredEvent>>>,
}

impl Hub {
    pub fn subscribe(&self, job: &str) -> broadcast::Receiver<StoredEvent> {
        let mut channels = self.channels.lock().unwrap_or_else(|p| p.into_inner());
        channels
            .entry(job.to_string())
            .or_insert_with(|| broadcast::channel(1024).0)
            .subscribe()
    }

    /// Drops the job's channel when no listener is left (a listener that
    /// subscribed to a job that then ended without publishing again).
    pub fn forget_if_unused(&self, job: &str) {
        let mut channels = self.channels.lock().unwrap_or_else(|p| p.into_inner());
        if channels.get(job).is_some_and(|s| s.receiver_count() == 0) {
            channels.remove(job);
        }
    }

    /// Whether anyone here listens to the job's events.
    pub fn watched(&self, job: &str) -> bool {
        let channels = self.channels.lock().unwrap_or_else(|p| p.into_inner());
        channels.contains_key(job)
    }

    /// Sends an event to the job's listeners. After a final event the channel
    /// is dropped: listeners still receive what was sent, then `Closed`.
    pub fn publish(&self, job: &str, event: StoredEvent) {
        let last = event.kind.is_final();
        let mut channels = self.channels.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(sender) = channels.get(job)
            && (sender.send(event).is_err() || last)
        {
            // Nobody listens any more, or nothing more will come.
            channels.remove(job);
        }
    }
}

/// Process-lifetime counters for /metrics.
#[derive(Default)]
pub struct Counters {
    /// Synchronous simulations (POST /v1/simulate).
    pub simulate: Timings,
    /// Design job runs in this process (a resumed job counts again).
    pub jobs: Timings,
    pub forward_solves: AtomicU64,
    pub claims: AtomicU64,
    pub takeovers: AtomicU64,
    pub leases_lost: AtomicU64,
}

/// How many times something ran and its total wall time: a Prometheus summary
/// without quantiles.
#[derive(Default)]
pub struct Timings {
    count: AtomicU64,
    micros: AtomicU64,
}

impl Timings {
    pub fn record(&self, took: std::time::Duration) {
        self.count.fetch_add(1, Ordering::Relaxed);
        self.micros
            .fetch_add(took.as_micros() as u64, Ordering::Relaxed);
    }

    pub fn count(&self) -> u64 {
        self.count.load(Ordering::Relaxed)
    }

    pub fn seconds(&self) -> f64 {
        self.micros.load(Ordering::Relaxed) as f64 * 1e-6
    }
}

impl Shared {
    /// Appends an event to the store and publishes it live; with `fence`
    /// (a worker's attempt) only while the job is that attempt's.
    pub async fn emit(
        &self,
        job: &str,
        kind: EventKind,
        data: &serde_json::Value,
        fence: Option<i64>,
    ) -> Result<(), sqlx::Error> {
        let stored = self
            .store
            .append_event(job, kind, &data.to_string(), fence)
            .await?;
        if let Some(event) = stored {
            self.hub.publish(job, event);
        }
        Ok(())
    }

    /// Ends a job (failed or cancelled) with its final event; false if it
    /// had already ended.
    pub async fn end_job(
        &self,
        job: &str,
        ending: Ending,
        error: Option<&str>,
        data: &serde_json::Value,
        fence: Option<i64>,
    ) -> Result<bool, sqlx::Error> {
        let stored = self
            .store
            .end(job, ending, error, &data.to_string(), fence)
            .await?;
        Ok(match stored {
            Some(event) => {
                self.hub.publish(job, event);
                true
            }
            None => false,
        })
    }

    pub fn control(&self, job: &str) -> Option<Arc<JobControl>> {
        self.running.lock().ok().and_then(|r| r.get(job).cloned())
    }
}
