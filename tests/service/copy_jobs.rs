//! `patchwork copy-jobs` from a SQLite file into the store under test (a
//! second SQLite file, or in the PostgreSQL pass a PostgreSQL database): a
//! lab's server killed with jobs in every state, copied, and served again
//! from the copy.

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use serde_json::{Value, json};

use crate::support::*;

/// `patchwork copy-jobs`: whether it succeeded, its stdout and its stderr.
fn run_copy_jobs(from: &Path, to: &str) -> (bool, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_patchwork"))
        .arg("copy-jobs")
        .arg("--from")
        .arg(from)
        .args(["--to", to])
        .output()
        .unwrap();
    let text = |bytes: &[u8]| String::from_utf8_lossy(bytes).trim().to_string();
    (
        output.status.success(),
        text(&output.stdout),
        text(&output.stderr),
    )
}

fn copy_jobs(from: &Path, to: &str) -> String {
    let (ok, stdout, stderr) = run_copy_jobs(from, to);
    assert!(ok, "{stderr}");
    stdout
}

async fn submit_with_key(api: &Api, body: &Value, key: &str) -> String {
    let response = api.submit_keyed(body, key).await;
    assert_eq!(response.status(), 202);
    let job: Value = response.json().await.unwrap();
    job["id"].as_str().unwrap().to_string()
}

async fn text(api: &Api, path: &str) -> String {
    let response = api.get(path).await;
    assert_eq!(response.status(), 200, "{path}");
    response.text().await.unwrap()
}

/// A succeeded, a cancelled, a running and a queued job, the server killed
/// (kill -9): the copy answers the ended jobs as they were (result, files,
/// events), resumes the running one from its checkpoint and runs the queued
/// one; copying again skips every job.
#[tokio::test(flavor = "multi_thread")]
async fn copied_jobs_are_served_as_they_were_and_unfinished_ones_go_on() {
    let dir = tempfile::tempdir().unwrap();
    let lab = dir.path().join("lab.db");
    let mut source = Server::with(Options {
        sqlite: true,
        workers: Some(1),
        db: Some(lab.clone()),
        ..Options::default()
    });
    let api = source.api();
    let done = submit_with_key(&api, &quick_job(5), "run-1").await;
    api.wait_for(&done, &["succeeded"], Duration::from_secs(120))
        .await;
    let cancelled = api.submit(&long_job(2000)).await;
    api.wait_for(&cancelled, &["running"], Duration::from_secs(60))
        .await;
    api.post(&format!("/v1/jobs/{cancelled}/cancel"), &Value::Null)
        .await;
    let running = api.submit(&long_job(300)).await;
    let before = read_events(&api, &running, None, |e| {
        e.kind == "progress" && e.data["evaluations"].as_u64().unwrap() >= 60
    })
    .await;
    let queued = api.submit(&quick_job(7)).await;
    let profile =
        json!({"balloon": {"length_mm": 250, "material": {"model": "neo_hookean", "mu_mpa": 0.3}}});
    let put = (api.request(reqwest::Method::PUT, "/v1/balloons/latex-7"))
        .json(&profile)
        .send()
        .await
        .unwrap();
    assert_eq!(put.status(), 201);
    let saved = text(&api, "/v1/balloons/latex-7").await;
    let result = text(&api, &format!("/v1/jobs/{done}/result")).await;
    let dxf = text(&api, &format!("/v1/jobs/{done}/files/patches.dxf")).await;
    let events = read_events(&api, &done, None, |_| false).await;
    source.kill_hard();

    let copy = dir.path().join("copy.db");
    let to = database_for(&copy, None);
    let said = copy_jobs(&lab, &to);
    assert!(said.starts_with("copied 4 jobs"), "{said}");
    assert!(said.contains("and 1 balloon profile from"), "{said}");
    let served = Server::with(Options {
        workers: Some(1),
        db: Some(copy),
        ..Options::default()
    });
    let api = served.api();
    assert_eq!(text(&api, &format!("/v1/jobs/{done}/result")).await, result);
    let same_dxf = text(&api, &format!("/v1/jobs/{done}/files/patches.dxf")).await;
    assert_eq!(same_dxf, dxf);
    let copied = read_events(&api, &done, None, |_| false).await;
    let ids = |e: &[SseEvent]| e.iter().map(|e| (e.id, e.kind.clone())).collect::<Vec<_>>();
    assert_eq!(ids(&copied), ids(&events));
    assert_eq!(api.job(&cancelled).await["status"], "cancelled");
    assert_eq!(text(&api, "/v1/balloons/latex-7").await, saved);

    let after = read_events(&api, &running, Some(before.last().unwrap().id), |_| false).await;
    let resumed = after.iter().find(|e| e.kind == "progress").unwrap();
    // From the checkpoint, not from the start (a generation is 9 evaluations).
    assert!(
        resumed.data["evaluations"].as_u64().unwrap() > 17,
        "{resumed:?}"
    );
    assert_eq!(after.last().unwrap().kind, "done");
    let all = read_events(&api, &running, None, |_| false).await;
    assert!(all.iter().enumerate().all(|(i, e)| e.id == i as u64 + 1));
    let job = api
        .wait_for(&queued, &["succeeded", "failed"], Duration::from_secs(120))
        .await;
    assert_eq!(job["status"], "succeeded");

    let again = copy_jobs(&lab, &to);
    assert!(again.starts_with("copied 0 jobs"), "{again}");
    assert!(
        again.ends_with("4 jobs and 1 profile already there, skipped"),
        "{again}"
    );
    drop(served);

    // A store where the key "run-1" already made another job: that job is
    // not copied, and the command fails saying so.
    let other = dir.path().join("other.db");
    let server = Server::with(Options {
        workers: Some(1),
        db: Some(other.clone()),
        ..Options::default()
    });
    submit_with_key(&server.api(), &quick_job(9), "run-1").await;
    drop(server);
    let (ok, stdout, stderr) = run_copy_jobs(&lab, &database_for(&other, None));
    assert!(!ok, "{stdout}");
    assert!(stdout.starts_with("copied 3 jobs"), "{stdout}");
    assert!(stderr.contains("1 job not copied"), "{stderr}");
    assert!(stderr.contains(&done), "{stderr}");
}
