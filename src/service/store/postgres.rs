//! The PostgreSQL backend, migrated at start by sqlx from
//! `migrations/postgres/`. Several nodes share it: a worker claims the oldest
//! claimable job with `FOR UPDATE SKIP LOCKED`, and a job's event ids come
//! from a counter on its row, so concurrent writers (a worker, a cancel on
//! another node) never take the same id.

use std::time::Duration;

use super::statements::shared_statements;
use super::transfer::{self, transfer_statements};
use super::{
    Claim, Iteration, JOB_COLUMNS, JobRow, Lease, Renewal, StoredEvent, after, claim_of, now,
    renewal_of,
};
use patchwork_core::fabrication::OutputFile;
use sqlx::postgres::{PgConnectOptions, PgConnection, PgPool, PgPoolOptions};
use sqlx::{ConnectOptions, Connection};

#[derive(Clone)]
pub struct PgStore {
    pool: PgPool,
}

impl PgStore {
    pub(super) async fn open(url: &str) -> Result<PgStore, sqlx::Error> {
        let options: PgConnectOptions = url.parse()?;
        // One connection first, so that a server that cannot be reached or
        // refuses the login says why (the pool would only time out).
        let first = tokio::time::timeout(Duration::from_secs(5), options.connect()).await;
        match first {
            Ok(connection) => connection?.close().await?,
            Err(_) => return Err(sqlx::Error::PoolTimedOut),
        }
        let pool = PgPoolOptions::new()
            .max_connections(8)
            .acquire_timeout(Duration::from_secs(5))
            .connect_with(options)
            .await?;
        sqlx::migrate!("./migrations/postgres").run(&pool).await?;
        Ok(PgStore { pool })
    }

    pub(super) fn pool(&self) -> &PgPool {
        &self.pool
    }

    shared_statements!();
    transfer_statements!();
}

/// Concurrent claims of several nodes pass over each other's rows.
const CLAIM_LOCK: &str = "FOR UPDATE SKIP LOCKED";

/// The job's event counter continues after its last imported event.
const IMPORT_SEQ: &str = "UPDATE jobs SET last_seq = (SELECT COALESCE(MAX(seq), 0) FROM events
                          WHERE job_id = $1) WHERE id = $1";

/// Inserts an event with the job's next id, taken from the counter on the
/// job's row (whose row lock orders concurrent writers) in the caller's
/// transaction; with `fence`, only while the job runs under that attempt.
async fn insert_event(
    connection: &mut PgConnection,
    id: &str,
    (kind, data): (&str, &str),
    fence: Option<i64>,
) -> Result<Option<StoredEvent>, sqlx::Error> {
    sqlx::query_as(
        "WITH next AS (
             UPDATE jobs SET last_seq = last_seq + 1
             WHERE id = $1 AND ($5::bigint IS NULL OR (attempt = $5 AND status = 'running'))
             RETURNING last_seq)
         INSERT INTO events (job_id, seq, kind, data, created_at)
         SELECT $1, last_seq, $2, $3, $4 FROM next
         RETURNING seq, kind, data",
    )
    .bind(id)
    .bind(kind)
    .bind(data)
    .bind(now())
    .bind(fence)
    .fetch_optional(connection)
    .await
}
