//! Jobs stored before job specs (`spec.rs`) get theirs from their stored
//! request, once: at a server's start and after `copy-jobs`. A job still to
//! run whose request no longer makes a valid job fails, saying why; an ended
//! job keeps its request and goes without (its detail then shows no search
//! budget). After this, only submission writes specs and only the worker
//! reads them.

use serde_json::json;

use super::job_state::Ending;
use super::request::JobRequest;
use super::spec::JobSpec;
use super::store::JobStore;

/// What [`derive_specs`] did.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Derived {
    /// Jobs that got a spec.
    pub specs: usize,
    /// Jobs still to run that could not get one, failed.
    pub failed: usize,
}

/// Gives every job stored without a spec the one its request makes.
pub async fn derive_specs(store: &dyn JobStore) -> Result<Derived, sqlx::Error> {
    let mut derived = Derived::default();
    for row in store.jobs_without_spec().await? {
        let spec = serde_json::from_str::<JobRequest>(&row.request)
            .map_err(|e| format!("the stored request is not readable: {e}"))
            .and_then(|request| request.spec(None).map_err(|e| e.to_string()));
        match spec {
            Ok(spec) => {
                if store
                    .set_spec(&row.id, &JobSpec::Design(Box::new(spec)).to_stored())
                    .await?
                {
                    derived.specs += 1;
                }
            }
            Err(reason) if row.status.is_pending() => {
                let error = format!("the job as stored is no longer valid: {reason}");
                tracing::warn!(job = %row.id, "{error}");
                let data = json!({ "error": error }).to_string();
                if store
                    .end(&row.id, Ending::Failed, Some(&error), &data, None)
                    .await?
                    .is_some()
                {
                    derived.failed += 1;
                }
            }
            Err(_) => {}
        }
    }
    Ok(derived)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::service::job_state::JobStatus;
    use crate::service::store::{Database, ExportRow, JobExport, Store, now};

    /// A job as a store before job specs held it.
    async fn stored_before_specs(store: &Store, status: JobStatus, request: &str) -> String {
        let id = uuid::Uuid::now_v7().to_string();
        let row = ExportRow {
            id: id.clone(),
            owner: "lab".into(),
            status,
            request: request.into(),
            spec: None,
            idempotency_key: None,
            created_at: now(),
            updated_at: now(),
            progress: None,
            error: None,
            checkpoint: None,
            result: None,
            attempt: 0,
            checkpoint_evaluations: 0,
        };
        let job = JobExport {
            row,
            events: vec![],
            iterations: vec![],
            files: vec![],
        };
        assert!(store.import_job(&job).await.unwrap());
        id
    }

    #[tokio::test]
    async fn jobs_stored_before_specs_get_the_spec_their_request_makes() {
        let dir = tempfile::tempdir().unwrap();
        let store = Database::Sqlite(dir.path().join("jobs.db"))
            .open()
            .await
            .unwrap();
        let request =
            r#"{"curve": {"preset": "arc"}, "options": {"fidelity": "draft", "seed": 4}}"#;
        let refused = r#"{"curve": {"preset": "arc"}, "options": {"budget": 0}}"#;
        let valid = stored_before_specs(&store, JobStatus::Queued, request).await;
        let invalid = stored_before_specs(&store, JobStatus::Queued, refused).await;
        let ended = stored_before_specs(&store, JobStatus::Succeeded, refused).await;
        let derived = derive_specs(store.as_ref()).await.unwrap();
        assert_eq!(
            derived,
            Derived {
                specs: 1,
                failed: 1
            }
        );

        let row = store.job(&valid, None).await.unwrap().unwrap();
        let expected = serde_json::from_str::<JobRequest>(request)
            .unwrap()
            .spec(None)
            .unwrap();
        let spec = JobSpec::from_stored(row.spec.as_deref().unwrap()).unwrap();
        let JobSpec::Design(design) = spec else {
            panic!("a design job")
        };
        assert_eq!(*design, expected);
        assert_eq!(design.plan().settings().seed, 4);
        assert_eq!(row.status, JobStatus::Queued);

        let row = store.job(&invalid, None).await.unwrap().unwrap();
        assert_eq!(row.status, JobStatus::Failed);
        let error = row.error.unwrap_or_default();
        assert!(error.contains("options.budget"), "{error}");

        let row = store.job(&ended, None).await.unwrap().unwrap();
        assert_eq!((row.status, row.spec), (JobStatus::Succeeded, None));
        assert_eq!(
            derive_specs(store.as_ref()).await.unwrap(),
            Derived::default(),
            "once"
        );
    }
}
