//! Nothing is lost on restart: a job running when the server is killed with
//! SIGKILL resumes from its last checkpoint; SIGTERM checkpoints and exits; a
//! queued job runs after a restart.

use std::time::Duration;

use crate::support::*;

/// Evaluations of the search's first generation in a fresh run (population 8
/// for one patch's five variables, plus the seed).
const FIRST_GENERATION: u64 = 9;

#[tokio::test(flavor = "multi_thread")]
async fn a_killed_server_resumes_running_jobs_from_their_checkpoints() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("patchwork.db");
    let options = Options {
        workers: Some(1),
        db: Some(db.clone()),
        ..Options::default()
    };
    let mut server = Server::with(options.clone());
    let api = server.api();
    let id = api.submit(&long_job(600)).await;
    let queued = api.submit(&quick_job(20)).await;
    // Let the search run for a few generations, then kill -9.
    let before = read_events(&api, &id, None, |e| {
        e.kind == "progress" && e.data["evaluations"].as_u64().unwrap() >= 60
    })
    .await;
    let evaluations_at_kill = before.last().unwrap().data["evaluations"].as_u64().unwrap();
    server.kill_hard();

    let server = Server::with(options);
    let api = server.api();
    let last_seen = before.last().unwrap().id;
    let after = read_events(&api, &id, Some(last_seen), |_| false).await;
    let first_progress = after
        .iter()
        .find(|e| e.kind == "progress")
        .expect("progress after the restart");
    let resumed_at = first_progress.data["evaluations"].as_u64().unwrap();
    println!("killed at {evaluations_at_kill} evaluations; resumed run first reports {resumed_at}");
    // Resumed from a checkpoint at most a generation behind, not from scratch.
    assert!(resumed_at > FIRST_GENERATION + 8, "restarted from scratch");
    assert!(resumed_at + 8 >= evaluations_at_kill);
    assert_eq!(after.last().unwrap().kind, "done", "{after:?}");
    // Event ids stayed monotonic across the restart.
    assert!(after.windows(2).all(|w| w[1].id == w[0].id + 1));
    assert_eq!(after[0].id, last_seen + 1);
    let job = api.job(&id).await;
    assert_eq!(job["status"], "succeeded");
    // The job that was queued at the kill runs too.
    let job = api
        .wait_for(&queued, &["succeeded", "failed"], Duration::from_secs(60))
        .await;
    assert_eq!(job["status"], "succeeded");
}

#[tokio::test(flavor = "multi_thread")]
async fn sigterm_checkpoints_running_jobs_and_the_next_start_finishes_them() {
    let dir = tempfile::tempdir().unwrap();
    let options = Options {
        workers: Some(1),
        db: Some(dir.path().join("patchwork.db")),
        ..Options::default()
    };
    let mut server = Server::with(options.clone());
    let api = server.api();
    let id = api.submit(&long_job(600)).await;
    let before = read_events(&api, &id, None, |e| {
        e.kind == "progress" && e.data["evaluations"].as_u64().unwrap() >= 40
    })
    .await;
    let status = server.terminate();
    assert!(status.success(), "graceful exit: {status:?}");

    let server = Server::with(options);
    let api = server.api();
    let after = read_events(&api, &id, Some(before.last().unwrap().id), |_| false).await;
    let resumed_at = after.iter().find(|e| e.kind == "progress").unwrap().data["evaluations"]
        .as_u64()
        .unwrap();
    assert!(resumed_at > FIRST_GENERATION + 8, "restarted from scratch");
    assert_eq!(after.last().unwrap().kind, "done");
}

/// A job queued by a server whose requests still carried the research
/// options (`options.patience`, `options.refine`, `objective`) runs after an
/// upgrade: the migration moves them into `tuning`. A SQLite file's own
/// migration (PostgreSQL stores came later, with `tuning` from the start).
#[tokio::test(flavor = "multi_thread")]
async fn a_job_queued_before_the_tuning_object_runs_after_the_upgrade() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("patchwork.db");
    let first = dir.path().join("migrations");
    std::fs::create_dir(&first).unwrap();
    std::fs::copy(
        "migrations/sqlite/0001_jobs.sql",
        first.join("0001_jobs.sql"),
    )
    .unwrap();
    let old_request = serde_json::json!({
        "curve": {"preset": "arc", "params": {"radius_mm": 40, "angle_deg": 90}},
        "options": {"budget": 8, "seed": 3, "fidelity": "draft", "patience": 0, "refine": 2,
                    "correction": false, "start": "ksa"},
        "objective": {"shape_weight": 5}
    });
    {
        let options = sqlx::sqlite::SqliteConnectOptions::new()
            .filename(&db)
            .create_if_missing(true);
        let pool = sqlx::SqlitePool::connect_with(options).await.unwrap();
        let migrator = sqlx::migrate::Migrator::new(first.as_path()).await.unwrap();
        migrator.run(&pool).await.unwrap();
        sqlx::query(
            "INSERT INTO jobs (id, owner, status, request, created_at, updated_at)
             VALUES ('0190a5c4-0000-7000-8000-000000000001', '', 'queued', ?,
                     '2026-11-01T00:00:00Z', '2026-11-01T00:00:00Z')",
        )
        .bind(old_request.to_string())
        .execute(&pool)
        .await
        .unwrap();
        pool.close().await;
    }
    let server = Server::with(Options {
        workers: Some(1),
        db: Some(db),
        sqlite: true,
        ..Options::default()
    });
    let api = server.api();
    let id = "0190a5c4-0000-7000-8000-000000000001";
    let job = api
        .wait_for(id, &["succeeded", "failed"], Duration::from_secs(60))
        .await;
    assert_eq!(job["status"], "succeeded", "{job}");
    let result: serde_json::Value = api
        .get(&format!("/v1/jobs/{id}/result"))
        .await
        .json()
        .await
        .unwrap();
    // The refine ran with the old request's 2 solves, uncorrected.
    assert!(
        result["refine"]["solves"].as_u64().unwrap() <= 2,
        "{}",
        result["refine"]
    );
}
