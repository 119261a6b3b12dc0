//! Whole jobs out of one store and into another (`patchwork copy-jobs`):
//! the job's row, every event, iteration and result file, in one
//! transaction per job on the receiving side. The statements read alike on
//! both backends, like `statements.rs`; the receiving backend adds how it
//! restores a job's event counter (`IMPORT_SEQ`).

use sqlx::FromRow;

/// A job with everything it produced, as stored.
#[derive(Debug, Clone)]
pub struct JobExport {
    pub row: ExportRow,
    pub events: Vec<ExportEvent>,
    pub iterations: Vec<super::Iteration>,
    pub files: Vec<ExportFile>,
}

/// The job's own columns that outlive a lease.
#[derive(Debug, Clone, FromRow)]
pub struct ExportRow {
    pub id: String,
    pub owner: String,
    pub status: String,
    pub request: String,
    pub idempotency_key: Option<String>,
    pub created_at: String,
    pub updated_at: String,
    pub progress: Option<String>,
    pub error: Option<String>,
    pub checkpoint: Option<String>,
    pub result: Option<String>,
    pub attempt: i64,
    pub checkpoint_evaluations: i64,
}

#[derive(Debug, Clone, FromRow)]
pub struct ExportEvent {
    pub seq: i64,
    pub kind: String,
    pub data: String,
    pub created_at: String,
}

#[derive(Debug, Clone, FromRow)]
pub struct ExportFile {
    pub name: String,
    pub content_type: String,
    pub body: Vec<u8>,
}

/// The export and import methods of both backends (see the module doc).
/// The invoking module provides `IMPORT_SEQ`.
macro_rules! transfer_statements {
    () => {
        /// Every job's id, oldest first.
        pub(super) async fn job_ids(&self) -> Result<Vec<String>, sqlx::Error> {
            sqlx::query_scalar("SELECT id FROM jobs ORDER BY id")
                .fetch_all(&self.pool)
                .await
        }

        pub(super) async fn export_job(
            &self,
            id: &str,
        ) -> Result<Option<transfer::JobExport>, sqlx::Error> {
            let row: Option<transfer::ExportRow> = sqlx::query_as(
                "SELECT id, owner, status, request, idempotency_key, created_at, updated_at,
                        progress, error, checkpoint, result, attempt, checkpoint_evaluations
                 FROM jobs WHERE id = $1",
            )
            .bind(id)
            .fetch_optional(&self.pool)
            .await?;
            let Some(row) = row else { return Ok(None) };
            let events = sqlx::query_as(
                "SELECT seq, kind, data, created_at FROM events WHERE job_id = $1 ORDER BY seq",
            )
            .bind(id)
            .fetch_all(&self.pool)
            .await?;
            let iterations = self.iterations(id, -1, i64::MAX).await?;
            let files = sqlx::query_as(
                "SELECT name, content_type, body FROM files WHERE job_id = $1 ORDER BY name",
            )
            .bind(id)
            .fetch_all(&self.pool)
            .await?;
            Ok(Some(transfer::JobExport {
                row,
                events,
                iterations,
                files,
            }))
        }

        /// Stores `job` as it was, except that a job that was running is
        /// queued (to resume from its checkpoint here) and holds no lease.
        /// `false` when this store already has the job (or its owner's
        /// idempotency key): nothing is written then.
        pub(super) async fn import_job(
            &self,
            job: &transfer::JobExport,
        ) -> Result<bool, sqlx::Error> {
            let r = &job.row;
            let status = if r.status == "running" {
                "queued"
            } else {
                r.status.as_str()
            };
            let mut tx = self.pool.begin().await?;
            let inserted = sqlx::query(
                "INSERT INTO jobs (id, owner, status, request, idempotency_key, created_at,
                                   updated_at, progress, error, checkpoint, result, attempt,
                                   checkpoint_evaluations)
                 VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13)
                 ON CONFLICT DO NOTHING",
            )
            .bind(&r.id)
            .bind(&r.owner)
            .bind(status)
            .bind(&r.request)
            .bind(&r.idempotency_key)
            .bind(&r.created_at)
            .bind(&r.updated_at)
            .bind(&r.progress)
            .bind(&r.error)
            .bind(&r.checkpoint)
            .bind(&r.result)
            .bind(r.attempt)
            .bind(r.checkpoint_evaluations)
            .execute(&mut *tx)
            .await?;
            if inserted.rows_affected() != 1 {
                return Ok(false);
            }
            for e in &job.events {
                sqlx::query(
                    "INSERT INTO events (job_id, seq, kind, data, created_at)
                     VALUES ($1, $2, $3, $4, $5)",
                )
                .bind(&r.id)
                .bind(e.seq)
                .bind(&e.kind)
                .bind(&e.data)
                .bind(&e.created_at)
                .execute(&mut *tx)
                .await?;
            }
            for it in &job.iterations {
                sqlx::query(
                    "INSERT INTO iterations
                     (job_id, evaluations, generation, best_objective, sigma, elapsed_s)
                     VALUES ($1, $2, $3, $4, $5, $6)",
                )
                .bind(&r.id)
                .bind(it.evaluations)
                .bind(it.generation)
                .bind(it.best_objective)
                .bind(it.sigma)
                .bind(it.elapsed_s)
                .execute(&mut *tx)
                .await?;
            }
            for f in &job.files {
                sqlx::query(
                    "INSERT INTO files (job_id, name, content_type, body) VALUES ($1, $2, $3, $4)",
                )
                .bind(&r.id)
                .bind(&f.name)
                .bind(&f.content_type)
                .bind(&f.body)
                .execute(&mut *tx)
                .await?;
            }
            if !IMPORT_SEQ.is_empty() {
                sqlx::query(IMPORT_SEQ)
                    .bind(&r.id)
                    .execute(&mut *tx)
                    .await?;
            }
            tx.commit().await?;
            Ok(true)
        }
    };
}

pub(super) use transfer_statements;
