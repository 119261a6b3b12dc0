//! Several `patchwork serve` nodes on one PostgreSQL database. A SQLite file
//! has one node, so these are ignored unless asked for: `.ci/run`'s
//! PostgreSQL pass runs them (`--include-ignored`, with
//! `PATCHWORK_TEST_POSTGRES` set), and without a server they fail.

use std::time::Duration;

use futures_util::future::join_all;
use serde_json::Value;

use crate::support::*;

fn require_postgres() {
    assert!(
        std::env::var_os("PATCHWORK_TEST_POSTGRES").is_some(),
        "several nodes need PostgreSQL: set PATCHWORK_TEST_POSTGRES (.ci/run does)"
    );
}

fn node(db: &std::path::Path, workers: usize, config: Option<&'static str>) -> Server {
    Server::with(Options {
        workers: Some(workers),
        db: Some(db.to_path_buf()),
        config,
        ..Options::default()
    })
}

/// Two nodes, three workers: fifty jobs submitted at once through both all
/// succeed, each run exactly once (one seed stage, one `done`). The jobs
/// stop after their seed, so that the nodes claim one about every tenth of
/// a second.
#[tokio::test(flavor = "multi_thread")]
#[ignore = "needs PostgreSQL (PATCHWORK_TEST_POSTGRES); run by .ci/run\'s PostgreSQL pass"]
async fn fifty_jobs_through_two_nodes_each_run_once() {
    require_postgres();
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("shared.db");
    let (a, b) = (node(&db, 2, None), node(&db, 1, None));
    let (api_a, api_b) = (a.api(), b.api());
    let job = seed_only_job();
    let submits = (0..50).map(|i| {
        let api = if i % 2 == 0 { &api_a } else { &api_b };
        api.submit(&job)
    });
    let ids = join_all(submits).await;
    for id in &ids {
        let job = api_b
            .wait_for(id, &["succeeded", "failed"], Duration::from_secs(300))
            .await;
        assert_eq!(job["status"], "succeeded", "{job}");
        let events = read_events(&api_a, id, None, |_| false).await;
        let count = |kind: &str, stage: Option<&str>| {
            events
                .iter()
                .filter(|e| e.kind == kind && stage.is_none_or(|s| e.data["stage"] == s))
                .count()
        };
        assert_eq!(count("done", None), 1, "{id}: {events:?}");
        assert_eq!(count("stage", Some("seed")), 1, "{id} ran more than once");
    }
}

/// The node running a job is killed (kill -9): another node claims it when
/// its lease runs out and finishes it from the checkpoint.
#[tokio::test(flavor = "multi_thread")]
#[ignore = "needs PostgreSQL (PATCHWORK_TEST_POSTGRES); run by .ci/run\'s PostgreSQL pass"]
async fn a_killed_nodes_job_is_finished_by_another_from_its_checkpoint() {
    require_postgres();
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("shared.db");
    let mut a = node(&db, 1, Some("lease_s = 2"));
    let id = a.api().submit(&long_job(600)).await;
    let before = read_events(&a.api(), &id, None, |e| {
        e.kind == "progress" && e.data["evaluations"].as_u64().unwrap() >= 60
    })
    .await;
    let b = node(&db, 1, Some("lease_s = 2"));
    a.kill_hard();
    let last_seen = before.last().unwrap().id;
    let after = read_events(&b.api(), &id, Some(last_seen), |_| false).await;
    let resumed = after
        .iter()
        .find(|e| e.kind == "progress")
        .expect("progress after the takeover");
    // Resumed from a checkpoint (the first generation has 9 evaluations).
    assert!(
        resumed.data["evaluations"].as_u64().unwrap() > 17,
        "{resumed:?}"
    );
    assert_eq!(after.last().unwrap().kind, "done");
    assert!(
        after.windows(2).all(|w| w[1].id == w[0].id + 1),
        "{after:?}"
    );
    assert_eq!(b.api().job(&id).await["status"], "succeeded");
    let metrics = b.api().get("/metrics").await.text().await.unwrap();
    assert!(metrics.contains("patchwork_takeovers_total 1"), "{metrics}");
}

/// An API-only node (`--workers 0`) streams the events of a job that runs
/// on another node, live; a cancel through one node stops the job running
/// on the other.
#[tokio::test(flavor = "multi_thread")]
#[ignore = "needs PostgreSQL (PATCHWORK_TEST_POSTGRES); run by .ci/run\'s PostgreSQL pass"]
async fn events_and_cancels_cross_nodes() {
    require_postgres();
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("shared.db");
    let worker = node(&db, 1, None);
    let front = node(&db, 0, None);
    let id = front.api().submit(&long_job(200)).await;
    let events = read_events(&front.api(), &id, None, |_| false).await;
    let progress = events.iter().filter(|e| e.kind == "progress").count();
    assert!(
        progress > 3,
        "live progress through the API-only node: {events:?}"
    );
    assert_eq!(events.last().unwrap().kind, "done");

    let id = worker.api().submit(&long_job(2000)).await;
    read_events(&front.api(), &id, None, |e| e.kind == "progress").await;
    let response = front
        .api()
        .post(&format!("/v1/jobs/{id}/cancel"), &Value::Null)
        .await;
    assert_eq!(response.status(), 200);
    let rest = read_events(&worker.api(), &id, None, |_| false).await;
    assert_eq!(rest.last().unwrap().kind, "cancelled");
    // The worker is free again: a quick job through the front node runs.
    let quick = front.api().submit(&quick_job(5)).await;
    let job = front
        .api()
        .wait_for(&quick, &["succeeded", "failed"], Duration::from_secs(120))
        .await;
    assert_eq!(job["status"], "succeeded");
}

/// An Idempotency-Key used through one node gives the same job through the
/// other; a key's jobs stay its own on every node.
#[tokio::test(flavor = "multi_thread")]
#[ignore = "needs PostgreSQL (PATCHWORK_TEST_POSTGRES); run by .ci/run\'s PostgreSQL pass"]
async fn idempotency_and_keys_hold_across_nodes() {
    require_postgres();
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("shared.db");
    let keyed = |workers| {
        Server::with(Options {
            workers: Some(workers),
            db: Some(db.clone()),
            keys: Some("alice-key,bob-key"),
            ..Options::default()
        })
    };
    let (a, b) = (keyed(1), keyed(0));
    let send = |server: &Server| {
        let alice = server.as_key("alice-key");
        async move { alice.submit_keyed(&quick_job(5), "lab-7-run-12").await }
    };
    let first: Value = send(&a).await.json().await.unwrap();
    let again = send(&b).await;
    assert_eq!(again.status(), 202);
    let again: Value = again.json().await.unwrap();
    assert_eq!(
        first["id"], again["id"],
        "one job for one key, whichever node"
    );
    let id = first["id"].as_str().unwrap();
    for server in [&a, &b] {
        let bob = server.as_key("bob-key");
        assert_eq!(bob.get(&format!("/v1/jobs/{id}")).await.status(), 404);
        let listed: Value = bob.get("/v1/jobs").await.json().await.unwrap();
        assert_eq!(listed["jobs"].as_array().unwrap().len(), 0);
        let alice = server.as_key("alice-key");
        assert_eq!(alice.get(&format!("/v1/jobs/{id}")).await.status(), 200);
    }
}
