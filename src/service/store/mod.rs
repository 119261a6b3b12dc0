//! The job store: every event, iteration, checkpoint and result file of a
//! job, so nothing is lost on restart. Two backends behind one interface:
//! SQLite (`sqlite.rs`, a file; the default) and PostgreSQL (`postgres.rs`,
//! a server that several nodes can share), each migrated at start from its
//! own `migrations/` folder. Most statements are written once for both
//! (`statements.rs`); each backend adds how it opens, numbers a job's
//! events and locks a claim. The service tests run against both.

mod postgres;
mod sqlite;
mod statements;
mod transfer;

use std::fmt;
use std::path::PathBuf;
use std::time::Duration;

use patchwork_core::fabrication::OutputFile;
use serde::Serialize;
use sqlx::FromRow;

pub use transfer::JobExport;

use postgres::PgStore;
use sqlite::SqliteStore;

/// Where the jobs live: `--db ./patchwork.db` or `--db postgres://…`.
#[derive(Debug, Clone)]
pub enum Database {
    Sqlite(PathBuf),
    Postgres(String),
}

impl Database {
    pub fn parse(text: &str) -> Database {
        if text.starts_with("postgres://") || text.starts_with("postgresql://") {
            Database::Postgres(text.to_string())
        } else {
            Database::Sqlite(PathBuf::from(text))
        }
    }
}

impl fmt::Display for Database {
    /// The location without a password.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Database::Sqlite(path) => write!(f, "{}", path.display()),
            Database::Postgres(url) => {
                let shown = match (url.find("://"), url.rfind('@')) {
                    (Some(scheme), Some(at)) if at > scheme => {
                        let credentials = &url[scheme + 3..at];
                        let user = credentials.split(':').next().unwrap_or_default();
                        format!("{}{user}@{}", &url[..scheme + 3], &url[at + 1..])
                    }
                    _ => url.clone(),
                };
                write!(f, "{shown}")
            }
        }
    }
}

#[derive(Clone)]
pub enum Store {
    Sqlite(SqliteStore),
    Postgres(PgStore),
}

/// A job as stored (without its checkpoint and result).
#[derive(Debug, Clone, FromRow)]
pub struct JobRow {
    pub id: String,
    pub status: String,
    pub request: String,
    pub created_at: String,
    pub updated_at: String,
    pub progress: Option<String>,
    pub error: Option<String>,
}

/// One server-sent event of a job.
#[derive(Debug, Clone, FromRow)]
pub struct StoredEvent {
    pub seq: i64,
    pub kind: String,
    pub data: String,
}

/// One CMA-ES generation of a job.
#[derive(Debug, Clone, Serialize, FromRow)]
pub struct Iteration {
    pub evaluations: i64,
    pub generation: i64,
    pub best_objective: f64,
    pub sigma: f64,
    pub elapsed_s: f64,
}

/// Every job status, and those of jobs that have ended.
pub const STATUSES: [&str; 5] = ["queued", "running", "succeeded", "failed", "cancelled"];
pub const TERMINAL: [&str; 3] = ["succeeded", "failed", "cancelled"];

const JOB_COLUMNS: &str = "id, status, request, created_at, updated_at, progress, error";

/// Now, as fixed-width RFC 3339 UTC (sorts as text).
pub fn now() -> String {
    after(Duration::ZERO)
}

/// `delay` from now, as [`now`] writes times (a lease's end).
pub fn after(delay: Duration) -> String {
    let format = time::macros::format_description!(
        "[year]-[month]-[day]T[hour]:[minute]:[second].[subsecond digits:6]Z"
    );
    (time::OffsetDateTime::now_utc() + delay)
        .format(&format)
        .unwrap_or_default()
}

/// A worker's hold on a running job: the job and the claim's attempt number.
/// Every write of the worker names it, and is dropped when the job has been
/// claimed again since (the lease ran out) or has ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Lease {
    pub id: String,
    pub attempt: i64,
}

/// A claimed job: the job, its last checkpoint, and the lease.
#[derive(Debug, Clone)]
pub struct Claim {
    pub job: JobRow,
    pub checkpoint: Option<String>,
    pub lease: Lease,
    /// The job was running under a lease that had run out (its node died).
    pub taken_over: bool,
}

/// What renewing a lease found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Renewal {
    /// Renewed: the job is still this worker's.
    Held,
    /// The job was cancelled (on any node): stop.
    Cancelled,
    /// Another worker claimed the job, or it ended: stop writing.
    Lost,
}

/// A claim from the row `claim_next` returns (the job's columns,
/// `checkpoint` and `attempt`).
fn claim_of<R: sqlx::Row>(row: &R) -> Result<Claim, sqlx::Error>
where
    JobRow: for<'r> FromRow<'r, R>,
    for<'c> &'c str: sqlx::ColumnIndex<R>,
    Option<String>: for<'r> sqlx::Decode<'r, R::Database> + sqlx::Type<R::Database>,
    i64: for<'r> sqlx::Decode<'r, R::Database> + sqlx::Type<R::Database>,
    bool: for<'r> sqlx::Decode<'r, R::Database> + sqlx::Type<R::Database>,
{
    let job = JobRow::from_row(row)?;
    let lease = Lease {
        id: job.id.clone(),
        attempt: row.try_get("attempt")?,
    };
    Ok(Claim {
        checkpoint: row.try_get("checkpoint")?,
        taken_over: row.try_get("taken_over")?,
        job,
        lease,
    })
}

