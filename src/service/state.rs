//! What every handler and worker shares: the store, the live event hub, the
//! controls of running jobs, the settings and the counters.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use tokio::sync::{Notify, broadcast};

use super::config::Config;
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
}

/// Why a running job is being stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    Cancelled,
    TimeLimit,
    /// The server is shutting down: the job goes back to the queue and
    /// resumes from its checkpoint at the next start.
    Shutdown,
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

    pub fn publish(&self, job: &str, event: StoredEvent) {
        let mut channels = self.channels.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(sender) = channels.get(job)
            && sender.send(event).is_err()
        {
            // Nobody listens any more.
            channels.remove(job);
        }
    }
}

/// Process-lifetime counters for /metrics.
#[derive(Default)]
pub struct Counters {
    pub simulate_requests: AtomicU64,
    /// Sum of synchronous simulate times, microseconds.
    pub simulate_micros: AtomicU64,
    pub jobs_finished: AtomicU64,
    /// Sum of finished jobs' wall times, microseconds.
    pub job_micros: AtomicU64,
    pub forward_solves: AtomicU64,
}

impl Shared {
    /// Appends an event to the store and publishes it live.
    pub async fn emit(
        &self,
        job: &str,
        kind: &str,
        data: &serde_json::Value,
    ) -> Result<(), sqlx::Error> {
        let event = self
            .store
            .append_event(job, kind, &data.to_string())
            .await?;
        self.hub.publish(job, event);
        Ok(())
    }

    pub fn control(&self, job: &str) -> Option<Arc<JobControl>> {
        self.running.lock().ok().and_then(|r| r.get(job).cloned())
    }
}
