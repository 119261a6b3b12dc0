//! What a job store is: the [`JobStore`] trait that the service uses, the
//! [`JobTransfer`] trait that moves whole jobs between stores, and the
//! [`Dialect`] a backend gives so that the statements written once
//! (`statements.rs`, `transfer.rs`) run on it. A new backend implements
//! `Dialect`, invokes `job_store!` and `job_transfer!` with its own
//! `requeue_orphans`, and passes the conformance suite (`conformance.rs`);
//! the compiler names whatever it leaves out.

use std::future::Future;
use std::time::Duration;

use async_trait::async_trait;
use patchwork_core::fabrication::OutputFile;

use super::export::JobExport;
use super::{Claim, Iteration, JobRow, Lease, ProfileRow, Renewal, StoredEvent};
use crate::service::job_state::{Ending, EventKind, JobStatus};

/// Every job's events, iterations, checkpoints, results and files, and
/// the owners' balloon profiles.
#[async_trait]
pub trait JobStore: JobTransfer + ProfileStore + Send + Sync {
    /// Whether the database answers.
    async fn ping(&self) -> bool;

    /// Inserts a queued job — the request as sent and its job spec — with
    /// its first event, at once (a worker never sees the job without it);
    /// `None` when the owner already used `idempotency_key`.
    async fn insert_job(
        &self,
        id: &str,
        owner: &str,
        request: &str,
        spec: &str,
        idempotency_key: Option<&str>,
        event: (EventKind, &str),
    ) -> Result<Option<(JobRow, StoredEvent)>, sqlx::Error>;

    async fn job_by_idempotency_key(
        &self,
        owner: &str,
        key: &str,
    ) -> Result<Option<JobRow>, sqlx::Error>;

    /// The job if it exists and belongs to `owner` (`None` sees every job).
    async fn job(&self, id: &str, owner: Option<&str>) -> Result<Option<JobRow>, sqlx::Error>;

    /// Newest first; `before` is the id of the last job of the previous page.
    async fn list_jobs(
        &self,
        owner: Option<&str>,
        status: Option<JobStatus>,
        before: Option<&str>,
        limit: i64,
    ) -> Result<Vec<JobRow>, sqlx::Error>;

    /// How many jobs have each status (statuses without jobs left out).
    async fn count_by_status(&self) -> Result<Vec<(JobStatus, i64)>, sqlx::Error>;

    async fn queued_count(&self) -> Result<i64, sqlx::Error>;

    /// Takes the oldest job that is queued, or running with a lease that ran
    /// out (its node died), marks it running under a new lease of
    /// `duration` held by `node`, and counts the attempt.
    async fn claim_next(
        &self,
        node: &str,
        duration: Duration,
    ) -> Result<Option<Claim>, sqlx::Error>;

    /// Extends the lease by `duration` if the job is still this lease's.
    async fn renew(&self, lease: &Lease, duration: Duration) -> Result<Renewal, sqlx::Error>;

    /// At start-up of the one node of a SQLite file: jobs left running (the
    /// process was killed) are queued again at once, to resume from their
    /// checkpoints. A store that several nodes share waits for such leases
    /// to run out instead (another node may hold them). Returns how many.
    async fn requeue_orphans(&self) -> Result<u64, sqlx::Error>;

    /// Puts a running job back in the queue (shutdown); its checkpoint stays.
    async fn requeue(&self, lease: &Lease) -> Result<(), sqlx::Error>;

    /// Ends a job that has not ended — failed or cancelled — and stores its
    /// final event (`ending`'s, with `data`) in the same transaction, so an
    /// ended job always has its final event. `None` when the job had already
    /// ended, or `fence` (a worker's attempt) is no longer the job's.
    async fn end(
        &self,
        id: &str,
        ending: Ending,
        error: Option<&str>,
        data: &str,
        fence: Option<i64>,
    ) -> Result<Option<StoredEvent>, sqlx::Error>;

    /// Appends an event with the job's next id; with `fence` (a worker's
    /// attempt) only while the job is running under that attempt.
    async fn append_event(
        &self,
        id: &str,
        kind: EventKind,
        data: &str,
        fence: Option<i64>,
    ) -> Result<Option<StoredEvent>, sqlx::Error>;

    /// Jobs stored before job specs (their `spec` is `None`), oldest first.
    async fn jobs_without_spec(&self) -> Result<Vec<JobRow>, sqlx::Error>;

    /// Stores the spec of a job stored without one; `false` when the job is
    /// gone or already has one.
    async fn set_spec(&self, id: &str, spec: &str) -> Result<bool, sqlx::Error>;