/// What a failed renewal means, from the job's status and attempt now.
fn renewal_of(now: Option<(String, i64)>, lease: &Lease) -> Renewal {
    match now {
        Some((status, attempt)) if status == "cancelled" && attempt == lease.attempt => {
            Renewal::Cancelled
        }
        _ => Renewal::Lost,
    }
}

/// Whether `error` says the database could not be reached or is going away
/// (a restart, a network failure, an exhausted pool) rather than that a
/// statement was wrong: worth trying again once it answers. PostgreSQL's
/// SQLSTATE classes 08 (connection exception) and 57P (operator
/// intervention: shutdown, starting up) count.
pub fn unavailable(error: &sqlx::Error) -> bool {
    match error {
        sqlx::Error::Io(_)
        | sqlx::Error::Tls(_)
        | sqlx::Error::PoolTimedOut
        | sqlx::Error::PoolClosed
        | sqlx::Error::WorkerCrashed => true,
        sqlx::Error::Database(e) => e
            .code()
            .is_some_and(|code| code.starts_with("08") || code.starts_with("57P")),
        _ => false,
    }
}

/// The same call on whichever backend this store is.
macro_rules! on_backend {
    ($store:expr, $backend:ident => $call:expr) => {
        match $store {
            Store::Sqlite($backend) => $call,
            Store::Postgres($backend) => $call,
        }
    };
}

impl Store {
    pub async fn open(database: &Database) -> Result<Store, sqlx::Error> {
        Ok(match database {
            Database::Sqlite(path) => Store::Sqlite(SqliteStore::open(path).await?),
            Database::Postgres(url) => Store::Postgres(PgStore::open(url).await?),
        })
    }

    /// The PostgreSQL pool, for LISTEN (none on SQLite: one node).
    pub fn postgres(&self) -> Option<&sqlx::PgPool> {
        match self {
            Store::Sqlite(_) => None,
            Store::Postgres(s) => Some(s.pool()),
        }
    }

    pub async fn ping(&self) -> bool {
        on_backend!(self, s => s.ping().await)
    }

    /// Inserts a queued job with its first event, at once (a worker never
    /// sees the job without it); `None` when the owner already used
    /// `idempotency_key`.
    pub async fn insert_job(
        &self,
        id: &str,
        owner: &str,
        request: &str,
        idempotency_key: Option<&str>,
        event: (&str, &str),
    ) -> Result<Option<(JobRow, StoredEvent)>, sqlx::Error> {
        on_backend!(self, s => s.insert_job(id, owner, request, idempotency_key, event).await)
    }

    pub async fn job_by_idempotency_key(
        &self,
        owner: &str,
        key: &str,
    ) -> Result<Option<JobRow>, sqlx::Error> {
        on_backend!(self, s => s.job_by_idempotency_key(owner, key).await)
    }

    /// The job if it exists and belongs to `owner` (`None` sees every job).
    pub async fn job(&self, id: &str, owner: Option<&str>) -> Result<Option<JobRow>, sqlx::Error> {
        on_backend!(self, s => s.job(id, owner).await)
    }

    /// Newest first; `before` is the id of the last job of the previous page.
    pub async fn list_jobs(
        &self,
        owner: Option<&str>,
        status: Option<&str>,
        before: Option<&str>,
        limit: i64,
    ) -> Result<Vec<JobRow>, sqlx::Error> {
        on_backend!(self, s => s.list_jobs(owner, status, before, limit).await)
    }

    pub async fn count_by_status(&self) -> Result<Vec<(String, i64)>, sqlx::Error> {
        on_backend!(self, s => s.count_by_status().await)
    }

    pub async fn queued_count(&self) -> Result<i64, sqlx::Error> {
        on_backend!(self, s => s.queued_count().await)
    }

    /// Takes the oldest job that is queued, or running with a lease that ran
    /// out (its node died), marks it running under a new lease of
    /// `duration` held by `node`, and counts the attempt.
    pub async fn claim_next(
        &self,
        node: &str,
        duration: Duration,
    ) -> Result<Option<Claim>, sqlx::Error> {
        on_backend!(self, s => s.claim_next(node, duration).await)
    }

    /// Extends the lease by `duration` if the job is still this lease's.
    pub async fn renew(&self, lease: &Lease, duration: Duration) -> Result<Renewal, sqlx::Error> {
        on_backend!(self, s => s.renew(lease, duration).await)
    }

