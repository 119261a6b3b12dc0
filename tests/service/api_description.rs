//! Schemathesis (PyPI; `.ci/run` installs it) against the openapi.yaml the
//! server serves: every check, every phase (examples, coverage, fuzzing and
//! the stateful phase that follows the description's links from a created
//! job to its routes), with the hooks in `tests/schemathesis` for the rules
//! that join fields. Passes when schemathesis reports no failure and no
//! error, and every operation of the description was called.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Command;

use serde_json::Value;

use crate::support::*;

/// Requests per operation and phase: enough to reach every branch of the
/// description (the coverage phase adds its boundary cases on top).
const MAX_EXAMPLES: &str = "25";

#[test]
fn the_served_description_holds_under_schemathesis() {
    // Jobs that schemathesis creates run a second at most, four at a time,
    // so that a job's event stream (open until the job ends) answers soon;
    // a simulation stops after 5 s, within schemathesis' 10 s response time.
    let server = Server::with(Options {
        workers: Some(4),
        job_time_limit_s: Some(1),
        queue_capacity: Some(100_000),
        config: Some("simulate_time_limit_s = 5"),
        ..Options::default()
    });
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report.ndjson");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let output = Command::new("python3")
        .args(["-m", "schemathesis.cli", "--config-file"])
        .arg(root.join("tests/schemathesis/schemathesis.toml"))
        .args(["run", &format!("{}/openapi.yaml", server.base)])
        .args(["--checks", "all", "--max-examples", MAX_EXAMPLES])
        .args(["--seed", "1", "--request-timeout", "60"])
        .args(["--report", "ndjson", "--report-ndjson-path"])
        .arg(&report)
        .env("PYTHONPATH", root.join("tests/schemathesis"))
        .env("SCHEMATHESIS_HOOKS", "hooks")
        .env("NO_COLOR", "1")
        // Schemathesis keeps a cache in its working folder: not the clone.
        .current_dir(dir.path())
        .output()
        .expect("python3 runs (schemathesis: `.ci/run` installs it)");
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "schemathesis failed:\n{text}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let events: Vec<Value> = std::fs::read_to_string(&report)
        .unwrap()
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    let described = described_operations();
    let mut answered = answered_operations(&events, &described);
    // Schemathesis leaves the route of the description it loaded out of the
    // operations it tests: loading it was that route's call.
    let loaded = events.iter().any(|e| e.get("LoadingFinished").is_some());
    assert!(loaded, "schemathesis did not load the description\n{text}");
    answered
        .entry(("GET".into(), "/openapi.yaml".into()))
        .or_default()
        .insert(200);
    let missed: Vec<_> = described
        .iter()
        .filter(|op| !answered.contains_key(*op))
        .collect();
    assert!(missed.is_empty(), "never called: {missed:?}\n{text}");
    let stateful = events
        .iter()
        .filter_map(|e| e.get("ScenarioFinished"))
        .any(|s| {
            s["phase"] == "stateful"
                && s["status"] == "success"
                && s["recorder"]["interactions"]
                    .as_object()
                    .is_some_and(|i| !i.is_empty())
        });
    assert!(stateful, "the stateful phase ran no scenario\n{text}");
}

/// `(METHOD, /path/{template})` of every operation in the description (the
/// file the server embeds and serves).
fn described_operations() -> BTreeSet<(String, String)> {
    let mut operations = BTreeSet::new();
    for (path, item) in crate::schema::spec()["paths"].as_object().unwrap() {
        for method in item.as_object().unwrap().keys() {
            if ["get", "post", "put", "patch", "delete"].contains(&method.as_str()) {
                operations.insert((method.to_uppercase(), path.clone()));
            }
        }
    }
    operations
}

/// The statuses each described operation answered in schemathesis' event
/// log (every recorded request, matched to its operation by method and path).
fn answered_operations(
    events: &[Value],
    described: &BTreeSet<(String, String)>,
) -> BTreeMap<(String, String), BTreeSet<u64>> {
    let mut answered: BTreeMap<_, BTreeSet<u64>> = BTreeMap::new();
    let interactions = events
        .iter()
        .filter_map(|e| e.get("ScenarioFinished"))
        .filter_map(|s| s["recorder"]["interactions"].as_object())
        .flat_map(|i| i.values());
    for interaction in interactions {
        let (request, response) = (&interaction["request"], &interaction["response"]);
        let (Some(method), Some(uri), Some(status)) = (
            request["method"].as_str(),
            request["uri"].as_str(),
            response["status_code"].as_u64(),
        ) else {
            continue;
        };
        let path = uri.split("://").nth(1).unwrap_or(uri);
        let path = &path[path.find('/').unwrap_or(path.len())..];
        let path = path.split('?').next().unwrap_or(path);
        if let Some(op) = described
            .iter()
            .find(|(m, template)| m == method && matches(template, path))
        {
            answered.entry(op.clone()).or_default().insert(status);
        }
    }
    answered
}

/// Whether `path` is an instance of the path template (`{id}` matches one
/// non-empty segment).
fn matches(template: &str, path: &str) -> bool {
    let (t, p): (Vec<_>, Vec<_>) = (template.split('/').collect(), path.split('/').collect());
    t.len() == p.len()
        && t.iter().zip(&p).all(|(t, p)| match t.starts_with('{') {
            true => !p.is_empty(),
            false => t == p,
        })
}
