//! The PostgreSQL backend, migrated at start by sqlx from
//! `migrations/postgres/`. The same statements as the SQLite backend in
//! PostgreSQL's dialect; a worker claims the oldest queued job with
//! `FOR UPDATE SKIP LOCKED`, and a job's event ids come from a counter on its
//! row, so concurrent writers (a worker, a cancel) never take the same id.

use std::time::Duration;

use super::{
    Claim, Iteration, JOB_COLUMNS, JobRow, Lease, Renewal, StoredEvent, after, claim_of, now,
    renewal_of,
};
use patchwork_core::fabrication::OutputFile;
use sqlx::postgres::{PgConnection, PgPool, PgPoolOptions};

#[derive(Clone)]
pub struct PgStore {
    pool: PgPool,
}

impl PgStore {
    pub(super) async fn open(url: &str) -> Result<PgStore, sqlx::Error> {
        let pool = PgPoolOptions::new()
            .max_connections(8)
            .acquire_timeout(Duration::from_secs(10))
            .connect(url)
            .await?;
        sqlx::migrate!("./migrations/postgres").run(&pool).await?;
        Ok(PgStore { pool })
    }

    pub(super) fn pool(&self) -> &PgPool {
        &self.pool
    }

    pub(super) async fn ping(&self) -> bool {
        sqlx::query("SELECT 1").execute(&self.pool).await.is_ok()
    }

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
             VALUES ($1, $2, 'queued', $3, $4, $5, $5)
             ON CONFLICT DO NOTHING RETURNING {JOB_COLUMNS}"
        );
        sqlx::query_as::<_, JobRow>(&sql)
            .bind(id)
            .bind(owner)
            .bind(request)
            .bind(idempotency_key)
            .bind(&at)
            .fetch_optional(&self.pool)
            .await
    }

    pub(super) async fn job_by_idempotency_key(
        &self,
        owner: &str,
        key: &str,
    ) -> Result<Option<JobRow>, sqlx::Error> {
        let sql =
            format!("SELECT {JOB_COLUMNS} FROM jobs WHERE owner = $1 AND idempotency_key = $2");
        sqlx::query_as(&sql)
            .bind(owner)
            .bind(key)
            .fetch_optional(&self.pool)
            .await
    }

    pub(super) async fn job(
        &self,
        id: &str,
        owner: Option<&str>,
    ) -> Result<Option<JobRow>, sqlx::Error> {
        let sql = format!(
            "SELECT {JOB_COLUMNS} FROM jobs WHERE id = $1 AND ($2::text IS NULL OR owner = $2)"
        );
        sqlx::query_as(&sql)
            .bind(id)
            .bind(owner)
            .fetch_optional(&self.pool)
            .await
    }

    pub(super) async fn list_jobs(
        &self,
        owner: Option<&str>,
        status: Option<&str>,
        before: Option<&str>,
        limit: i64,
    ) -> Result<Vec<JobRow>, sqlx::Error> {
        let sql = format!(
            "SELECT {JOB_COLUMNS} FROM jobs
             WHERE ($1::text IS NULL OR owner = $1) AND ($2::text IS NULL OR status = $2)
               AND ($3::text IS NULL OR id < $3)
             ORDER BY id DESC LIMIT $4"
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
                    taken_over = (status = 'running'), lease_until = $2,
                    node = $3, updated_at = $1
             WHERE id = (SELECT id FROM jobs
                         WHERE status = 'queued'
                            OR (status = 'running' AND (lease_until IS NULL OR lease_until < $1))
                         ORDER BY id LIMIT 1 FOR UPDATE SKIP LOCKED)
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
            "UPDATE jobs SET lease_until = $1
             WHERE id = $2 AND attempt = $3 AND status = 'running'",
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
            sqlx::query_as("SELECT status, attempt FROM jobs WHERE id = $1")
                .bind(&lease.id)
                .fetch_optional(&self.pool)
                .await?;
        Ok(renewal_of(now, lease))
    }

    pub(super) async fn requeue(&self, lease: &Lease) -> Result<(), sqlx::Error> {
        sqlx::query(
            "UPDATE jobs SET status = 'queued', lease_until = NULL, updated_at = $1
             WHERE id = $2 AND attempt = $3 AND status = 'running'",
        )
        .bind(now())
        .bind(&lease.id)
        .bind(lease.attempt)
        .execute(&self.pool)
        .await
        .map(|_| ())
    }

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
            "UPDATE jobs SET status = $1, error = $2, lease_until = NULL, updated_at = $3
             WHERE id = $4 AND status NOT IN ('succeeded', 'failed', 'cancelled')
               AND ($5::bigint IS NULL OR attempt = $5)",
        )
        .bind(status)
        .bind(error)
        .bind(now())
        .bind(id)
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

    pub(super) async fn append_event(
        &self,
        id: &str,
        kind: &str,
        data: &str,
        fence: Option<i64>,
    ) -> Result<Option<StoredEvent>, sqlx::Error> {
        let mut tx = self.pool.begin().await?;
        let stored = insert_event(&mut tx, id, (kind, data), fence).await?;
        tx.commit().await?;
        Ok(stored)
    }

    pub(super) async fn events_after(
        &self,
        id: &str,
        after: i64,
    ) -> Result<Vec<StoredEvent>, sqlx::Error> {
        sqlx::query_as(
            "SELECT seq, kind, data FROM events WHERE job_id = $1 AND seq > $2 ORDER BY seq",
        )
        .bind(id)
        .bind(after)
        .fetch_all(&self.pool)
        .await
    }

    pub(super) async fn record_progress(
        &self,
        lease: &Lease,
        progress: &str,
        iteration: Option<&Iteration>,
    ) -> Result<(), sqlx::Error> {
        let mut tx = self.pool.begin().await?;
        let updated = sqlx::query(
            "UPDATE jobs SET progress = $1, updated_at = $2
             WHERE id = $3 AND attempt = $4 AND status = 'running'",
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
                "INSERT INTO iterations
                 (job_id, evaluations, generation, best_objective, sigma, elapsed_s)
                 VALUES ($1, $2, $3, $4, $5, $6)
                 ON CONFLICT (job_id, evaluations) DO UPDATE SET
                   generation = EXCLUDED.generation, best_objective = EXCLUDED.best_objective,
                   sigma = EXCLUDED.sigma, elapsed_s = EXCLUDED.elapsed_s",
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
            "UPDATE jobs SET checkpoint = $1, checkpoint_evaluations = $2
             WHERE id = $3 AND attempt = $4 AND status = 'running'
               AND checkpoint_evaluations <= $2",
        )
        .bind(checkpoint)
        .bind(evaluations)
        .bind(&lease.id)
        .bind(lease.attempt)
        .execute(&self.pool)
        .await
        .map(|_| ())
    }

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
            "UPDATE jobs SET status = 'succeeded', result = $1, lease_until = NULL, updated_at = $2
             WHERE id = $3 AND attempt = $4 AND status = 'running'",
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
                "INSERT INTO files (job_id, name, content_type, body) VALUES ($1, $2, $3, $4)
                 ON CONFLICT (job_id, name) DO UPDATE SET
                   content_type = EXCLUDED.content_type, body = EXCLUDED.body",
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
             WHERE job_id = $1 AND evaluations > $2 ORDER BY evaluations LIMIT $3",
        )
        .bind(id)
        .bind(after)
        .bind(limit)
        .fetch_all(&self.pool)
        .await
    }

    pub(super) async fn result(&self, id: &str) -> Result<Option<String>, sqlx::Error> {
        sqlx::query_scalar("SELECT result FROM jobs WHERE id = $1")
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
        sqlx::query_as("SELECT content_type, body FROM files WHERE job_id = $1 AND name = $2")
            .bind(id)
            .bind(name)
            .fetch_optional(&self.pool)
            .await
    }

    pub(super) async fn delete(&self, id: &str) -> Result<(), sqlx::Error> {
        sqlx::query("DELETE FROM jobs WHERE id = $1")
            .bind(id)
            .execute(&self.pool)
            .await
            .map(|_| ())
    }
}

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
