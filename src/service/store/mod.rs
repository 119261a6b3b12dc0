//! The job store: every event, iteration, checkpoint and result file of a
//! job, so nothing is lost on restart. Two backends behind one interface:
//! SQLite (`sqlite.rs`, a file; the default) and PostgreSQL (`postgres.rs`,
//! a server that several nodes can share), each migrated at start from its
//! own `migrations/` folder. The SQL is each backend's own; the semantics
//! (and the service tests, run against both) are the same.

mod postgres;
mod sqlite;

use std::fmt;
use std::path::PathBuf;

use patchwork_core::fabrication::OutputFile;
use serde::Serialize;
use sqlx::FromRow;

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
    let format = time::macros::format_description!(
        "[year]-[month]-[day]T[hour]:[minute]:[second].[subsecond digits:6]Z"
    );
    time::OffsetDateTime::now_utc()
        .format(&format)
        .unwrap_or_default()
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

    pub async fn ping(&self) -> bool {
        on_backend!(self, s => s.ping().await)
    }

    /// Inserts a queued job; `None` when the owner already used `idempotency_key`.
    pub async fn insert_job(
        &self,
        id: &str,
        owner: &str,
        request: &str,
        idempotency_key: Option<&str>,
    ) -> Result<Option<JobRow>, sqlx::Error> {
        on_backend!(self, s => s.insert_job(id, owner, request, idempotency_key).await)
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

    /// Takes the oldest queued job and marks it running.
    pub async fn claim_next(&self) -> Result<Option<(JobRow, Option<String>)>, sqlx::Error> {
        on_backend!(self, s => s.claim_next().await)
    }

    /// After a crash: jobs that were running are queued again (they resume
    /// from their checkpoints). Returns how many.
    pub async fn requeue_running(&self) -> Result<u64, sqlx::Error> {
        on_backend!(self, s => s.requeue_running().await)
    }

    /// Puts a running job back in the queue (shutdown); its checkpoint stays.
    pub async fn requeue(&self, id: &str) -> Result<(), sqlx::Error> {
        on_backend!(self, s => s.requeue(id).await)
    }

    /// Ends a job that has not ended — `failed` or `cancelled` — and stores its
    /// final event in the same transaction, so an ended job always has its
    /// final event. `None` when the job had already ended.
    pub async fn end(
        &self,
        id: &str,
        status: &str,
        error: Option<&str>,
        event: (&str, &str),
    ) -> Result<Option<StoredEvent>, sqlx::Error> {
        on_backend!(self, s => s.end(id, status, error, event).await)
    }

    /// Appends an event with the job's next id.
    pub async fn append_event(
        &self,
        id: &str,
        kind: &str,
        data: &str,
    ) -> Result<StoredEvent, sqlx::Error> {
        on_backend!(self, s => s.append_event(id, kind, data).await)
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
        id: &str,
        progress: &str,
        iteration: Option<&Iteration>,
    ) -> Result<(), sqlx::Error> {
        on_backend!(self, s => s.record_progress(id, progress, iteration).await)
    }

    pub async fn save_checkpoint(&self, id: &str, checkpoint: &str) -> Result<(), sqlx::Error> {
        on_backend!(self, s => s.save_checkpoint(id, checkpoint).await)
    }

    /// Stores the result, its files and the `done` event and marks the job
    /// succeeded, all at once. `None` (nothing stored) when the job had
    /// already ended (cancelled).
    pub async fn finish(
        &self,
        id: &str,
        result: &str,
        files: &[OutputFile],
        done: &str,
    ) -> Result<Option<StoredEvent>, sqlx::Error> {
        on_backend!(self, s => s.finish(id, result, files, done).await)
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
