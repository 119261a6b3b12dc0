//! The contract every backend keeps, run against each: a fresh store per
//! check, the same checks for all. SQLite runs in every `cargo test`;
//! PostgreSQL needs a server (`PATCHWORK_TEST_POSTGRES`, which `.ci/run`'s
//! PostgreSQL pass sets and runs the ignored tests with).

use std::time::Duration;

use patchwork_core::fabrication::OutputFile;

use super::export::JobExport;
use super::profile_conformance::{
    profiles_are_kept_per_owner_and_replaced_in_place, profiles_saved_at_once_all_land,
};
use super::{Database, Iteration, Lease, Renewal, Store};
use crate::service::job_state::{Ending, EventKind, JobStatus};

const LEASE: Duration = Duration::from_secs(60);

/// Where a fresh store comes from, and what keeps it alive.
enum Backend {
    Sqlite(tempfile::TempDir),
    Postgres(String),
}

impl Backend {
    async fn fresh(&self) -> Store {
        match self {
            Backend::Sqlite(dir) => {
                let file = dir.path().join(format!("{}.db", uuid::Uuid::now_v7()));
                Database::Sqlite(file)
                    .open()
                    .await
                    .expect("opens a SQLite file")
            }
            Backend::Postgres(server) => {
                use sqlx::Connection;
                let name = format!("patchwork_contract_{}", uuid::Uuid::now_v7().simple());
                let mut admin = sqlx::PgConnection::connect(server)
                    .await
                    .expect("PATCHWORK_TEST_POSTGRES answers");
                sqlx::query(&format!("CREATE DATABASE {name}"))
                    .execute(&mut admin)
                    .await
                    .expect("creates a database");
                let base = server.rsplit_once('/').map_or(server.as_str(), |(b, _)| b);
                Database::Postgres(format!("{base}/{name}"))
                    .open()
                    .await
                    .expect("opens the new database")
            }
        }
    }
}

/// Inserts a queued job `n` of `owner` with its `stage` event.
async fn submit(store: &Store, n: u32, owner: &str) -> String {
    let id = uuid::Uuid::now_v7().to_string();
    let request = format!("{{\"n\": {n}}}");
    let spec = format!("{{\"spec\": {n}}}");
    let (row, event) = store
        .insert_job(&id, owner, &request, &spec, None, (EventKind::Stage, "{}"))
        .await
        .unwrap()
        .expect("a new job is inserted");
    assert_eq!(
        (row.status, event.seq, event.kind),
        (JobStatus::Queued, 1, EventKind::Stage)
    );
    assert_eq!((row.request, row.spec), (request, Some(spec)));
    assert_eq!(row.owner, owner);
    id
}

async fn claim(store: &Store, duration: Duration) -> super::Claim {
    store
        .claim_next("node-a", duration)
        .await
        .unwrap()
        .expect("a job to claim")
}

async fn status(store: &Store, id: &str) -> JobStatus {
    store.job(id, None).await.unwrap().expect("the job").status
}

async fn kinds(store: &Store, id: &str) -> Vec<EventKind> {
    let events = store.events_after(id, 0).await.unwrap();
    let seqs: Vec<i64> = events.iter().map(|e| e.seq).collect();
    assert_eq!(
        seqs,
        (1..=events.len() as i64).collect::<Vec<_>>(),
        "event ids 1, 2, 3, …"
    );
    events.iter().map(|e| e.kind).collect()
}

fn design_json() -> OutputFile {
    OutputFile {
        name: "design.json",
        content_type: "application/json",
        body: b"{\"patches\": []}".to_vec(),
    }
}

async fn jobs_are_owned_and_idempotent(store: Store) {
    let id = uuid::Uuid::now_v7().to_string();
    let first = store
        .insert_job(
            &id,
            "lab",
            "{}",
            "{}",
            Some("key-1"),
            (EventKind::Stage, "{}"),
        )
        .await
        .unwrap();
    assert!(first.is_some());
    let other = uuid::Uuid::now_v7().to_string();
    let again = store
        .insert_job(
            &other,
            "lab",
            "{}",
            "{}",
            Some("key-1"),
            (EventKind::Stage, "{}"),
        )
        .await
        .unwrap();
    assert!(again.is_none(), "a used idempotency key inserts nothing");
    let found = store.job_by_idempotency_key("lab", "key-1").await.unwrap();
    assert_eq!(found.map(|r| r.id), Some(id.clone()));
    assert!(store.job(&other, None).await.unwrap().is_none());
    assert!(store.job(&id, Some("lab")).await.unwrap().is_some());
    assert!(store.job(&id, Some("another lab")).await.unwrap().is_none());
    assert!(
        store
            .job_by_idempotency_key("another lab", "key-1")
            .await
            .unwrap()
            .is_none()
    );
}

