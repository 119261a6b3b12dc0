//! The statements both backends run, written once. Each is SQL that SQLite
//! and PostgreSQL read alike: numbered parameters (`$1`, reused where a value
//! appears twice), `CAST(… AS TEXT)` where PostgreSQL must know a parameter's
//! type, and `ON CONFLICT … DO UPDATE` for upserts. The macro expands to the
//! same methods in each backend's `impl`, over its own pool; a backend adds
//! what only it can say: how it opens, how it numbers an event
//! (`insert_event`), and how a claim locks its row (`CLAIM_LOCK`).

/// The methods shared by `SqliteStore` and `PgStore` (see the module doc).
/// The invoking module provides `insert_event`, `CLAIM_LOCK` and the
/// store's types (`JobRow`, `Lease`, …).
macro_rules! shared_statements {
    () => {
        pub(super) async fn ping(&self) -> bool {
            sqlx::query("SELECT 1").execute(&self.pool).await.is_ok()
        }

        pub(super) async fn insert_job(
            &self,
            id: &str,
            owner: &str,
            request: &str,
            idempotency_key: Option<&str>,
            event: (&str, &str),
        ) -> Result<Option<(JobRow, StoredEvent)>, sqlx::Error> {
            let sql = format!(
                "INSERT INTO jobs (id, owner, status, request, idempotency_key, created_at, updated_at)
                 VALUES ($1, $2, 'queued', $3, $4, $5, $5)
                 ON CONFLICT DO NOTHING RETURNING {JOB_COLUMNS}"
            );
            let mut tx = self.pool.begin().await?;
            let row = sqlx::query_as::<_, JobRow>(&sql)
                .bind(id)
                .bind(owner)
                .bind(request)
                .bind(idempotency_key)
                .bind(now())
                .fetch_optional(&mut *tx)
                .await?;
            let Some(row) = row else { return Ok(None) };
            let stored = insert_event(&mut tx, id, event, None).await?;
            tx.commit().await?;
            Ok(stored.map(|event| (row, event)))
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
                "SELECT {JOB_COLUMNS} FROM jobs
                 WHERE id = $1 AND (CAST($2 AS TEXT) IS NULL OR owner = $2)"
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
                 WHERE (CAST($1 AS TEXT) IS NULL OR owner = $1)
                   AND (CAST($2 AS TEXT) IS NULL OR status = $2)
                   AND (CAST($3 AS TEXT) IS NULL OR id < $3)
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
                                OR (status = 'running'
                                    AND (lease_until IS NULL OR lease_until < $1))
                             ORDER BY id LIMIT 1 {CLAIM_LOCK})
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
                   AND (CAST($5 AS BIGINT) IS NULL OR attempt = $5)",
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
    };
}

pub(super) use shared_statements;
