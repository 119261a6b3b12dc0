//! Service load benchmark, on each job store: SQLite (one node, two workers)
//! and PostgreSQL (two nodes sharing one database, one worker each). On
//! each: the claim latency (queued → running) with a worker idle; the
//! cancel latency (the cancel answered → the worker stopped, through the
//! other node where there are two); status requests at a paced 500 per
//! second while two designs compute, over every node; and 100 SSE clients
//! spread over the nodes, each of which must receive every event.
//!
//! `cargo bench --bench service_load [-- --out FILE] [--postgres URL]`
//! starts the nodes on port 0. PostgreSQL is the server at URL (an empty
//! database the bench may fill) or, by default, a throwaway cluster of its
//! own (`.ci/pg-cluster`; skipped, and said so, when PostgreSQL is not
//! installed). Prints the report's section and writes it to FILE
//! (`patchwork bench --suite report` includes docs/bench/service.md).

mod load;
mod nodes;

use std::fmt::Write;
use std::time::Instant;

use serde_json::{Value, json};

use load::{RATE, WINDOW, Window, quantile};
use nodes::{Cluster, Node};

const WINDOWS: usize = 3;
const SSE_CLIENTS: usize = 100;
const CLAIMS: usize = 20;
const CANCELS: usize = 6;
/// The first event id of the SSE job counted as live (the queued and seed
/// stages come before every client is connected).
const LIVE_FROM: u64 = 5;

/// A design that spends its whole budget (no early end when the search
/// stalls), about 20 ms per evaluation.
fn job(budget: usize, seed: u64) -> Value {
    json!({
        "curve": {"preset": "helix", "params": {"radius_mm": 15, "pitch_mm": 40, "turns": 0.6}},
        "options": {"budget": budget, "seed": seed, "fidelity": "draft"},
        "tuning": {"search_patience": 0}
    })
}

/// A design of about a second (one patch on a 90° arc).
fn quick_job(seed: u64) -> Value {
    json!({
        "curve": {"preset": "arc", "params": {"radius_mm": 40, "angle_deg": 90}},
        "options": {"budget": 5, "seed": seed, "fidelity": "draft"}
    })
}

/// What one deployment measured.
struct Figures {
    windows: Vec<Window>,
    claim_ms: Vec<f64>,
    cancel_ms: Vec<f64>,
    sse_complete: usize,
    sse_events: usize,
    sse_job_s: f64,
    /// Per live event: the last client's receipt after the first's, ms.
    sse_spread_ms: Vec<f64>,
}

#[tokio::main(flavor = "multi_thread")]
async fn main() {
    let argument = |name: &str| std::env::args().skip_while(|a| a != name).nth(1);
    let client = reqwest::Client::builder()
        .pool_max_idle_per_host(256)
        .build()
        .unwrap();

    let dir = tempfile::tempdir().unwrap();
    let sqlite = dir.path().join("bench.db").display().to_string();
    let sqlite = measure(&client, &[Node::start(&sqlite, 2)]).await;

    let cluster = match argument("--postgres") {
        Some(_) => None,
        None => Cluster::start(),
    };
    let url = argument("--postgres").or_else(|| cluster.as_ref().map(|c| c.url.clone()));
    let postgres = match &url {
        Some(url) => Some(measure(&client, &[Node::start(url, 1), Node::start(url, 1)]).await),
        None => None,
    };
    drop(cluster);

    let report = report(&sqlite, postgres.as_ref());
    print!("{report}");
    if let Some(path) = argument("--out") {
        std::fs::write(&path, &report).expect("the --out file can be written");
    }
}

