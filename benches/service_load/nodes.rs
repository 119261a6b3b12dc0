//! The servers under test: `patchwork serve` processes on port 0, and the
//! PostgreSQL server they share (the one given, or a throwaway cluster of
//! the bench's own made with `.ci/pg-cluster`).

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use serde_json::Value;

pub struct Node {
    child: Child,
    pub base: String,
}

impl Node {
    /// `patchwork serve --workers N --db DB` on a free port.
    pub fn start(db: &str, workers: usize) -> Node {
        let mut child = Command::new(env!("CARGO_BIN_EXE_patchwork"))
            .args(["serve", "--addr", "127.0.0.1:0", "--db", db])
            .args(["--workers", &workers.to_string()])
            .env("RUST_LOG", "warn")
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("patchwork serve starts");
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let base = line.trim().trim_start_matches("listening on ").to_string();
        assert!(base.starts_with("http://"), "patchwork serve said {line:?}");
        Node { child, base }
    }

    pub fn url(&self, path: &str) -> String {
        format!("{}{path}", self.base)
    }

    /// Submits a job; returns its id.
    pub async fn submit(&self, client: &reqwest::Client, body: &Value) -> String {
        let job = json_of(client.post(self.url("/v1/jobs")).json(body)).await;
        job["id"].as_str().expect("a job id").to_string()
    }

    pub async fn status(&self, client: &reqwest::Client, id: &str) -> String {
        let job = json_of(client.get(self.url(&format!("/v1/jobs/{id}")))).await;
        job["status"].as_str().unwrap_or_default().to_string()
    }

    pub async fn cancel(&self, client: &reqwest::Client, id: &str) {
        let url = self.url(&format!("/v1/jobs/{id}/cancel"));
        let _ = client.post(url).send().await;
    }

    /// The designs running on this node now (`/metrics`).
    pub async fn running(&self, client: &reqwest::Client) -> u64 {
        let text = client
            .get(self.url("/metrics"))
            .send()
            .await
            .unwrap()
            .text()
            .await
            .unwrap();
        text.lines()
            .find_map(|l| l.strip_prefix("patchwork_node_running_jobs "))
            .and_then(|n| n.trim().parse().ok())
            .unwrap_or(0)
    }
}

/// The JSON answer to `request`.
async fn json_of(request: reqwest::RequestBuilder) -> Value {
    request.send().await.unwrap().json().await.unwrap()
}

impl Drop for Node {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A throwaway PostgreSQL cluster (`.ci/pg-cluster`), removed on drop.
pub struct Cluster {
    dir: PathBuf,
    pub url: String,
}

const CLUSTER_SCRIPT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/.ci/pg-cluster");

impl Cluster {
    /// `None` when PostgreSQL's server programs are not installed.
    pub fn start() -> Option<Cluster> {
        let dir = std::env::temp_dir().join(format!("patchwork-bench-pg-{}", std::process::id()));
        let output = Command::new(CLUSTER_SCRIPT)
            .arg("init")
            .arg(&dir)
            .output()
            .ok()?;
        if !output.status.success() {
            eprintln!(
                "no PostgreSQL cluster: {}",
                String::from_utf8_lossy(&output.stderr).trim()
            );
            remove(&dir);
            return None;
        }
        let url = String::from_utf8_lossy(&output.stdout).trim().to_string();
        Some(Cluster { dir, url })
    }
}

fn remove(dir: &Path) {
    let _ = Command::new(CLUSTER_SCRIPT).arg("remove").arg(dir).output();
}

impl Drop for Cluster {
    fn drop(&mut self) {
        remove(&self.dir);
    }
}
