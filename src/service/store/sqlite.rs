//! The SQLite backend: one file (WAL, busy timeout, foreign keys), migrated
//! at start by sqlx from `migrations/sqlite/`. The default; one node.

use std::path::Path;
use std::time::Duration;

use patchwork_core::fabrication::OutputFile;
use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{SqliteConnection, SqlitePool};

use super::{
    Claim, Iteration, JOB_COLUMNS, JobRow, Lease, Renewal, StoredEvent, after, claim_of, now,
    renewal_of,
};

#[derive(Clone)]
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

    pub(super) async fn ping(&self) -> bool {
        sqlx::query("SELECT 1").execute(&self.pool).await.is_ok()
    }

    /// Inserts a queued job; `None` when the owner already used `idempotency_key`.
    pub(super) async fn insert_job(
        &self,
        id: &str,
        owner: &str,
        request: &str,
        idempotency_key: Option<&str>,
    ) -> Result<Option<JobRow>, sqlx::Error> {
        let at = now();
        let sql = format!(
            "INSERT INTO jobs (id, owner, status, request, idempotency_key, created_at, updated_at)
             VALUES (?, ?, 'queued', ?, ?, ?, ?)
             ON CONFLICT DO NOTHING RETURNING {JOB_COLUMNS}"
        );
        sqlx::query_as::<_, JobRow>(&sql)
            .bind(id)
            .bind(owner)
            .bind(request)
            .bind(idempotency_key)
            .bind(&at)
            .bind(&at)
            .fetch_optional(&self.pool)
            .await
    }

    pub(super) async fn job_by_idempotency_key(
        &self,
        owner: &str,
        key: &str,
    ) -> Result<Option<JobRow>, sqlx::Error> {
        let sql = format!("SELECT {JOB_COLUMNS} FROM jobs WHERE owner = ? AND idempotency_key = ?");
        sqlx::query_as(&sql)
            .bind(owner)
            .bind(key)
            .fetch_optional(&self.pool)
            .await
    }

    /// The job if it exists and belongs to `owner` (`None` sees every job).
    pub(super) async fn job(
        &self,
        id: &str,
        owner: Option<&str>,
    ) -> Result<Option<JobRow>, sqlx::Error> {
        let sql =
            format!("SELECT {JOB_COLUMNS} FROM jobs WHERE id = ? AND (? IS NULL OR owner = ?)");
        sqlx::query_as(&sql)
            .bind(id)
            .bind(owner)
            .bind(owner)
            .fetch_optional(&self.pool)
            .await
    }

    /// Newest first; `before` is the id of the last job of the previous page.
    pub(super) async fn list_jobs(
        &self,
        owner: Option<&str>,
        status: Option<&str>,
        before: Option<&str>,
        limit: i64,
    ) -> Result<Vec<JobRow>, sqlx::Error> {
        let sql = format!(
            "SELECT {JOB_COLUMNS} FROM jobs
             WHERE (?1 IS NULL OR owner = ?1) AND (?2 IS NULL OR status = ?2)
               AND (?3 IS NULL OR id < ?3)
             ORDER BY id DESC LIMIT ?4"
        );
        sqlx::query_as(&sql)
            .bind(owner)
            .bind(status)
            .bind(before)
            .bind(limit)
            .fetch_all(&self.pool)
            .await
    }

    pub(super) async fn count_by_status(&self) -> Result<Vec<(String, i64)>, sqlx::Error> {
        sqlx::query_as("SELECT status, COUNT(*) FROM jobs GROUP BY status")
            .fetch_all(&self.pool)
            .await
    }

    pub(super) async fn queued_count(&self) -> Result<i64, sqlx::Error> {
        sqlx::query_scalar("SELECT COUNT(*) FROM jobs WHERE status = 'queued'")
            .fetch_one(&self.pool)
            .await
    }

    pub(super) async fn claim_next(
        &self,
        node: &str,
        duration: Duration,
    ) -> Result<Option<Claim>, sqlx::Error> {
        let sql = format!(
            "UPDATE jobs SET status = 'running', attempt = attempt + 1,
                    taken_over = (status = 'running'), lease_until = ?2,
                    node = ?3, updated_at = ?1
             WHERE id = (SELECT id FROM jobs
                         WHERE status = 'queued'
                            OR (status = 'running' AND (lease_until IS NULL OR lease_until < ?1))
                         ORDER BY id LIMIT 1)
             RETURNING {JOB_COLUMNS}, checkpoint, attempt, taken_over"
        );
        let row = sqlx::query(&sql)
            .bind(now())
            .bind(after(duration))
            .bind(node)
            .fetch_optional(&self.pool)
            .await?;
        row.map(|row| claim_of(&row)).transpose()
    }

    pub(super) async fn renew(
        &self,
        lease: &Lease,
        duration: Duration,
    ) -> Result<Renewal, sqlx::Error> {
        let renewed = sqlx::query(
            "UPDATE jobs SET lease_until = ? WHERE id = ? AND attempt = ? AND status = 'running'",
        )
        .bind(after(duration))
        .bind(&lease.id)
        .bind(lease.attempt)
        .execute(&self.pool)
        .await?;
        if renewed.rows_affected() == 1 {
            return Ok(Renewal::Held);
        }
        let now: Option<(String, i64)> =
            sqlx::query_as("SELECT status, attempt FROM jobs WHERE id = ?")
                .bind(&lease.id)
                .fetch_optional(&self.pool)
                .await?;
        Ok(renewal_of(now, lease))
    }

    /// After a crash: jobs that were running are queued again (they resume
    /// from their checkpoints). Returns how many.
    pub(super) async fn requeue_running(&self) -> Result<u64, sqlx::Error> {
        Ok(sqlx::query(
            "UPDATE jobs SET status = 'queued', updated_at = ? WHERE status = 'running'",
        )
        .bind(now())
        .execute(&self.pool)
        .await?
        .rows_affected())
    }

    /// Puts a running job back in the queue (shutdown); its checkpoint stays.
    pub(super) async fn requeue(&self, lease: &Lease) -> Result<(), sqlx::Error> {
        sqlx::query(
            "UPDATE jobs SET status = 'queued', lease_until = NULL, updated_at = ?
             WHERE id = ? AND attempt = ? AND status = 'running'",
        )
        .bind(now())
        .bind(&lease.id)
        .bind(lease.attempt)
        .execute(&self.pool)
        .await
        .map(|_| ())
    }

    /// Ends a job that has not ended — `failed` or `cancelled` — and stores its
    /// final event in the same transaction, so an ended job always has its
    /// final event. `None` when the job had already ended.
    pub(super) async fn end(
        &self,
        id: &str,
        status: &str,
        error: Option<&str>,
        event: (&str, &str),
        fence: Option<i64>,
    ) -> Result<Option<StoredEvent>, sqlx::Error> {
        let mut tx = self.pool.begin().await?;
        let updated = sqlx::query(
            "UPDATE jobs SET status = ?, error = ?, lease_until = NULL, updated_at = ?
             WHERE id = ? AND status NOT IN ('succeeded', 'failed', 'cancelled')
               AND (? IS NULL OR attempt = ?)",
        )
        .bind(status)
        .bind(error)
        .bind(now())
        .bind(id)
        .bind(fence)
        .bind(fence)
        .execute(&mut *tx)
        .await?;
        if updated.rows_affected() != 1 {
            return Ok(None);
        }
        let stored = insert_event(&mut tx, id, event, None).await?;
        tx.commit().await?;
        Ok(stored)
    }

    /// Appends an event with the job's next id.
    pub(super) async fn append_event(
        &self,
        id: &str,
        kind: &str,
        data: &str,
        fence: Option<i64>,
    ) -> Result<Option<StoredEvent>, sqlx::Error> {
        let mut connection = self.pool.acquire().await?;
        insert_event(&mut connection, id, (kind, data), fence).await
    }

    pub(super) async fn events_after(
        &self,
        id: &str,
        after: i64,
    ) -> Result<Vec<StoredEvent>, sqlx::Error> {
        sqlx::query_as(
            "SELECT seq, kind, data FROM events WHERE job_id = ? AND seq > ? ORDER BY seq",
        )
        .bind(id)
        .bind(after)
        .fetch_all(&self.pool)
        .await
    }

    /// The latest progress, and the generation's row when it is one.
    pub(super) async fn record_progress(
        &self,
        lease: &Lease,
        progress: &str,
        iteration: Option<&Iteration>,
    ) -> Result<(), sqlx::Error> {
        let mut tx = self.pool.begin().await?;
        let updated = sqlx::query(
            "UPDATE jobs SET progress = ?, updated_at = ?
             WHERE id = ? AND attempt = ? AND status = 'running'",
        )
        .bind(progress)
        .bind(now())
        .bind(&lease.id)
        .bind(lease.attempt)
        .execute(&mut *tx)
        .await?;
        let id = &lease.id;
        if let Some(it) = iteration.filter(|_| updated.rows_affected() == 1) {
            sqlx::query(
                "INSERT OR REPLACE INTO iterations
                 (job_id, evaluations, generation, best_objective, sigma, elapsed_s)
                 VALUES (?, ?, ?, ?, ?, ?)",
            )
            .bind(id)
            .bind(it.evaluations)
            .bind(it.generation)
            .bind(it.best_objective)
            .bind(it.sigma)
            .bind(it.elapsed_s)
            .execute(&mut *tx)
            .await?;
        }
        tx.commit().await
    }

    pub(super) async fn save_checkpoint(
        &self,
        lease: &Lease,
        checkpoint: &str,
        evaluations: i64,
    ) -> Result<(), sqlx::Error> {
        sqlx::query(
            "UPDATE jobs SET checkpoint = ?, checkpoint_evaluations = ?
             WHERE id = ? AND attempt = ? AND status = 'running'
               AND checkpoint_evaluations <= ?",
        )
        .bind(checkpoint)
        .bind(evaluations)
        .bind(&lease.id)
        .bind(lease.attempt)
        .bind(evaluations)
        .execute(&self.pool)
        .await
        .map(|_| ())
    }

    /// Stores the result, its files and the `done` event and marks the job
    /// succeeded, all at once. `None` (nothing stored) when the job had
    /// already ended (cancelled).
    pub(super) async fn finish(
        &self,
        lease: &Lease,
        result: &str,
        files: &[OutputFile],
        done: &str,
    ) -> Result<Option<StoredEvent>, sqlx::Error> {
        let id = &lease.id;
        let mut tx = self.pool.begin().await?;
        let updated = sqlx::query(
            "UPDATE jobs SET status = 'succeeded', result = ?, lease_until = NULL, updated_at = ?
             WHERE id = ? AND attempt = ? AND status = 'running'",
        )
        .bind(result)
        .bind(now())
        .bind(id)
        .bind(lease.attempt)
        .execute(&mut *tx)
        .await?;
        if updated.rows_affected() != 1 {
            return Ok(None);
        }
        for file in files {
            sqlx::query(
                "INSERT OR REPLACE INTO files (job_id, name, content_type, body) VALUES (?, ?, ?, ?)",
            )
            .bind(id)
            .bind(file.name)
            .bind(file.content_type)
            .bind(&file.body)
            .execute(&mut *tx)
            .await?;
        }
        let stored = insert_event(&mut tx, id, ("done", done), None).await?;
        tx.commit().await?;
        Ok(stored)
    }

    pub(super) async fn iterations(
        &self,
        id: &str,
        after: i64,
        limit: i64,
    ) -> Result<Vec<Iteration>, sqlx::Error> {
        sqlx::query_as(
            "SELECT evaluations, generation, best_objective, sigma, elapsed_s FROM iterations
             WHERE job_id = ? AND evaluations > ? ORDER BY evaluations LIMIT ?",
        )
        .bind(id)
        .bind(after)
        .bind(limit)
        .fetch_all(&self.pool)
        .await
    }

    pub(super) async fn result(&self, id: &str) -> Result<Option<String>, sqlx::Error> {
        sqlx::query_scalar("SELECT result FROM jobs WHERE id = ?")
            .bind(id)
            .fetch_optional(&self.pool)
            .await
            .map(Option::flatten)
    }

    pub(super) async fn file(
        &self,
        id: &str,
        name: &str,
    ) -> Result<Option<(String, Vec<u8>)>, sqlx::Error> {
        sqlx::query_as("SELECT content_type, body FROM files WHERE job_id = ? AND name = ?")
            .bind(id)
            .bind(name)
            .fetch_optional(&self.pool)
            .await
    }

    pub(super) async fn delete(&self, id: &str) -> Result<(), sqlx::Error> {
        sqlx::query("DELETE FROM jobs WHERE id = ?")
            .bind(id)
            .execute(&self.pool)
            .await
            .map(|_| ())
    }
}

/// Inserts an event with the job's next id (one statement, so two writers
/// never take the same id); with `fence`, only while the job runs under
/// that attempt.
async fn insert_event(
    connection: &mut SqliteConnection,
    id: &str,
    (kind, data): (&str, &str),
    fence: Option<i64>,
) -> Result<Option<StoredEvent>, sqlx::Error> {
    sqlx::query_as(
        "INSERT INTO events (job_id, seq, kind, data, created_at)
         SELECT ?1, next, ?2, ?3, ?4
         FROM (SELECT COALESCE(MAX(seq), 0) + 1 AS next FROM events WHERE job_id = ?1)
         WHERE ?5 IS NULL
            OR EXISTS (SELECT 1 FROM jobs WHERE id = ?1 AND attempt = ?5 AND status = 'running')
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