async fn lists_page_newest_first_and_count_by_status(store: Store) {
    let ids = [
        submit(&store, 1, "lab").await,
        submit(&store, 2, "lab").await,
        submit(&store, 3, "lab").await,
    ];
    submit(&store, 4, "another lab").await;
    let page = store.list_jobs(Some("lab"), None, None, 2).await.unwrap();
    let page: Vec<&str> = page.iter().map(|r| r.id.as_str()).collect();
    assert_eq!(page, [ids[2].as_str(), ids[1].as_str()]);
    let rest = store
        .list_jobs(Some("lab"), None, Some(&ids[1]), 2)
        .await
        .unwrap();
    assert_eq!(
        rest.iter().map(|r| r.id.as_str()).collect::<Vec<_>>(),
        [ids[0].as_str()]
    );
    claim(&store, LEASE).await;
    let running = store
        .list_jobs(None, Some(JobStatus::Running), None, 10)
        .await
        .unwrap();
    assert_eq!(
        running.iter().map(|r| r.id.as_str()).collect::<Vec<_>>(),
        [ids[0].as_str()]
    );
    let mut counts = store.count_by_status().await.unwrap();
    counts.sort_by_key(|(s, _)| s.as_str());
    assert_eq!(counts, [(JobStatus::Queued, 3), (JobStatus::Running, 1)]);
    assert_eq!(store.queued_count().await.unwrap(), 3);
}

async fn a_claim_takes_the_oldest_and_a_cancel_stops_its_lease(store: Store) {
    let first = submit(&store, 1, "lab").await;
    let second = submit(&store, 2, "lab").await;
    let c = claim(&store, LEASE).await;
    assert_eq!(
        (c.job.id.as_str(), c.lease.attempt, c.taken_over),
        (first.as_str(), 1, false)
    );
    assert_eq!(c.job.status, JobStatus::Running);
    assert_eq!(claim(&store, LEASE).await.job.id, second);
    assert!(
        store.claim_next("node-a", LEASE).await.unwrap().is_none(),
        "nothing left"
    );
    assert_eq!(store.renew(&c.lease, LEASE).await.unwrap(), Renewal::Held);
    let ended = store
        .end(&first, Ending::Cancelled, None, "{}", None)
        .await
        .unwrap();
    assert_eq!(
        ended.map(|e| (e.seq, e.kind)),
        Some((2, EventKind::Cancelled))
    );
    assert_eq!(
        store.renew(&c.lease, LEASE).await.unwrap(),
        Renewal::Cancelled
    );
    assert!(
        store
            .end(&first, Ending::Failed, Some("late"), "{}", None)
            .await
            .unwrap()
            .is_none()
    );
    assert_eq!(status(&store, &first).await, JobStatus::Cancelled);
    assert_eq!(
        kinds(&store, &first).await,
        [EventKind::Stage, EventKind::Cancelled]
    );
}

async fn a_lapsed_lease_is_taken_over_and_its_writes_dropped(store: Store) {
    let id = submit(&store, 1, "lab").await;
    let old = claim(&store, Duration::ZERO).await.lease;
    tokio::time::sleep(Duration::from_millis(5)).await;
    let taken = claim(&store, LEASE).await;
    assert_eq!((taken.lease.attempt, taken.taken_over), (2, true));
    assert_eq!(store.renew(&old, LEASE).await.unwrap(), Renewal::Lost);
    let fenced = store.append_event(&id, EventKind::Progress, "{}", Some(old.attempt));
    assert!(
        fenced.await.unwrap().is_none(),
        "an old attempt's event is dropped"
    );
    store
        .record_progress(&old, "{\"old\": true}", None)
        .await
        .unwrap();
    assert_eq!(store.job(&id, None).await.unwrap().unwrap().progress, None);
    assert!(
        store
            .finish(&old, "{}", &[design_json()], "{}")
            .await
            .unwrap()
            .is_none()
    );
    let failed = store.end(&id, Ending::Failed, Some("old"), "{}", Some(old.attempt));
    assert!(
        failed.await.unwrap().is_none(),
        "an old attempt cannot end the job"
    );
    let fenced = store.append_event(&id, EventKind::Progress, "{}", Some(taken.lease.attempt));
    assert_eq!(fenced.await.unwrap().map(|e| e.seq), Some(2));
    assert_eq!(status(&store, &id).await, JobStatus::Running);
}

