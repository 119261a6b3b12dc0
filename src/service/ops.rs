//! Operations: liveness, readiness, Prometheus metrics, the OpenAPI document.

use std::fmt::Write;
use std::sync::atomic::Ordering;
use std::time::Duration;

use axum::extract::State;
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde_json::json;

use super::problem::Problem;
use super::state::AppState;
use super::store::STATUSES;

pub const OPENAPI: &str = include_str!("../../openapi.yaml");

pub async fn healthz() -> Response {
    axum::Json(json!({"status": "ok"})).into_response()
}

/// Ready when the database answers and the server is not shutting down.
pub async fn readyz(State(state): State<AppState>) -> Response {
    if state.shutting_down.load(Ordering::Relaxed) {
        return Problem::new(StatusCode::SERVICE_UNAVAILABLE, "shutting down").into_response();
    }
    // A database that went away can leave a connection waiting: give the
    // answer within two seconds either way.
    let ping = tokio::time::timeout(Duration::from_secs(2), state.store.ping());
    if !ping.await.unwrap_or(false) {
        return Problem::new(
            StatusCode::SERVICE_UNAVAILABLE,
            "the database does not answer",
        )
        .into_response();
    }
    axum::Json(json!({"status": "ready", "workers": state.config.workers})).into_response()
}

pub async fn openapi() -> Response {
    ([(header::CONTENT_TYPE, "application/yaml")], OPENAPI).into_response()
}

/// Prometheus text exposition format 0.0.4.
pub async fn metrics(State(state): State<AppState>) -> Result<Response, Problem> {
    let by_status = state.store.count_by_status().await?;
    let count = |status: &str| {
        by_status
            .iter()
            .find(|(s, _)| s == status)
            .map_or(0, |(_, n)| *n)
    };
    let c = &state.counters;
    let mut out = String::new();
    let mut metric = |name: &str, kind: &str, help: &str, lines: Vec<(String, f64)>| {
        let _ = writeln!(out, "# HELP {name} {help}\n# TYPE {name} {kind}");
        for (labels, value) in lines {
            let _ = writeln!(out, "{name}{labels} {value}");
        }
    };
    metric(
        "patchwork_queue_depth",
        "gauge",
        "Jobs waiting for a worker.",
        vec![(String::new(), count("queued") as f64)],
    );
    metric(
        "patchwork_jobs",
        "gauge",
        "Jobs in the store by status.",
        STATUSES
            .iter()
            .map(|s| (format!("{{status=\"{s}\"}}"), count(s) as f64))
            .collect(),
    );
    metric(
        "patchwork_workers",
        "gauge",
        "Design workers of this node.",
        vec![(String::new(), state.config.workers as f64)],
    );
    let running_here = state.running.lock().map_or(0, |r| r.len());
    metric(
        "patchwork_node_running_jobs",
        "gauge",
        "Jobs this node's workers are running.",
        vec![(String::new(), running_here as f64)],
    );
    for (name, help, counter) in [
        (
            "patchwork_claims_total",
            "Jobs this node's workers claimed (a resumed job counts again).",
            &c.claims,
        ),
        (
            "patchwork_takeovers_total",
            "Claims of jobs whose previous holder's lease had run out (its node died).",
            &c.takeovers,
        ),
        (
            "patchwork_leases_lost_total",
            "Runs this node stopped because another worker had claimed the job.",
            &c.leases_lost,
        ),
    ] {
        metric(
            name,
            "counter",
            help,
            vec![(String::new(), counter.load(Ordering::Relaxed) as f64)],
        );
    }
    metric(
        "patchwork_evaluations_total",
        "counter",
        "Forward evaluations by design jobs since the server started.",
        vec![(
            String::new(),
            c.forward_solves.load(Ordering::Relaxed) as f64,
        )],
    );
    for (name, help, timings) in [
        (
            "patchwork_job_seconds",
            "Wall time of design job runs in this process.",
            &c.jobs,
        ),
        (
            "patchwork_simulate_seconds",
            "Wall time of synchronous forward solves (POST /v1/simulate).",
            &c.simulate,
        ),
    ] {
        // A summary without quantiles: the `_sum` and `_count` series.
        metric(
            name,
            "summary",
            help,
            vec![
                ("_sum".to_string(), timings.seconds()),
                ("_count".to_string(), timings.count() as f64),
            ],
        );
    }
    Ok(([(header::CONTENT_TYPE, "text/plain; version=0.0.4")], out).into_response())
}
