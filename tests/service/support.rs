//! A real `patchwork serve` process on port 0 with a fresh database, an HTTP
//! client, a server-sent-events reader, and validation against openapi.yaml
//! (`schema.rs`).
//!
//! The database is a SQLite file, or with `PATCHWORK_TEST_POSTGRES` set to a
//! PostgreSQL server's URL (`.ci/run` starts a throwaway one), a fresh
//! database on that server: the same tests against either backend.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use futures_util::StreamExt;
use serde_json::{Value, json};

pub use crate::schema::assert_schema;

pub struct Server {
    child: Child,
    pub base: String,
    _dir: Option<tempfile::TempDir>,
}

/// A client of a server, with or without an API key.
pub struct Api {
    pub base: String,
    pub client: reqwest::Client,
    key: Option<String>,
}

#[derive(Default, Clone)]
pub struct Options {
    pub keys: Option<&'static str>,
    pub workers: Option<usize>,
    pub queue_capacity: Option<usize>,
    /// Reuse this database (restart tests).
    pub db: Option<PathBuf>,
    /// Contents of a TOML config file passed with --config.
    pub config: Option<&'static str>,
    pub job_time_limit_s: Option<u64>,
    /// Listen here instead of on a free port (restart tests that keep a
    /// client's address).
    pub addr: Option<std::net::SocketAddr>,
    /// A SQLite file whatever the backend under test (SQLite's own migrations).
    pub sqlite: bool,
    /// This PostgreSQL server instead of `PATCHWORK_TEST_POSTGRES`'s (a
    /// test's own cluster, which it restarts).
    pub postgres: Option<String>,
}

