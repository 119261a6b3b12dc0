//! Whole jobs out of one store and into another (`patchwork copy-jobs`):
//! the job's row, every event, iteration and result file, in one
//! transaction per job on the receiving side. The statements read alike on
//! both backends, like `statements.rs`; the receiving backend's
//! [`Dialect`](super::contract::Dialect) says how it restores a job's event
//! counter (`IMPORT_SEQ`).

/// `job_transfer!(Backend)`: `impl JobTransfer for Backend` over the
/// backend's `pool` (see the module doc). The backend must implement
/// `Dialect`.
macro_rules! job_transfer {
    ($store:ty) => {
        // A block, so that the names the statements use are imported here.
        const _: () = {
        use $crate::service::job_state::JobStatus;
        use $crate::service::store::contract::{Dialect, JobStore, JobTransfer};
        use $crate::service::store::export::{ExportRow, JobExport};

        #[async_trait::async_trait]
        impl JobTransfer for $store {
        /// Every job's id, oldest first.
        async fn job_ids(&self) -> Result<Vec<String>, sqlx::Error> {
            sqlx::query_scalar("SELECT id FROM jobs ORDER BY id")
                .fetch_all(&self.pool)
                .await
        }

        async fn export_job(
            &self,
            id: &str,
        ) -> Result<Option<JobExport>, sqlx::Error> {
            let row: Option<ExportRow> = sqlx::query_as(
                "SELECT id, owner, status, request, spec, idempotency_key, created_at, updated_at,
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
            Ok(Some(JobExport {
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
        async fn import_job(&self, job: &JobExport) -> Result<bool, sqlx::Error> {
            let mut tx = self.pool.begin().await?;
            if !insert_row(&mut *tx, &job.row).await? {
                return Ok(false);
            }
            insert_products(&mut *tx, job).await?;
            let import_seq = <$store as Dialect>::IMPORT_SEQ;
            if !import_seq.is_empty() {
                sqlx::query(import_seq)
                    .bind(&job.row.id)
                    .execute(&mut *tx)
                    .await?;
            }
            tx.commit().await?;
            Ok(true)
        }
        }

        /// The job's row (running → queued, without a lease); false when the
        /// store already has it.
        async fn insert_row(
            connection: &mut <$store as Dialect>::Connection,
            r: &ExportRow,
        ) -> Result<bool, sqlx::Error> {
            let status = match r.status {
                JobStatus::Running => JobStatus::Queued,
                other => other,
            };
            let inserted = sqlx::query(
                "INSERT INTO jobs (id, owner, status, request, spec, idempotency_key, created_at,
                                   updated_at, progress, error, checkpoint, result, attempt,
                                   checkpoint_evaluations)
                 VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13, $14)
                 ON CONFLICT DO NOTHING",
            )
            .bind(&r.id)
            .bind(&r.owner)
            .bind(status.as_str())
            .bind(&r.request)
            .bind(&r.spec)
            .bind(&r.idempotency_key)
            .bind(&r.created_at)
            .bind(&r.updated_at)
            .bind(&r.progress)
            .bind(&r.error)
            .bind(&r.checkpoint)
            .bind(&r.result)
            .bind(r.attempt)
            .bind(r.checkpoint_evaluations)
            .execute(&mut *connection)
            .await?;
            Ok(inserted.rows_affected() == 1)
        }

        /// The job's events, iterations and files, as they were.
        async fn insert_products(
            connection: &mut <$store as Dialect>::Connection,
            job: &JobExport,
        ) -> Result<(), sqlx::Error> {
            let id = &job.row.id;
            for e in &job.events {
                sqlx::query(
                    "INSERT INTO events (job_id, seq, kind, data, created_at)
                     VALUES ($1, $2, $3, $4, $5)",
                )
                .bind(id)
                .bind(e.seq)
                .bind(e.kind.as_str())
                .bind(&e.data)
                .bind(&e.created_at)
                .execute(&mut *connection)
                .await?;
            }
            for it in &job.iterations {
                sqlx::query(
                    "INSERT INTO iterations
                     (job_id, evaluations, generation, best_objective, sigma, elapsed_s)
                     VALUES ($1, $2, $3, $4, $5, $6)",
                )
                .bind(id)
                .bind(it.evaluations)
                .bind(it.generation)
                .bind(it.best_objective)
                .bind(it.sigma)
                .bind(it.elapsed_s)
                .execute(&mut *connection)
                .await?;
            }
            for f in &job.files {
                sqlx::query(
                    "INSERT INTO files (job_id, name, content_type, body) VALUES ($1, $2, $3, $4)",
                )
                .bind(id)
                .bind(&f.name)
                .bind(&f.content_type)
                .bind(&f.body)
                .execute(&mut *connection)
                .await?;
            }
            Ok(())
        }
        };
    };
}

pub(super) use job_transfer;
