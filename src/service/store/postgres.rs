//! The PostgreSQL backend, migrated at start by sqlx from
//! `migrations/postgres/`. Several nodes share it: a worker claims the oldest
//! claimable job with `FOR UPDATE SKIP LOCKED`, and a job's event ids come
//! from a counter on its row, so concurrent writers (a worker, a cancel on
//! another node) never take the same id.

use std::time::Duration;

use sqlx::postgres::{PgConnectOptions, PgConnection, PgPool, PgPoolOptions};
use sqlx::{ConnectOptions, Connection};

use super::contract::Dialect;
use super::profiles::profile_store;
use super::statements::job_store;
use super::transfer::job_transfer;
use super::{StoredEvent, now};
use crate::service::job_state::EventKind;

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
}

job_store!(PgStore {
    /// Jobs left running by a node that died are claimed again once their
    /// leases run out (another node may still hold them): none at once.
    async fn requeue_orphans(&self) -> Result<u64, sqlx::Error> {
        Ok(0)
    }

    fn postgres(&self) -> Option<&PgPool> {
        Some(&self.pool)
    }
});

job_transfer!(PgStore);
profile_store!(PgStore);

impl Dialect for PgStore {
    type Connection = PgConnection;

    /// Concurrent claims of several nodes pass over each other's rows.
    const CLAIM_LOCK: &'static str = "FOR UPDATE SKIP LOCKED";

    /// The job's event counter continues after its last imported event.
    const IMPORT_SEQ: &'static str = "UPDATE jobs SET last_seq = (SELECT COALESCE(MAX(seq), 0)
                                      FROM events WHERE job_id = $1) WHERE id = $1";

    /// The job's next id from the counter on its row (whose row lock orders
    /// concurrent writers).
    fn insert_event<'c>(
        connection: &'c mut PgConnection,
        id: &'c str,
        (kind, data): (EventKind, &'c str),
        fence: Option<i64>,
    ) -> impl Future<Output = Result<Option<StoredEvent>, sqlx::Error>> + Send + 'c {
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
        .bind(kind.as_str())
        .bind(data)
        .bind(now())
        .bind(fence)
        .fetch_optional(connection)
    }
}