/// The `--db` of a server whose SQLite file would be `file`: that file, or
/// on PostgreSQL `server` (by default `PATCHWORK_TEST_POSTGRES`) a database
/// named after it (created the first time; a restarted server finds its
/// jobs again).
pub fn database_for(file: &Path, server: Option<String>) -> String {
    let Some(server) = server.or_else(|| std::env::var("PATCHWORK_TEST_POSTGRES").ok()) else {
        return file.display().to_string();
    };
    use std::hash::{Hash, Hasher};
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    file.hash(&mut hasher);
    let name = format!("patchwork_{:016x}", hasher.finish());
    let psql = |sql: &str| {
        let output = Command::new("psql")
            .args([
                "-X",
                "-q",
                "-t",
                "-A",
                "-v",
                "ON_ERROR_STOP=1",
                &server,
                "-c",
                sql,
            ])
            .output()
            .expect("psql runs (PostgreSQL's client; `.ci/run` installs it)");
        assert!(
            output.status.success(),
            "psql {sql}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        String::from_utf8_lossy(&output.stdout).trim().to_string()
    };
    let exists = psql(&format!(
        "SELECT count(*) FROM pg_database WHERE datname = '{name}'"
    ));
    if exists == "0" {
        psql(&format!("CREATE DATABASE {name}"));
    }
    let base = server.rsplit_once('/').map_or(server.as_str(), |(b, _)| b);
    format!("{base}/{name}")
}

impl Server {
    pub fn start() -> Server {
        Server::with(Options::default())
    }

    pub fn with(options: Options) -> Server {
        let (dir, db) = match &options.db {
            Some(db) => (None, db.clone()),
            None => {
                let dir = tempfile::tempdir().unwrap();
                let db = dir.path().join("patchwork.db");
                (Some(dir), db)
            }
        };
        let log = db.with_extension(format!("{}.log", std::process::id()));
        let database = match options.sqlite {
            true => db.display().to_string(),
            false => database_for(&db, options.postgres.clone()),
        };
        let mut command = Command::new(env!("CARGO_BIN_EXE_patchwork"));
        command
            .args(["serve", "--addr"])
            .arg(
                options
                    .addr
                    .map_or("127.0.0.1:0".to_string(), |a| a.to_string()),
            )
            .arg("--db")
            .arg(&database)
            .args(["--workers", &options.workers.unwrap_or(2).to_string()])
            .env("PATCHWORK_API_KEYS", options.keys.unwrap_or(""))
            .env("RUST_LOG", "info")
            .stdout(Stdio::piped())
            .stderr(
                std::fs::OpenOptions::new()
                    .create(true)
                    .append(true)
                    .open(&log)
                    .unwrap(),
            );
        if let Some(n) = options.queue_capacity {
            command.args(["--queue-capacity", &n.to_string()]);
        }
        if let Some(n) = options.job_time_limit_s {
            command.args(["--job-time-limit-s", &n.to_string()]);
        }
        if let Some(text) = options.config {
            let path = db.with_extension("toml");
            std::fs::write(&path, text).unwrap();
            command.arg("--config").arg(path);
        }
        let mut child = command.spawn().expect("patchwork serve starts");
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let base = line
            .trim()
            .strip_prefix("listening on ")
            .unwrap_or_else(|| panic!("unexpected first line {line:?}; log in {}", log.display()))
            .to_string();
        Server {
            child,
            base,
            _dir: dir,
        }
    }

    /// A client without an API key.
    pub fn api(&self) -> Api {
        Api {
            base: self.base.clone(),
            client: reqwest::Client::new(),
            key: None,
        }
    }

    /// A client sending `Authorization: Bearer <key>`.
    pub fn as_key(&self, key: &str) -> Api {
        Api {
            key: Some(key.to_string()),
            ..self.api()
        }
    }

    /// Sends SIGKILL: no shutdown, no checkpoint beyond the last one.
    pub fn kill_hard(&mut self) {
        self.child.kill().unwrap();
        self.child.wait().unwrap();
    }

    /// Sends SIGTERM and waits for the process to exit.
    pub fn terminate(&mut self) -> std::process::ExitStatus {
        Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status()
            .unwrap();
        self.child.wait().unwrap()
    }
}

impl Api {
    pub fn url(&self, path: &str) -> String {
        format!("{}{}", self.base, path)
    }

    pub fn request(&self, method: reqwest::Method, path: &str) -> reqwest::RequestBuilder {
        let builder = self.client.request(method, self.url(path));
        match &self.key {
            Some(key) => builder.bearer_auth(key),
            None => builder,
        }
    }

    pub async fn get(&self, path: &str) -> reqwest::Response {
        self.request(reqwest::Method::GET, path)
            .send()
            .await
            .unwrap()
    }

    pub async fn post(&self, path: &str, body: &Value) -> reqwest::Response {
        self.request(reqwest::Method::POST, path)
            .json(body)
            .send()
            .await
            .unwrap()
    }

    /// `POST /v1/jobs` with an `Idempotency-Key`.
    pub async fn submit_keyed(&self, body: &Value, key: &str) -> reqwest::Response {
        self.request(reqwest::Method::POST, "/v1/jobs")
            .header("Idempotency-Key", key)
            .json(body)
            .send()
            .await
            .unwrap()
    }

    /// Submits a job; returns its id.
    pub async fn submit(&self, body: &Value) -> String {
        let response = self.post("/v1/jobs", body).await;
        assert_eq!(response.status(), 202, "{:?}", response.text().await);
        let job: Value = response.json().await.unwrap();
        job["id"].as_str().unwrap().to_string()
    }

    pub async fn job(&self, id: &str) -> Value {
        self.get(&format!("/v1/jobs/{id}"))
            .await
            .json()
            .await
            .unwrap()
    }

    /// Polls until the job's status is one of `states`.
    pub async fn wait_for(&self, id: &str, states: &[&str], limit: Duration) -> Value {
        let started = Instant::now();
        loop {
            let job = self.job(id).await;
            if states.contains(&job["status"].as_str().unwrap_or("")) {
                return job;
            }
            assert!(started.elapsed() < limit, "job stuck: {job}");
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A job that finishes in about a second: one patch on a 90° arc, draft
/// fidelity, a small budget.
pub fn quick_job(budget: usize) -> Value {
    json!({
        "curve": {"preset": "arc", "params": {"radius_mm": 40, "angle_deg": 90}},
        "options": {"budget": budget, "seed": 3, "fidelity": "draft"}
    })
}

/// A job that stops after its seed stage (a time limit of 1 ms): KSA's
/// design, verified, in about a third of a second.
pub fn seed_only_job() -> Value {
    json!({
        "curve": {"preset": "arc", "params": {"radius_mm": 40, "angle_deg": 90}},
        "options": {"seed": 3, "fidelity": "draft", "time_limit_s": 0.001}
    })
}

/// A job that runs for about 20 ms per evaluation (a part-turn helix),
/// spends its whole budget in the search (no early end when it stalls) and
/// then refines nothing.
pub fn long_job(budget: usize) -> Value {
    json!({
        "curve": {"preset": "helix", "params": {"radius_mm": 15, "pitch_mm": 40, "turns": 0.6}},
        "options": {"budget": budget, "seed": 5, "fidelity": "draft"},
        "tuning": {"search_patience": 0, "refine_budget": 0}
    })
}

#[derive(Debug, Clone)]
pub struct SseEvent {
    pub id: u64,
    pub kind: String,
    pub data: Value,
}

/// Reads a job's event stream until it ends, or until `stop` says so.
pub async fn read_events(
    server: &Api,
    id: &str,
    last_event_id: Option<u64>,
    stop: impl Fn(&SseEvent) -> bool,
) -> Vec<SseEvent> {
    let mut request = server.request(reqwest::Method::GET, &format!("/v1/jobs/{id}/events"));
    if let Some(last) = last_event_id {
        request = request.header("Last-Event-ID", last.to_string());
    }
    let response = request.send().await.unwrap();
    assert_eq!(response.status(), 200);
    assert!(
        response.headers()["content-type"]
            .to_str()
            .unwrap()
            .starts_with("text/event-stream")
    );
    let mut stream = response.bytes_stream();
    let mut buffer = String::new();
    let mut events = Vec::new();
    let read = async {
        while let Some(chunk) = stream.next().await {
            buffer.push_str(&String::from_utf8_lossy(&chunk.unwrap()));
            while let Some(end) = buffer.find("\n\n") {
                let block: String = buffer.drain(..end + 2).collect();
                if let Some(event) = parse_block(&block) {
                    let done = stop(&event);
                    events.push(event);
                    if done {
                        return;
                    }
                }
            }
        }
    };
    tokio::time::timeout(Duration::from_secs(120), read)
        .await
        .expect("event stream ended in time");
    events
}

fn parse_block(block: &str) -> Option<SseEvent> {
    let (mut id, mut kind, mut data) = (None, None, String::new());
    for line in block.lines() {
        if let Some(v) = line.strip_prefix("id:") {
            id = v.trim().parse().ok();
        } else if let Some(v) = line.strip_prefix("event:") {
            kind = Some(v.trim().to_string());
        } else if let Some(v) = line.strip_prefix("data:") {
            data.push_str(v.trim());
        }
    }
    Some(SseEvent {
        id: id?,
        kind: kind?,
        data: serde_json::from_str(&data).ok()?,
    })
}

/// Asserts a problem+json response with `status`, naming `field` when given.
pub async fn assert_problem(
    response: reqwest::Response,
    status: u16,
    field: Option<&str>,
) -> Value {
    assert_eq!(response.status().as_u16(), status);
    assert_eq!(
        response.headers()["content-type"],
        "application/problem+json"
    );
    let problem: Value = response.json().await.unwrap();
    assert_schema("Problem", &problem);
    assert_eq!(problem["status"], status);
    if let Some(field) = field {
        assert_eq!(problem["field"], field, "{problem}");
    }
    problem
}

/// ezdxf's audit error count for a DXF held in memory.
pub fn ezdxf_errors(bytes: &[u8]) -> usize {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("file.dxf");
    std::fs::write(&path, bytes).unwrap();
    crate::common::ezdxf_errors(&path)
}
