//! Service load benchmark (issue 5): while two design jobs compute, (1) status
//! requests at a paced 500 per second — achieved rate and latency percentiles —
//! and (2) 100 concurrent SSE clients, each of which must receive every event.
//!
//! `cargo bench --bench service_load [-- --out FILE]` (starts `patchwork serve`
//! on port 0 with a fresh database; prints the report's section, and writes it
//! to FILE: `patchwork bench --suite report` includes docs/bench/service.md).

use std::fmt::Write;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use futures_util::StreamExt;
use serde_json::{Value, json};

const RATE: u64 = 500;
const WINDOW: Duration = Duration::from_secs(5);
const WINDOWS: usize = 3;
const SSE_CLIENTS: usize = 100;

fn job(budget: usize, seed: u64) -> Value {
    json!({
        "curve": {"preset": "helix", "params": {"radius_mm": 15, "pitch_mm": 40, "turns": 0.6}},
        "options": {"budget": budget, "seed": seed, "fidelity": "draft"}
    })
}

#[tokio::main(flavor = "multi_thread")]
async fn main() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_patchwork"))
        .args(["serve", "--addr", "127.0.0.1:0", "--workers", "2", "--db"])
        .arg(dir.path().join("bench.db"))
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
    let client = reqwest::Client::builder()
        .pool_max_idle_per_host(256)
        .build()
        .unwrap();

    // Two long jobs keep both workers (both cores) busy.
    let mut busy = Vec::new();
    for seed in [1, 2] {
        busy.push(submit(&client, &base, job(100_000, seed)).await);
    }
    tokio::time::sleep(Duration::from_secs(2)).await;
    let status_url = format!("{base}/v1/jobs/{}", busy[0]);

    let out = std::env::args()
        .skip_while(|a| a != "--out")
        .nth(1)
        .map(std::path::PathBuf::from);
    let mut report = String::new();
    let _ = write!(
        report,
        "Goal: {RATE} status requests per second with p99 under 20 ms while two \
         design jobs compute; {SSE_CLIENTS} SSE clients each get every event.\n\n\
         ```sh\ncargo bench --bench service_load\n```\n\n\
         `patchwork serve --workers 2` (a fresh SQLite file) runs two long design \
         jobs that keep both workers computing, while the bench, on the same \
         machine, sends `GET /v1/jobs/{{id}}` at a paced {RATE} per second (on \
         schedule, whether or not earlier requests have answered) in {WINDOWS} \
         windows of {} s. Then {SSE_CLIENTS} SSE clients follow a fresh job while \
         one long job computes; each client's event ids are compared with the \
         whole stored stream read after the job ended.\n\n\
         | window | requests | achieved req/s | errors | p50 ms | p99 ms | max ms |\n\
         |---|---|---|---|---|---|---|\n",
        WINDOW.as_secs()
    );
    let mut p99s = Vec::new();
    for window in 1..=WINDOWS {
        let (latencies, errors, elapsed) = paced_status_load(&client, &status_url).await;
        let mut sorted = latencies.clone();
        sorted.sort_by(f64::total_cmp);
        let pct = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
        p99s.push(pct(0.99));
        let _ = writeln!(
            report,
            "| {window} | {} | {:.0} | {errors} | {:.2} | {:.2} | {:.2} |",
            latencies.len(),
            latencies.len() as f64 / elapsed,
            pct(0.5),
            pct(0.99),
            pct(1.0)
        );
    }
    p99s.sort_by(f64::total_cmp);
    let _ = writeln!(
        report,
        "\nMedian p99 over the {WINDOWS} windows: **{:.2} ms** (goal < 20 ms).\n",
        p99s[WINDOWS / 2]
    );

    // SSE fan-out: 100 clients on a fresh job while the two long jobs compute
    // (the third job waits for a worker, so cancel one long job first).
    let _ = client
        .post(format!("{base}/v1/jobs/{}/cancel", busy[1]))
        .send()
        .await;
    let id = submit(&client, &base, job(300, 9)).await;
    let started = Instant::now();
    let clients: Vec<_> = (0..SSE_CLIENTS)
        .map(|_| {
            let client = client.clone();
            let url = format!("{base}/v1/jobs/{id}/events");
            tokio::spawn(async move { event_ids(&client, &url).await })
        })
        .collect();
    let mut received = Vec::new();
    for handle in clients {
        received.push(handle.await.unwrap());
    }
    let elapsed = started.elapsed().as_secs_f64();
    // The reference: the whole stored stream, read after the job ended.
    let reference = event_ids(&client, &format!("{base}/v1/jobs/{id}/events")).await;
    let complete = received.iter().filter(|ids| **ids == reference).count();
    let _ = writeln!(
        report,
        "SSE: **{complete}/{SSE_CLIENTS}** clients received all {} events (ids 1..={}) of a {elapsed:.1} s job.",
        reference.len(),
        reference.last().copied().unwrap_or(0)
    );
    let _ = client
        .post(format!("{base}/v1/jobs/{}/cancel", busy[0]))
        .send()
        .await;
    let _ = child.kill();
    let _ = child.wait();
    print!("{report}");
    if let Some(path) = out {
        std::fs::write(&path, &report).expect("the --out file can be written");
    }
}

/// Submits a job; returns its id.
async fn submit(client: &reqwest::Client, base: &str, body: Value) -> String {
    let job: Value = client
        .post(format!("{base}/v1/jobs"))
        .json(&body)
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    job["id"].as_str().unwrap().to_string()
}

/// GET status at a fixed rate (requests are issued on schedule whether or not
/// earlier ones have answered, so slow answers show up as latency).
async fn paced_status_load(client: &reqwest::Client, url: &str) -> (Vec<f64>, usize, f64) {
    let total = RATE * WINDOW.as_secs();
    let mut ticker = tokio::time::interval(Duration::from_micros(1_000_000 / RATE));
    ticker.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Burst);
    let started = Instant::now();
    let mut handles = Vec::with_capacity(total as usize);
    for _ in 0..total {
        ticker.tick().await;
        let client = client.clone();
        let url = url.to_string();
        handles.push(tokio::spawn(async move {
            let sent = Instant::now();
            let ok = match client.get(&url).send().await {
                Ok(r) => r.status().is_success() && r.bytes().await.is_ok(),
                Err(_) => false,
            };
            (sent.elapsed().as_secs_f64() * 1e3, ok)
        }));
    }
    let mut latencies = Vec::with_capacity(handles.len());
    let mut errors = 0;
    for handle in handles {
        let (ms, ok) = handle.await.unwrap();
        if ok {
            latencies.push(ms);
        } else {
            errors += 1;
        }
    }
    (latencies, errors, started.elapsed().as_secs_f64())
}

/// The ids of every event of one SSE connection, to the end of the stream.
async fn event_ids(client: &reqwest::Client, url: &str) -> Vec<u64> {
    let response = client.get(url).send().await.unwrap();
    let mut stream = response.bytes_stream();
    let mut buffer = String::new();
    let mut ids = Vec::new();
    while let Some(chunk) = stream.next().await {
        let Ok(chunk) = chunk else { break };
        buffer.push_str(&String::from_utf8_lossy(&chunk));
        while let Some(end) = buffer.find("\n\n") {
            let block: String = buffer.drain(..end + 2).collect();
            if let Some(id) = block.lines().find_map(|l| l.strip_prefix("id:")) {
                ids.push(id.trim().parse().unwrap());
            }
        }
    }
    ids
}