    /// At start-up of the one node of a SQLite file: jobs left running (the
    /// process was killed) are queued again at once, to resume from their
    /// checkpoints. PostgreSQL's nodes wait for such leases to run out
    /// instead (another node may hold them). Returns how many.
    pub async fn requeue_orphans(&self) -> Result<u64, sqlx::Error> {
        match self {
            Store::Sqlite(s) => s.requeue_running().await,
            Store::Postgres(_) => Ok(0),
        }
    }

    /// Puts a running job back in the queue (shutdown); its checkpoint stays.
    pub async fn requeue(&self, lease: &Lease) -> Result<(), sqlx::Error> {
        on_backend!(self, s => s.requeue(lease).await)
    }

    /// Ends a job that has not ended — `failed` or `cancelled` — and stores its
    /// final event in the same transaction, so an ended job always has its
    /// final event. `None` when the job had already ended, or `fence` (a
    /// worker's attempt) is no longer the job's.
    pub async fn end(
        &self,
        id: &str,
        status: &str,
        error: Option<&str>,
        event: (&str, &str),
        fence: Option<i64>,
    ) -> Result<Option<StoredEvent>, sqlx::Error> {
        on_backend!(self, s => s.end(id, status, error, event, fence).await)
    }

    /// Appends an event with the job's next id; with `fence` (a worker's
    /// attempt) only while the job is running under that attempt.
    pub async fn append_event(
        &self,
        id: &str,
        kind: &str,
        data: &str,
        fence: Option<i64>,
    ) -> Result<Option<StoredEvent>, sqlx::Error> {
        on_backend!(self, s => s.append_event(id, kind, data, fence).await)
    }

    pub async fn events_after(
        &self,
        id: &str,
        after: i64,
    ) -> Result<Vec<StoredEvent>, sqlx::Error> {
        on_backend!(self, s => s.events_after(id, after).await)
    }

    /// The latest progress, and the generation's row when it is one.
    pub async fn record_progress(
        &self,
        lease: &Lease,
        progress: &str,
        iteration: Option<&Iteration>,
    ) -> Result<(), sqlx::Error> {
        on_backend!(self, s => s.record_progress(lease, progress, iteration).await)
    }

    /// Keeps `checkpoint`, taken after `evaluations`, unless the job holds a
    /// later one: a checkpoint never goes back.
    pub async fn save_checkpoint(
        &self,
        lease: &Lease,
        checkpoint: &str,
        evaluations: i64,
    ) -> Result<(), sqlx::Error> {
        on_backend!(self, s => s.save_checkpoint(lease, checkpoint, evaluations).await)
    }

    /// Stores the result, its files and the `done` event and marks the job
    /// succeeded, all at once. `None` (nothing stored) when the job had
    /// already ended (cancelled).
    pub async fn finish(
        &self,
        lease: &Lease,
        result: &str,
        files: &[OutputFile],
        done: &str,
    ) -> Result<Option<StoredEvent>, sqlx::Error> {
        on_backend!(self, s => s.finish(lease, result, files, done).await)
    }

    pub async fn iterations(
        &self,
        id: &str,
        after: i64,
        limit: i64,
    ) -> Result<Vec<Iteration>, sqlx::Error> {
        on_backend!(self, s => s.iterations(id, after, limit).await)
    }

    pub async fn result(&self, id: &str) -> Result<Option<String>, sqlx::Error> {
        on_backend!(self, s => s.result(id).await)
    }

    pub async fn file(
        &self,
        id: &str,
        name: &str,
    ) -> Result<Option<(String, Vec<u8>)>, sqlx::Error> {
        on_backend!(self, s => s.file(id, name).await)
    }

    pub async fn delete(&self, id: &str) -> Result<(), sqlx::Error> {
        on_backend!(self, s => s.delete(id).await)
    }

    /// Every job's id, oldest first.
    pub async fn job_ids(&self) -> Result<Vec<String>, sqlx::Error> {
        on_backend!(self, s => s.job_ids().await)
    }

    /// The job with its events, iterations and files.
    pub async fn export_job(&self, id: &str) -> Result<Option<JobExport>, sqlx::Error> {
        on_backend!(self, s => s.export_job(id).await)
    }

    /// Stores an exported job (a running one as queued, to resume from its
    /// checkpoint); `false`, writing nothing, when the job is already here.
    pub async fn import_job(&self, job: &JobExport) -> Result<bool, sqlx::Error> {
        on_backend!(self, s => s.import_job(job).await)
    }
}

#[cfg(test)]
mod tests {
    use super::Database;

    #[test]
    fn a_database_is_a_file_or_a_postgres_url_shown_without_its_password() {
        assert!(matches!(
            Database::parse("./patchwork.db"),
            Database::Sqlite(_)
        ));
        let url = "postgres://lab:s3cret@db.example:5432/patchwork";
        let database = Database::parse(url);
        assert!(matches!(database, Database::Postgres(ref u) if u == url));
        assert_eq!(
            database.to_string(),
            "postgres://lab@db.example:5432/patchwork"
        );
        let bare = Database::parse("postgresql://db.example/patchwork");
        assert_eq!(bare.to_string(), "postgresql://db.example/patchwork");
    }
}