async fn a_finished_job_keeps_its_result_files_and_done_event(store: Store) {
    let id = submit(&store, 1, "lab").await;
    let lease = claim(&store, LEASE).await.lease;
    assert!(store.result(&id).await.unwrap().is_none());
    let files = [design_json()];
    let done = store.finish(&lease, "{\"ok\": 1}", &files, "{\"done\": 1}");
    assert_eq!(done.await.unwrap().map(|e| e.kind), Some(EventKind::Done));
    assert_eq!(status(&store, &id).await, JobStatus::Succeeded);
    assert_eq!(
        store.result(&id).await.unwrap().as_deref(),
        Some("{\"ok\": 1}")
    );
    let file = store.file(&id, "design.json").await.unwrap();
    assert_eq!(
        file,
        Some(("application/json".to_string(), design_json().body))
    );
    assert!(store.file(&id, "patches.dxf").await.unwrap().is_none());
    assert!(
        store
            .end(&id, Ending::Cancelled, None, "{}", None)
            .await
            .unwrap()
            .is_none()
    );
    assert_eq!(
        kinds(&store, &id).await,
        [EventKind::Stage, EventKind::Done]
    );
    store.delete(&id).await.unwrap();
    assert!(store.job(&id, None).await.unwrap().is_none());
    assert!(store.events_after(&id, 0).await.unwrap().is_empty());
    assert!(store.file(&id, "design.json").await.unwrap().is_none());
}

async fn progress_and_checkpoints_survive_a_requeue(store: Store) {
    let id = submit(&store, 1, "lab").await;
    let lease = claim(&store, LEASE).await.lease;
    let generation = |evaluations: i64, best: f64| Iteration {
        evaluations,
        generation: evaluations / 10,
        best_objective: best,
        sigma: 0.5,
        elapsed_s: 1.0,
    };
    store
        .record_progress(&lease, "{\"g\": 1}", Some(&generation(10, 2.0)))
        .await
        .unwrap();
    store
        .record_progress(&lease, "{\"g\": 1}", Some(&generation(10, 1.5)))
        .await
        .unwrap();
    store
        .record_progress(&lease, "{\"g\": 2}", Some(&generation(20, 1.0)))
        .await
        .unwrap();
    let rows = store.iterations(&id, -1, 10).await.unwrap();
    let best: Vec<(i64, f64)> = rows
        .iter()
        .map(|r| (r.evaluations, r.best_objective))
        .collect();
    assert_eq!(
        best,
        [(10, 1.5), (20, 1.0)],
        "one row per generation, the latest kept"
    );
    assert_eq!(store.iterations(&id, 10, 10).await.unwrap().len(), 1);
    store.save_checkpoint(&lease, "at 100", 100).await.unwrap();
    store.save_checkpoint(&lease, "at 50", 50).await.unwrap();
    store.requeue(&lease).await.unwrap();
    assert_eq!(status(&store, &id).await, JobStatus::Queued);
    let again = claim(&store, LEASE).await;
    assert_eq!(
        again.checkpoint.as_deref(),
        Some("at 100"),
        "a checkpoint never goes back"
    );
    assert_eq!((again.lease.attempt, again.taken_over), (2, false));
    let progress = again.job.progress.as_deref();
    assert_eq!(progress, Some("{\"g\": 2}"));
}

async fn orphans_of_a_one_node_store_are_queued_at_start(store: Store) {
    let id = submit(&store, 1, "lab").await;
    claim(&store, LEASE).await;
    let requeued = store.requeue_orphans().await.unwrap();
    // A shared store (PostgreSQL) leaves running jobs to their leases.
    let (count, now) = match store.postgres() {
        None => (1, JobStatus::Queued),
        Some(_) => (0, JobStatus::Running),
    };
    assert_eq!(requeued, count);
    assert_eq!(status(&store, &id).await, now);
}

