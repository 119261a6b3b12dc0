//! The measurements: paced status requests, claim and cancel latencies, and
//! SSE fan-out, each over every node of the deployment under test.

use std::time::{Duration, Instant};

use futures_util::StreamExt;

use crate::nodes::Node;

pub const RATE: u64 = 500;
pub const WINDOW: Duration = Duration::from_secs(5);

/// One window of paced status requests.
pub struct Window {
    pub requests: usize,
    pub achieved_per_s: f64,
    pub errors: usize,
    pub p50_ms: f64,
    pub p99_ms: f64,
    pub max_ms: f64,
}

/// The `q` quantile of `values` (nearest rank); NaN when there are none.
pub fn quantile(values: &[f64], q: f64) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    match sorted.len() {
        0 => f64::NAN,
        n => sorted[((n - 1) as f64 * q).round() as usize],
    }
}

/// `GET /v1/jobs/{id}` at a fixed rate, the requests taking the nodes in
/// turn (as a load balancer would), each issued on schedule whether or not
/// earlier ones have answered, so slow answers show up as latency.
pub async fn paced_status(client: &reqwest::Client, nodes: &[Node], id: &str) -> Window {
    let total = RATE * WINDOW.as_secs();
    let mut ticker = tokio::time::interval(Duration::from_micros(1_000_000 / RATE));
    ticker.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Burst);
    let started = Instant::now();
    let mut handles = Vec::with_capacity(total as usize);
    for i in 0..total as usize {
        ticker.tick().await;
        let client = client.clone();
        let url = nodes[i % nodes.len()].url(&format!("/v1/jobs/{id}"));
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
        match handle.await.unwrap() {
            (ms, true) => latencies.push(ms),
            _ => errors += 1,
        }
    }
    Window {
        requests: latencies.len() + errors,
        achieved_per_s: latencies.len() as f64 / started.elapsed().as_secs_f64(),
        errors,
        p50_ms: quantile(&latencies, 0.5),
        p99_ms: quantile(&latencies, 0.99),
        max_ms: quantile(&latencies, 1.0),
    }
}

/// Milliseconds from the answer to `POST /v1/jobs` (the job is stored,
/// queued) until the job is seen claimed, polling its status every
/// millisecond through the node it was submitted to; then waits for it to
/// end so the worker is idle again.
pub async fn claim_latency(client: &reqwest::Client, node: &Node, body: &serde_json::Value) -> f64 {
    let id = node.submit(client, body).await;
    let queued = Instant::now();
    while node.status(client, &id).await == "queued" {
        assert!(queued.elapsed() < Duration::from_secs(60), "never claimed");
        tokio::time::sleep(Duration::from_millis(1)).await;
    }
    let claimed = queued.elapsed().as_secs_f64() * 1e3;
    wait_until_ended(client, node, &id).await;
    claimed
}

pub async fn wait_until_ended(client: &reqwest::Client, node: &Node, id: &str) {
    let started = Instant::now();
    while !matches!(
        node.status(client, id).await.as_str(),
        "succeeded" | "failed" | "cancelled"
    ) {
        assert!(
            started.elapsed() < Duration::from_secs(300),
            "job {id} never ended"
        );
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

/// The designs running on each node.
pub async fn running_each(client: &reqwest::Client, nodes: &[Node]) -> Vec<u64> {
    let mut each = Vec::with_capacity(nodes.len());
    for node in nodes {
        each.push(node.running(client).await);
    }
    each
}

/// The designs running on every node together.
pub async fn running(client: &reqwest::Client, nodes: &[Node]) -> u64 {
    running_each(client, nodes).await.iter().sum()
}

/// Submits a long job through `node`, waits until a worker runs it, and
/// returns its id and the index of the node whose worker took it.
pub async fn start_long(
    client: &reqwest::Client,
    nodes: &[Node],
    node: &Node,
    body: &serde_json::Value,
) -> (String, usize) {
    let before = running_each(client, nodes).await;
    let id = node.submit(client, body).await;
    let started = Instant::now();
    loop {
        let now = running_each(client, nodes).await;
        if let Some(holder) = (0..nodes.len()).find(|&i| now[i] > before[i]) {
            return (id, holder);
        }
        assert!(started.elapsed() < Duration::from_secs(60), "never claimed");
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
}

/// Milliseconds from the answer to a cancel sent through `through` until
/// the worker running the job (on any node) has stopped: the nodes' running
/// designs drop from `busy` by one.
pub async fn cancel_latency(
    client: &reqwest::Client,
    nodes: &[Node],
    through: &Node,
    id: &str,
    busy: u64,
) -> f64 {
    through.cancel(client, id).await;
    let cancelled = Instant::now();
    while running(client, nodes).await >= busy {
        assert!(
            cancelled.elapsed() < Duration::from_secs(60),
            "never stopped"
        );
        tokio::time::sleep(Duration::from_millis(2)).await;
    }
    cancelled.elapsed().as_secs_f64() * 1e3
}

/// The ids of every event of one SSE connection, to the end of the stream,
/// each with when it arrived.
pub async fn event_ids(client: &reqwest::Client, url: &str) -> Vec<(u64, Instant)> {
    let response = client.get(url).send().await.unwrap();
    let mut stream = response.bytes_stream();
    let mut buffer = String::new();
    let mut ids = Vec::new();
    while let Some(chunk) = stream.next().await {
        let Ok(chunk) = chunk else { break };
        let arrived = Instant::now();
        buffer.push_str(&String::from_utf8_lossy(&chunk));
        while let Some(end) = buffer.find("\n\n") {
            let block: String = buffer.drain(..end + 2).collect();
            if let Some(id) = block.lines().find_map(|l| l.strip_prefix("id:")) {
                ids.push((id.trim().parse().unwrap(), arrived));
            }
        }
    }
    ids
}

/// For each event, how long after its first client the last one got it
/// (ms): clients on every node, so on PostgreSQL this includes relaying
/// the event to the nodes that do not run the job. Events every client got
/// live only (the first ones, replayed from the store as clients connect,
/// are left out).
pub fn delivery_spread_ms(received: &[Vec<(u64, Instant)>], live_from: u64) -> Vec<f64> {
    let mut spread: std::collections::BTreeMap<u64, (Instant, Instant)> = Default::default();
    for (id, at) in received.iter().flatten() {
        let entry = spread.entry(*id).or_insert((*at, *at));
        entry.0 = entry.0.min(*at);
        entry.1 = entry.1.max(*at);
    }
    spread
        .range(live_from..)
        .map(|(_, (first, last))| (*last - *first).as_secs_f64() * 1e3)
        .collect()
}
