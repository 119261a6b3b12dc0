//! The balloon profiles' statements, written once for both backends (as
//! `statements.rs` writes the jobs'): `profile_store!(Backend)` implements
//! [`ProfileStore`](super::contract::ProfileStore) over the backend's `pool`.

macro_rules! profile_store {
    ($store:ty) => {
        const _: () = {
            use $crate::service::store::contract::ProfileStore;
            use $crate::service::store::{ProfileRow, now};

            const COLUMNS: &str = "owner, name, profile, source_job, created_at, updated_at";

            #[async_trait::async_trait]
            impl ProfileStore for $store {
                /// Two single statements, each its own transaction: a save
                /// that read the row and then wrote it in one transaction
                /// could find its read stale under SQLite's WAL once another
                /// connection had written, and fail at once. A save that
                /// finds the row gone between the two statements (deleted
                /// meanwhile) creates it again.
                async fn put_profile(
                    &self,
                    owner: &str,
                    name: &str,
                    profile: &str,
                    source_job: Option<&str>,
                ) -> Result<bool, sqlx::Error> {
                    const INSERT: &str = "INSERT INTO balloon_profiles
                           (owner, name, profile, source_job, created_at, updated_at)
                         VALUES ($1, $2, $3, $4, $5, $5)
                         ON CONFLICT (owner, name) DO NOTHING";
                    const UPDATE: &str = "UPDATE balloon_profiles
                         SET profile = $3, source_job = $4, updated_at = $5
                         WHERE owner = $1 AND name = $2";
                    let write = |sql: &'static str, at: String| {
                        sqlx::query(sql)
                            .bind(owner)
                            .bind(name)
                            .bind(profile)
                            .bind(source_job)
                            .bind(at)
                            .execute(&self.pool)
                    };
                    loop {
                        let at = now();
                        if write(INSERT, at.clone()).await?.rows_affected() == 1 {
                            return Ok(true);
                        }
                        if write(UPDATE, at).await?.rows_affected() == 1 {
                            return Ok(false);
                        }
                    }
                }

                async fn profile(
                    &self,
                    owner: &str,
                    name: &str,
                ) -> Result<Option<ProfileRow>, sqlx::Error> {
                    let sql = format!(
                        "SELECT {COLUMNS} FROM balloon_profiles WHERE owner = $1 AND name = $2"
                    );
                    sqlx::query_as(&sql)
                        .bind(owner)
                        .bind(name)
                        .fetch_optional(&self.pool)
                        .await
                }

                async fn profiles(&self, owner: &str) -> Result<Vec<ProfileRow>, sqlx::Error> {
                    let sql = format!(
                        "SELECT {COLUMNS} FROM balloon_profiles WHERE owner = $1 ORDER BY name"
                    );
                    sqlx::query_as(&sql).bind(owner).fetch_all(&self.pool).await
                }

                async fn delete_profile(
                    &self,
                    owner: &str,
                    name: &str,
                ) -> Result<bool, sqlx::Error> {
                    let deleted =
                        sqlx::query("DELETE FROM balloon_profiles WHERE owner = $1 AND name = $2")
                            .bind(owner)
                            .bind(name)
                            .execute(&self.pool)
                            .await?;
                    Ok(deleted.rows_affected() == 1)
                }

                async fn all_profiles(&self) -> Result<Vec<ProfileRow>, sqlx::Error> {
                    let sql =
                        format!("SELECT {COLUMNS} FROM balloon_profiles ORDER BY owner, name");
                    sqlx::query_as(&sql).fetch_all(&self.pool).await
                }

                async fn import_profile(&self, p: &ProfileRow) -> Result<bool, sqlx::Error> {
                    let inserted = sqlx::query(
                        "INSERT INTO balloon_profiles
                           (owner, name, profile, source_job, created_at, updated_at)
                         VALUES ($1, $2, $3, $4, $5, $6)
                         ON CONFLICT (owner, name) DO NOTHING",
                    )
                    .bind(&p.owner)
                    .bind(&p.name)
                    .bind(&p.profile)
                    .bind(&p.source_job)
                    .bind(&p.created_at)
                    .bind(&p.updated_at)
                    .execute(&self.pool)
                    .await?;
                    Ok(inserted.rows_affected() == 1)
                }
            }
        };
    };
}

pub(super) use profile_store;
