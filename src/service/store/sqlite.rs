//! The SQLite backend: one file (WAL, busy timeout, foreign keys), migrated
//! at start by sqlx from `migrations/sqlite/`. The default; one node.

use std::path::Path;
use std::time::Duration;

use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{SqliteConnection, SqlitePool};

use super::contract::Dialect;
use super::profiles::profile_store;
use super::statements::job_store;
use super::transfer::job_transfer;
use super::{StoredEvent, now};
use crate::service::job_state::EventKind;

pub struct SqliteStore {
    pool: SqlitePool,
}

impl SqliteStore {
    pub(super) async fn open(path: &Path) -> Result<SqliteStore, sqlx::Error> {
        let options = SqliteConnectOptions::new()
            .filename(path)
            .create_if_missing(true)
            .journal_mode(SqliteJournalMode::Wal)
            .synchronous(SqliteSynchronous::Normal)
            .busy_timeout(Duration::from_secs(10))
            .foreign_keys(true);
        let pool = SqlitePoolOptions::new()
            .max_connections(8)
            .connect_with(options)
            .await?;
        sqlx::migrate!("./migrations/sqlite").run(&pool).await?;
        Ok(SqliteStore { pool })
    }
}

job_store!(SqliteStore {
    /// The one node of a SQLite file starts after a crash: jobs that were
    /// running are queued again (they resume from their checkpoints).
    async fn requeue_orphans(&self) -> Result<u64, sqlx::Error> {
        Ok(sqlx::query(
            "UPDATE jobs SET status = 'queued', updated_at = $1 WHERE status = 'running'",
        )
        .bind(now())
        .execute(&self.pool)
        .await?
        .rows_affected())
    }
});

job_transfer!(SqliteStore);
profile_store!(SqliteStore);

impl Dialect for SqliteStore {
    type Connection = SqliteConnection;

    /// One connection writes at a time: a claim's subquery needs no row lock.
    const CLAIM_LOCK: &'static str = "";

    /// SQLite numbers a job's events from the events themselves.
    const IMPORT_SEQ: &'static str = "";

    /// The job's next id from its events, in one statement, so two writers
    /// never take the same id.
    fn insert_event<'c>(
        connection: &'c mut SqliteConnection,
        id: &'c str,
        (kind, data): (EventKind, &'c str),
        fence: Option<i64>,
    ) -> impl Future<Output = Result<Option<StoredEvent>, sqlx::Error>> + Send + 'c {
        sqlx::query_as(
            "INSERT INTO events (job_id, seq, kind, data, created_at)
             SELECT ?1, next, ?2, ?3, ?4
             FROM (SELECT COALESCE(MAX(seq), 0) + 1 AS next FROM events WHERE job_id = ?1)
             WHERE ?5 IS NULL
                OR EXISTS (SELECT 1 FROM jobs WHERE id = ?1 AND attempt = ?5 AND status = 'running')
             RETURNING seq, kind, data",
        )
        .bind(id)
        .bind(kind.as_str())
        .bind(data)
        .bind(now())
        .bind(fence)
        .fetch_optional(connection)
    }
}