    /// The job's events after id `after`, in order.
    async fn events_after(&self, id: &str, after: i64) -> Result<Vec<StoredEvent>, sqlx::Error>;

    /// The latest progress, and the generation's row when it is one.
    async fn record_progress(
        &self,
        lease: &Lease,
        progress: &str,
        iteration: Option<&Iteration>,
    ) -> Result<(), sqlx::Error>;

    /// Keeps `checkpoint`, taken after `evaluations`, unless the job holds a
    /// later one: a checkpoint never goes back.
    async fn save_checkpoint(
        &self,
        lease: &Lease,
        checkpoint: &str,
        evaluations: i64,
    ) -> Result<(), sqlx::Error>;

    /// Stores the result, its files and the `done` event and marks the job
    /// succeeded, all at once. `None` (nothing stored) when the job had
    /// already ended (cancelled) or the lease is no longer the job's.
    async fn finish(
        &self,
        lease: &Lease,
        result: &str,
        files: &[OutputFile],
        done: &str,
    ) -> Result<Option<StoredEvent>, sqlx::Error>;

    /// Up to `limit` generations after `after` evaluations, in order.
    async fn iterations(
        &self,
        id: &str,
        after: i64,
        limit: i64,
    ) -> Result<Vec<Iteration>, sqlx::Error>;

    async fn result(&self, id: &str) -> Result<Option<String>, sqlx::Error>;

    /// A result file's content type and body.
    async fn file(&self, id: &str, name: &str) -> Result<Option<(String, Vec<u8>)>, sqlx::Error>;

    /// Removes the job and everything it produced.
    async fn delete(&self, id: &str) -> Result<(), sqlx::Error>;

    /// The PostgreSQL pool, for LISTEN; `None` for a store of one node.
    fn postgres(&self) -> Option<&sqlx::PgPool> {
        None
    }
}

/// Balloon profiles, by owner and name (`profiles.rs`).
#[async_trait]
pub trait ProfileStore: Send + Sync {
    /// Stores `profile` (JSON) as the owner's `name`, replacing one there;
    /// `true` when it is new.
    async fn put_profile(
        &self,
        owner: &str,
        name: &str,
        profile: &str,
        source_job: Option<&str>,
    ) -> Result<bool, sqlx::Error>;

    async fn profile(&self, owner: &str, name: &str) -> Result<Option<ProfileRow>, sqlx::Error>;

    /// The owner's profiles, by name.
    async fn profiles(&self, owner: &str) -> Result<Vec<ProfileRow>, sqlx::Error>;

    /// `false` when the owner has no such profile.
    async fn delete_profile(&self, owner: &str, name: &str) -> Result<bool, sqlx::Error>;

    /// Every owner's profiles, by owner and name (`patchwork copy-jobs`).
    async fn all_profiles(&self) -> Result<Vec<ProfileRow>, sqlx::Error>;

    /// Stores a profile read from another store as it was (its times
    /// kept); `false`, writing nothing, when its owner already has one of
    /// that name here.
    async fn import_profile(&self, profile: &ProfileRow) -> Result<bool, sqlx::Error>;
}

/// Whole jobs out of one store and into another (`patchwork copy-jobs`).
#[async_trait]
pub trait JobTransfer: Send + Sync {
    /// Every job's id, oldest first.
    async fn job_ids(&self) -> Result<Vec<String>, sqlx::Error>;

    /// The job with its events, iterations and files.
    async fn export_job(&self, id: &str) -> Result<Option<JobExport>, sqlx::Error>;

    /// Stores an exported job (a running one as queued, to resume from its
    /// checkpoint); `false`, writing nothing, when the job is already here.
    async fn import_job(&self, job: &JobExport) -> Result<bool, sqlx::Error>;
}

/// What a backend says that the shared statements cannot: how a claim locks
/// its row, how a job's events are numbered, and how an imported job's
/// event counter is restored.
pub trait Dialect {
    /// The backend's connection (a transaction dereferences to it).
    type Connection: Send;

    /// Appended to the claim's subquery (a row lock, or nothing).
    const CLAIM_LOCK: &'static str;

    /// Run after a job's events are imported, with the job's id as `$1`;
    /// empty when the events number themselves.
    const IMPORT_SEQ: &'static str;

    /// Inserts an event with the job's next id in the caller's transaction;
    /// with `fence`, only while the job runs under that attempt.
    fn insert_event<'c>(
        connection: &'c mut Self::Connection,
        id: &'c str,
        event: (EventKind, &'c str),
        fence: Option<i64>,
    ) -> impl Future<Output = Result<Option<StoredEvent>, sqlx::Error>> + Send + 'c;
}