/// Every measurement on one deployment: one worker busy with a long design
/// throughout, the other free for the claims and cancels, then busy too
/// for the status load, then following the SSE clients' job.
async fn measure(client: &reqwest::Client, nodes: &[Node]) -> Figures {
    let other = |i: usize| &nodes[(i + 1) % nodes.len()];
    let (first, _) = load::start_long(client, nodes, &nodes[0], &job(100_000, 1)).await;
    let mut claim_ms = Vec::new();
    for i in 0..CLAIMS {
        let node = &nodes[i % nodes.len()];
        claim_ms.push(load::claim_latency(client, node, &quick_job(i as u64)).await);
    }
    let mut cancel_ms = Vec::new();
    for i in 0..CANCELS {
        let node = &nodes[i % nodes.len()];
        let (id, holder) = load::start_long(client, nodes, node, &job(100_000, 2)).await;
        // At a spread of moments after the claim (not in step with the lease
        // renewals), through a node other than the one running the job,
        // where there is one.
        let delay = (i as u64 * 397) % 1000;
        tokio::time::sleep(std::time::Duration::from_millis(delay)).await;
        cancel_ms.push(load::cancel_latency(client, nodes, other(holder), &id, 2).await);
    }

    let second = other(0).submit(client, &job(100_000, 2)).await;
    tokio::time::sleep(std::time::Duration::from_secs(2)).await;
    let mut windows = Vec::new();
    for _ in 0..WINDOWS {
        windows.push(load::paced_status(client, nodes, &first).await);
    }

    other(0).cancel(client, &second).await;
    let (sse_complete, sse_events, sse_job_s, sse_spread_ms) = fan_out(client, nodes).await;
    nodes[0].cancel(client, &first).await;
    Figures {
        windows,
        claim_ms,
        cancel_ms,
        sse_complete,
        sse_events,
        sse_job_s,
        sse_spread_ms,
    }
}

/// SSE clients spread over the nodes follow a fresh job while a long one
/// computes; returns how many received the whole stored stream (read after
/// the job ended), its length, the job's seconds, and how long after its
/// first client each live event reached the last.
async fn fan_out(client: &reqwest::Client, nodes: &[Node]) -> (usize, usize, f64, Vec<f64>) {
    let id = nodes[0].submit(client, &job(300, 9)).await;
    let started = Instant::now();
    let clients: Vec<_> = (0..SSE_CLIENTS)
        .map(|i| {
            let client = client.clone();
            let url = nodes[i % nodes.len()].url(&format!("/v1/jobs/{id}/events"));
            tokio::spawn(async move { load::event_ids(&client, &url).await })
        })
        .collect();
    let mut received = Vec::new();
    for handle in clients {
        received.push(handle.await.unwrap());
    }
    let elapsed = started.elapsed().as_secs_f64();
    let url = nodes[0].url(&format!("/v1/jobs/{id}/events"));
    let reference: Vec<u64> = load::event_ids(client, &url)
        .await
        .iter()
        .map(|(id, _)| *id)
        .collect();
    let ids = |events: &Vec<(u64, Instant)>| events.iter().map(|(id, _)| *id).collect::<Vec<_>>();
    let complete = received.iter().filter(|r| ids(r) == reference).count();
    // Clients are connected well before the search's progress events.
    let spread = load::delivery_spread_ms(&received, LIVE_FROM);
    (complete, reference.len(), elapsed, spread)
}

