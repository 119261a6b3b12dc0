//! The job store: every event, iteration, checkpoint and result file of a
//! job, so nothing is lost on restart. Two backends behind one contract
//! ([`JobStore`], `contract.rs`): SQLite (`sqlite.rs`, a file; the default)
//! and PostgreSQL (`postgres.rs`, a server that several nodes can share),
//! each migrated at start from its own `migrations/` folder. Most statements
//! are written once for both (`statements.rs`, `transfer.rs`); each backend
//! adds how it opens and its `Dialect`. Both pass the same conformance suite
//! (`conformance.rs`); the service tests run against SQLite, and those of
//! several nodes, outages, recovery and a job's run end to end against
//! PostgreSQL as well.

#[cfg(test)]
mod conformance;
mod contract;
mod export;
mod postgres;
#[cfg(test)]
mod profile_conformance;
mod profiles;
mod sqlite;
mod statements;
mod transfer;

use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use serde::Serialize;
use sqlx::FromRow;

use super::job_state::{EventKind, JobStatus};

pub use contract::JobStore;
#[cfg(test)]
pub use export::{ExportRow, JobExport};

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

    /// Opens (creating a SQLite file where there is none) and migrates it.
    pub async fn open(&self) -> Result<Store, sqlx::Error> {
        Ok(match self {
            Database::Sqlite(path) => Arc::new(SqliteStore::open(path).await?),
            Database::Postgres(url) => Arc::new(PgStore::open(url).await?),
        })
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

/// The store the service uses, whichever its backend.
pub type Store = Arc<dyn JobStore>;

/// A job as stored (without its checkpoint and result).
#[derive(Debug, Clone, FromRow)]
pub struct JobRow {
    pub id: String,
    /// The API key's digest that submitted it ('' when keys are off).
    pub owner: String,
    #[sqlx(try_from = "String")]
    pub status: JobStatus,
    /// The request as the client sent it.
    pub request: String,
    /// The job as the worker runs it (`spec.rs`); `None` for a job stored
    /// before specs, until the next start derives it.
    pub spec: Option<String>,
    pub created_at: String,
    pub updated_at: String,
    pub progress: Option<String>,
    pub error: Option<String>,
}

/// A balloon profile as stored.
#[derive(Debug, Clone, FromRow)]
pub struct ProfileRow {
    /// The API key's digest it belongs to ('' when keys are off).
    pub owner: String,
    pub name: String,
    /// `{"balloon": …, "patch": …}`, as JSON.
    pub profile: String,
    pub source_job: Option<String>,
    pub created_at: String,
    pub updated_at: String,
}

/// One server-sent event of a job.
#[derive(Debug, Clone, FromRow)]
pub struct StoredEvent {
    pub seq: i64,
    #[sqlx(try_from = "String")]
    pub kind: EventKind,
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

const JOB_COLUMNS: &str =
    "id, owner, status, request, spec, created_at, updated_at, progress, error";

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
        Some((status, attempt))
            if status.parse() == Ok(JobStatus::Cancelled) && attempt == lease.attempt =>
        {
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
