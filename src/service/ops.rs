//! Operations: liveness, readiness, Prometheus metrics, the OpenAPI document.

use std::fmt::Write;
use std::sync::atomic::Ordering;
use std::time::Duration;

use axum::extract::State;
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde_json::json;

use super::job_state::JobStatus;
use super::problem::Problem;
use super::state::AppState;

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

/// Prometheus text exposition format 0.0.4: the store's jobs, then this
/// node's workers and counters.
pub async fn metrics(State(state): State<AppState>) -> Result<Response, Problem> {
    let by_status = state.store.count_by_status().await?;
    let mut out = Exposition::default();
    job_metrics(&mut out, &by_status);
    node_metrics(&mut out, &state);
    Ok((
        [(header::CONTENT_TYPE, "text/plain; version=0.0.4")],
        out.text,
    )
        .into_response())
}

/// Metric families in the text format.
#[derive(Default)]
struct Exposition {
    text: String,
}

impl Exposition {
    /// A family's HELP and TYPE lines, then one sample per (labels or name
    /// suffix, value).
    fn family(&mut self, name: &str, kind: &str, help: &str, samples: &[(String, f64)]) {
        let _ = writeln!(self.text, "# HELP {name} {help}\n# TYPE {name} {kind}");
        for (labels, value) in samples {
            let _ = writeln!(self.text, "{name}{labels} {value}");
        }
    }

    /// A family of one unlabelled sample.
    fn one(&mut self, name: &str, kind: &str, help: &str, value: f64) {
        self.family(name, kind, help, &[(String::new(), value)]);
    }
}

/// The queue's depth and the jobs by status, from the store.
fn job_metrics(out: &mut Exposition, by_status: &[(JobStatus, i64)]) {
    let count = |status: JobStatus| {
        by_status
            .iter()
            .find(|(s, _)| *s == status)
            .map_or(0, |(_, n)| *n) as f64
    };
    let queued = count(JobStatus::Queued);
    out.one(
        "patchwork_queue_depth",
        "gauge",
        "Jobs waiting for a worker.",
        queued,
    );
    let by_status: Vec<(String, f64)> = JobStatus::ALL
        .iter()
        .map(|&s| (format!("{{status=\"{s}\"}}"), count(s)))
        .collect();
    out.family(
        "patchwork_jobs",
        "gauge",
        "Jobs in the store by status.",
        &by_status,
    );
}

/// This node's workers, the jobs they run, and the counters since start.
fn node_metrics(out: &mut Exposition, state: &AppState) {
    let c = &state.counters;
    let workers = state.config.workers as f64;
    out.one(
        "patchwork_workers",
        "gauge",
        "Design workers of this node.",
        workers,
    );
    let running_here = state.running.lock().map_or(0, |r| r.len()) as f64;
    let help = "Jobs this node's workers are running.";
    out.one("patchwork_node_running_jobs", "gauge", help, running_here);
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
        (
            "patchwork_evaluations_total",
            "Forward evaluations by design jobs since the server started.",
            &c.forward_solves,
        ),
    ] {
        out.one(
            name,
            "counter",
            help,
            counter.load(Ordering::Relaxed) as f64,
        );
    }
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
        let samples = [
            ("_sum".to_string(), timings.seconds()),
            ("_count".to_string(), timings.count() as f64),
        ];
        out.family(name, "summary", help, &samples);
    }
}