fn report(sqlite: &Figures, postgres: Option<&Figures>) -> String {
    let mut r = String::new();
    let _ = write!(
        r,
        "Goals: {RATE} status requests per second with p99 under 20 ms while designs \
         compute; a queued job claimed within 100 ms by an idle worker; a cancel \
         through any node stops the run within 2 s; {SSE_CLIENTS} SSE clients each get \
         every event.\n\n\
         ```sh\ncargo bench --bench service_load\n```\n\n\
         Two deployments on this machine: SQLite, one `patchwork serve --workers 2`; \
         PostgreSQL, two `patchwork serve --workers 1` sharing one database (a \
         local throwaway cluster). On each, one worker computes a long design \
         throughout. Claim: {CLAIMS} short jobs, one at a time, submitted through the \
         nodes in turn; the time from `POST /v1/jobs`'s answer until the job's status \
         (polled every millisecond) is no longer `queued`. Cancel: {CANCELS} long jobs, \
         each cancelled once running, through the node that does not run it where there \
         are two; \
         the time from the cancel's answer until the nodes' `/metrics` count one \
         running design fewer. Status: with a second long design running, \
         `GET /v1/jobs/{{id}}` at a paced {RATE} per second (on schedule, whether or not \
         earlier requests have answered), taking the nodes in turn, in {WINDOWS} windows \
         of {} s. SSE: {SSE_CLIENTS} clients spread over the nodes follow a fresh job; \
         each client's event ids are compared with the whole stored stream read after \
         the job ended, and for each live event (id {LIVE_FROM} on) the time from its \
         first client's receipt to its last's is taken: on PostgreSQL half the clients \
         are on the node that does not run the job, so this includes relaying the \
         event across nodes.\n\n",
        WINDOW.as_secs()
    );
    let columns = [Some(sqlite), postgres];
    let row = |r: &mut String, label: &str, cell: &dyn Fn(&Figures) -> String| {
        let cells: Vec<String> = columns
            .iter()
            .map(|f| f.map_or("not run".to_string(), cell))
            .collect();
        let _ = writeln!(r, "| {label} | {} |", cells.join(" | "));
    };
    r.push_str("| | SQLite, one node | PostgreSQL, two nodes |\n|---|---|---|\n");
    row(&mut r, "claim: queued → running, median / max ms", &|f| {
        format!(
            "{:.1} / {:.1}",
            quantile(&f.claim_ms, 0.5),
            quantile(&f.claim_ms, 1.0)
        )
    });
    row(&mut r, "cancel → run stopped, median / max ms", &|f| {
        format!(
            "{:.0} / {:.0}",
            quantile(&f.cancel_ms, 0.5),
            quantile(&f.cancel_ms, 1.0)
        )
    });
    row(&mut r, "status: requests, errors, achieved req/s", &|f| {
        let requests: usize = f.windows.iter().map(|w| w.requests).sum();
        let errors: usize = f.windows.iter().map(|w| w.errors).sum();
        let rate = f.windows.iter().map(|w| w.achieved_per_s).sum::<f64>() / WINDOWS as f64;
        format!("{requests}, {errors}, {rate:.0}")
    });
    row(&mut r, "status p50 / p99 / max ms, per window", &|f| {
        let each: Vec<String> = f
            .windows
            .iter()
            .map(|w| format!("{:.2} / {:.2} / {:.1}", w.p50_ms, w.p99_ms, w.max_ms))
            .collect();
        each.join("; ")
    });
    row(&mut r, "status p99, median of windows, ms", &|f| {
        format!("{:.2}", median_p99(f))
    });
    row(&mut r, "SSE clients with every event", &|f| {
        format!(
            "{}/{SSE_CLIENTS} ({} events, {:.1} s job)",
            f.sse_complete, f.sse_events, f.sse_job_s
        )
    });
    row(
        &mut r,
        "SSE: last client after the first, median / max ms",
        &|f| {
            let spread = &f.sse_spread_ms;
            format!(
                "{:.1} / {:.1}",
                quantile(spread, 0.5),
                quantile(spread, 1.0)
            )
        },
    );
    if postgres.is_none() {
        r.push_str("\nPostgreSQL was not measured: its server programs are not installed.\n");
    }
    // The report's headline takes the two bold parts of this line.
    let short = |f: Option<&Figures>| {
        f.map_or("not run".to_string(), |f| {
            format!(
                "status p99 {:.2} ms, claims ≤ {:.0} ms, cancels ≤ {:.0} ms, SSE {}/{SSE_CLIENTS} \
                 with each event at every client ≤ {:.0} ms after the first",
                median_p99(f),
                quantile(&f.claim_ms, 1.0),
                quantile(&f.cancel_ms, 1.0),
                f.sse_complete,
                quantile(&f.sse_spread_ms, 1.0)
            )
        })
    };
    let _ = writeln!(
        r,
        "\nIn short — SQLite: **{}**; PostgreSQL, two nodes: **{}**.",
        short(Some(sqlite)),
        short(postgres)
    );
    r
}

fn median_p99(f: &Figures) -> f64 {
    let p99: Vec<f64> = f.windows.iter().map(|w| w.p99_ms).collect();
    quantile(&p99, 0.5)
}