async fn an_exported_job_is_imported_once_and_numbers_on(store: Store, into: Store) {
    let id = submit(&store, 1, "lab").await;
    let lease = claim(&store, LEASE).await.lease;
    store
        .append_event(&id, EventKind::Progress, "{}", Some(lease.attempt))
        .await
        .unwrap();
    store.save_checkpoint(&lease, "cp", 3).await.unwrap();
    let export: JobExport = store.export_job(&id).await.unwrap().expect("the job");
    assert!(
        store
            .export_job(&uuid::Uuid::now_v7().to_string())
            .await
            .unwrap()
            .is_none()
    );
    assert!(into.import_job(&export).await.unwrap());
    assert!(
        !into.import_job(&export).await.unwrap(),
        "already there: nothing written"
    );
    assert_eq!(into.job_ids().await.unwrap(), [id.as_str()]);
    assert_eq!(
        status(&into, &id).await,
        JobStatus::Queued,
        "a running job arrives queued"
    );
    let resumed = claim(&into, LEASE).await;
    assert_eq!(resumed.checkpoint.as_deref(), Some("cp"));
    let next = into
        .append_event(&id, EventKind::Progress, "{}", None)
        .await
        .unwrap();
    assert_eq!(
        next.map(|e| e.seq),
        Some(3),
        "events number on after the imported ones"
    );
    let done = Lease {
        id: id.clone(),
        attempt: resumed.lease.attempt,
    };
    assert!(into.finish(&done, "{}", &[], "{}").await.unwrap().is_some());
}

/// A job stored before job specs (imported without one) is listed until it
/// gets one, and gets one once.
async fn a_job_without_a_spec_gets_one_once(store: Store, into: Store) {
    let id = submit(&store, 1, "lab").await;
    let mut export = store.export_job(&id).await.unwrap().expect("the job");
    assert_eq!(export.row.spec.as_deref(), Some("{\"spec\": 1}"));
    export.row.spec = None;
    assert!(into.import_job(&export).await.unwrap());
    let claimed = claim(&into, LEASE).await;
    assert_eq!(claimed.job.spec, None);
    let missing = into.jobs_without_spec().await.unwrap();
    assert_eq!(missing.iter().map(|r| &r.id).collect::<Vec<_>>(), [&id]);
    assert!(store.jobs_without_spec().await.unwrap().is_empty());
    assert!(into.set_spec(&id, "{\"spec\": 2}").await.unwrap());
    assert!(!into.set_spec(&id, "{\"spec\": 3}").await.unwrap());
    assert!(into.jobs_without_spec().await.unwrap().is_empty());
    let row = into.job(&id, None).await.unwrap().expect("the job");
    assert_eq!(row.spec.as_deref(), Some("{\"spec\": 2}"));
}

/// Every check against fresh stores of `backend`.
async fn keeps_the_contract(backend: Backend) {
    jobs_are_owned_and_idempotent(backend.fresh().await).await;
    lists_page_newest_first_and_count_by_status(backend.fresh().await).await;
    a_claim_takes_the_oldest_and_a_cancel_stops_its_lease(backend.fresh().await).await;
    a_lapsed_lease_is_taken_over_and_its_writes_dropped(backend.fresh().await).await;
    a_finished_job_keeps_its_result_files_and_done_event(backend.fresh().await).await;
    progress_and_checkpoints_survive_a_requeue(backend.fresh().await).await;
    orphans_of_a_one_node_store_are_queued_at_start(backend.fresh().await).await;
    let (from, into) = (backend.fresh().await, backend.fresh().await);
    an_exported_job_is_imported_once_and_numbers_on(from, into).await;
    let (from, into) = (backend.fresh().await, backend.fresh().await);
    a_job_without_a_spec_gets_one_once(from, into).await;
    let (from, into) = (backend.fresh().await, backend.fresh().await);
    profiles_are_kept_per_owner_and_replaced_in_place(from, into).await;
    profiles_saved_at_once_all_land(backend.fresh().await).await;
    assert!(backend.fresh().await.ping().await);
}

#[tokio::test]
async fn the_sqlite_store_keeps_the_contract() {
    keeps_the_contract(Backend::Sqlite(tempfile::tempdir().unwrap())).await;
}

#[tokio::test]
#[ignore = "needs a PostgreSQL server in PATCHWORK_TEST_POSTGRES; .ci/run's PostgreSQL pass runs it"]
async fn the_postgres_store_keeps_the_contract() {
    let server = std::env::var("PATCHWORK_TEST_POSTGRES")
        .expect("PATCHWORK_TEST_POSTGRES: the URL of a PostgreSQL server to create databases on");
    keeps_the_contract(Backend::Postgres(server)).await;
}
