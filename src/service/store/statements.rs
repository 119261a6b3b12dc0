//! The statements every backend runs, written once. Each is SQL that SQLite
//! and PostgreSQL read alike: numbered parameters (`$1`, reused where a value
//! appears twice), `CAST(… AS TEXT)` where PostgreSQL must know a parameter's
//! type, and `ON CONFLICT … DO UPDATE` for upserts. What only a backend can
//! say (how it numbers an event, how a claim locks its row) it says in its
//! [`Dialect`](super::contract::Dialect).

/// `job_store!(Backend { own items })`: `impl JobStore for Backend` with the
/// shared statements, over the backend's `pool`, and the backend's own items
/// (those [`JobStore`](super::contract::JobStore) methods that differ between
/// backends: `requeue_orphans`, and `postgres` where it has a pool to LISTEN
/// on). The backend must implement `Dialect`.
macro_rules! job_store {
    ($store:ty { $($own:tt)* }) => {
        // A block, so that the names the statements use are imported here
        // and not asked of the invoking module.
        const _: () = {
        use std::time::Duration;

        use patchwork_core::fabrication::OutputFile;
        use $crate::service::job_state::{Ending, EventKind, JobStatus};
        use $crate::service::store::contract::{Dialect, JobStore};
        use $crate::service::store::{
            Claim, Iteration, JOB_COLUMNS, JobRow, Lease, Renewal, StoredEvent, after, claim_of,
            now, renewal_of,
        };

        #[async_trait::async_trait]
        impl JobStore for $store {
        $($own)*

        async fn ping(&self) -> bool {
            sqlx::query("SELECT 1").execute(&self.pool).await.is_ok()
        }

        async fn insert_job(
            &self,
            id: &str,
            owner: &str,
            request: &str,
            spec: &str,
            idempotency_key: Option<&str>,
            event: (EventKind, &str),
        ) -> Result<Option<(JobRow, StoredEvent)>, sqlx::Error> {
            let sql = format!(
                "INSERT INTO jobs (id, owner, status, request, spec, idempotency_key, created_at,
                                   updated_at)
                 VALUES ($1, $2, 'queued', $3, $4, $5, $6, $6)
                 ON CONFLICT DO NOTHING RETURNING {JOB_COLUMNS}"
            );
            let mut tx = self.pool.begin().await?;
            let row = sqlx::query_as::<_, JobRow>(&sql)
                .bind(id)
                .bind(owner)
                .bind(request)
                .bind(spec)
                .bind(idempotency_key)
                .bind(now())
                .fetch_optional(&mut *tx)
                .await?;
            let Some(row) = row else { return Ok(None) };
            let stored = <$store as Dialect>::insert_event(&mut *tx, id, event, None).await?;
            tx.commit().await?;
            Ok(stored.map(|event| (row, event)))
        }

        async fn job_by_idempotency_key(
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

        async fn job(
            &self,
            id: &str,
            owner: Option<&str>,
        ) -> Result<Option<JobRow>, sqlx::Error> {
            let sql = format!(
                "SELECT {JOB_COLUMNS} FROM jobs
                 WHERE id = $1 AND (CAST($2 AS TEXT) IS NULL OR owner = $2)"
            );
            sqlx::query_as(&sql)
                .bind(id)
                .bind(owner)
                .fetch_optional(&self.pool)
                .await
        }

        async fn list_jobs(
            &self,
            owner: Option<&str>,
            status: Option<JobStatus>,
            before: Option<&str>,
            limit: i64,
        ) -> Result<Vec<JobRow>, sqlx::Error> {
            let sql = format!(
                "SELECT {JOB_COLUMNS} FROM jobs
                 WHERE (CAST($1 AS TEXT) IS NULL OR owner = $1)
                   AND (CAST($2 AS TEXT) IS NULL OR status = $2)
                   AND (CAST($3 AS TEXT) IS NULL OR id < $3)
                 ORDER BY id DESC LIMIT $4"
            );
            sqlx::query_as(&sql)
                .bind(owner)
                .bind(status.map(JobStatus::as_str))
                .bind(before)
                .bind(limit)
                .fetch_all(&self.pool)
                .await
        }

        async fn count_by_status(
            &self,
        ) -> Result<Vec<(JobStatus, i64)>, sqlx::Error> {
            let counts: Vec<(String, i64)> =
                sqlx::query_as("SELECT status, COUNT(*) FROM jobs GROUP BY status")
                    .fetch_all(&self.pool)
                    .await?;
            // The schema's CHECK admits only JobStatus's names.
            Ok(counts
                .into_iter()
                .filter_map(|(status, n)| Some((status.parse().ok()?, n)))
                .collect())
        }

        async fn queued_count(&self) -> Result<i64, sqlx::Error> {
            sqlx::query_scalar("SELECT COUNT(*) FROM jobs WHERE status = 'queued'")
                .fetch_one(&self.pool)
                .await
        }

        async fn claim_next(
            &self,
            node: &str,
            duration: Duration,
        ) -> Result<Option<Claim>, sqlx::Error> {
            let lock = <$store as Dialect>::CLAIM_LOCK;
            let sql = format!(
                "UPDATE jobs SET status = 'running', attempt = attempt + 1,
                        taken_over = (status = 'running'), lease_until = $2,
                        node = $3, updated_at = $1
                 WHERE id = (SELECT id FROM jobs
                             WHERE status = 'queued'
                                OR (status = 'running'
                                    AND (lease_until IS NULL OR lease_until < $1))
                             ORDER BY id LIMIT 1 {lock})
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

        async fn renew(
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

        async fn requeue(&self, lease: &Lease) -> Result<(), sqlx::Error> {
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

        async fn end(
            &self,
            id: &str,
            ending: Ending,
            error: Option<&str>,
            data: &str,
            fence: Option<i64>,
        ) -> Result<Option<StoredEvent>, sqlx::Error> {
            let mut tx = self.pool.begin().await?;
            let updated = sqlx::query(
                "UPDATE jobs SET status = $1, error = $2, lease_until = NULL, updated_at = $3
                 WHERE id = $4 AND status NOT IN ('succeeded', 'failed', 'cancelled')
                   AND (CAST($5 AS BIGINT) IS NULL OR attempt = $5)",
            )
            .bind(ending.status().as_str())
            .bind(error)
            .bind(now())
            .bind(id)
            .bind(fence)
            .execute(&mut *tx)
            .await?;
            if updated.rows_affected() != 1 {
                return Ok(None);
            }
            let stored = <$store as Dialect>::insert_event(&mut *tx, id, (ending.event(), data), None).await?;
            tx.commit().await?;
            Ok(stored)
        }

        async fn append_event(
            &self,
            id: &str,
            kind: EventKind,
            data: &str,
            fence: Option<i64>,
        ) -> Result<Option<StoredEvent>, sqlx::Error> {
            let mut tx = self.pool.begin().await?;
            let stored = <$store as Dialect>::insert_event(&mut *tx, id, (kind, data), fence).await?;
            tx.commit().await?;
            Ok(stored)
        }

        async fn jobs_without_spec(&self) -> Result<Vec<JobRow>, sqlx::Error> {
            let sql = format!("SELECT {JOB_COLUMNS} FROM jobs WHERE spec IS NULL ORDER BY id");
            sqlx::query_as(&sql).fetch_all(&self.pool).await
        }

        async fn set_spec(&self, id: &str, spec: &str) -> Result<bool, sqlx::Error> {
            let done = sqlx::query("UPDATE jobs SET spec = $2 WHERE id = $1 AND spec IS NULL")
                .bind(id)
                .bind(spec)
                .execute(&self.pool)
                .await?;
            Ok(done.rows_affected() == 1)
        }

        async fn events_after(
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

        async fn record_progress(
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
            if let Some(it) = iteration.filter(|_| updated.rows_affected() == 1) {
                sqlx::query(
                    "INSERT INTO iterations
                     (job_id, evaluations, generation, best_objective, sigma, elapsed_s)
                     VALUES ($1, $2, $3, $4, $5, $6)
                     ON CONFLICT (job_id, evaluations) DO UPDATE SET
                       generation = excluded.generation, best_objective = excluded.best_objective,
                       sigma = excluded.sigma, elapsed_s = excluded.elapsed_s",
                )
                .bind(&lease.id)
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

        async fn save_checkpoint(
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

        async fn finish(
            &self,
            lease: &Lease,
            result: &str,
            files: &[OutputFile],
            done: &str,
        ) -> Result<Option<StoredEvent>, sqlx::Error> {
            let id = &lease.id;
            let mut tx = self.pool.begin().await?;
            let updated = sqlx::query(
                "UPDATE jobs SET status = 'succeeded', result = $1, lease_until = NULL,
                        updated_at = $2
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
                       content_type = excluded.content_type, body = excluded.body",
                )
                .bind(id)
                .bind(file.name)
                .bind(file.content_type)
                .bind(&file.body)
                .execute(&mut *tx)
                .await?;
            }
            let stored = <$store as Dialect>::insert_event(&mut *tx, id, (EventKind::Done, done), None).await?;
            tx.commit().await?;
            Ok(stored)
        }

        async fn iterations(
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

        async fn result(&self, id: &str) -> Result<Option<String>, sqlx::Error> {
            sqlx::query_scalar("SELECT result FROM jobs WHERE id = $1")
                .bind(id)
                .fetch_optional(&self.pool)
                .await
                .map(Option::flatten)
        }

        async fn file(
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

        async fn delete(&self, id: &str) -> Result<(), sqlx::Error> {
            sqlx::query("DELETE FROM jobs WHERE id = $1")
                .bind(id)
                .execute(&self.pool)
                .await
                .map(|_| ())
        }
        }
        };
    };
}

pub(super) use job_store;
