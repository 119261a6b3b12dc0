//! `patchwork serve` settings: command-line flags, an optional TOML config
//! file, and `PATCHWORK_API_KEYS` from the environment.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result};
use clap::Args;
use serde::Deserialize;
use sha2::{Digest, Sha256};

use super::store::Database;

#[derive(Args, Debug)]
pub struct ServeArgs {
    /// Address to listen on (port 0 picks a free port; the chosen address is
    /// printed on the first line of stdout).
    #[arg(long, default_value = "127.0.0.1:8080")]
    pub addr: SocketAddr,
    /// Where jobs are kept: a SQLite file (created and migrated if
    /// missing), or a PostgreSQL database as postgres://USER:PASSWORD@HOST:PORT/DB
    /// (migrated at start; the database must exist).
    #[arg(long, default_value = "./patchwork.db")]
    pub db: String,
    /// Design jobs computed at once (default: one per core); 0 makes an
    /// API-only node of a PostgreSQL database that other nodes work on.
    #[arg(long)]
    pub workers: Option<usize>,
    /// TOML file with `api_keys`, `cors_origins`, `queue_capacity`,
    /// `job_time_limit_s`, `simulate_time_limit_s`, `body_limit_bytes`,
    /// `scan_limit_bytes` (a scan upload's; default 256 MiB),
    /// `lease_s` (how long a running job's hold lasts unrenewed; default 10).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Queued jobs accepted before POST /v1/jobs answers 503.
    #[arg(long)]
    pub queue_capacity: Option<usize>,
    /// Wall-time limit of one design job (seconds).
    #[arg(long)]
    pub job_time_limit_s: Option<u64>,
}

/// The config file's contents; every field optional.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct ConfigFile {
    api_keys: Option<Vec<String>>,
    cors_origins: Option<Vec<String>>,
    workers: Option<usize>,
    queue_capacity: Option<usize>,
    job_time_limit_s: Option<u64>,
    simulate_time_limit_s: Option<u64>,
    body_limit_bytes: Option<usize>,
    scan_limit_bytes: Option<usize>,
    lease_s: Option<u64>,
}

/// Resolved settings.
#[derive(Debug, Clone)]
pub struct Config {
    pub addr: SocketAddr,
    pub db: Database,
    pub workers: usize,
    /// This process among the nodes sharing a database (host and process id).
    pub node: String,
    /// How long a worker's hold on a running job lasts unrenewed: a job whose
    /// node died is claimed again this long after its last renewal.
    pub lease: Duration,
    /// Owners (key digests) allowed; empty = no authentication.
    pub owners: Vec<String>,
    pub cors_origins: Vec<String>,
    pub queue_capacity: usize,
    pub job_time_limit: Duration,
    pub simulate_time_limit: Duration,
    pub body_limit_bytes: usize,
    /// The largest scan `POST /v1/jobs/{id}/compare/scan` takes (bytes).
    pub scan_limit_bytes: usize,
}

impl Config {
    pub fn resolve(args: &ServeArgs) -> Result<Config> {
        let file = match &args.config {
            Some(path) => {
                let text = std::fs::read_to_string(path)
                    .with_context(|| format!("cannot read {}", path.display()))?;
                toml::from_str::<ConfigFile>(&text)
                    .with_context(|| format!("{}: invalid config", path.display()))?
            }
            None => ConfigFile::default(),
        };
        // The environment wins over the file for keys.
        let keys: Vec<String> = match std::env::var("PATCHWORK_API_KEYS") {
            Ok(list) if !list.trim().is_empty() => list
                .split(',')
                .map(|k| k.trim().to_string())
                .filter(|k| !k.is_empty())
                .collect(),
            _ => file.api_keys.unwrap_or_default(),
        };
        let cores = patchwork_core::available_cores();
        let workers = args.workers.or(file.workers).unwrap_or(cores);
        let db = Database::parse(&args.db);
        anyhow::ensure!(
            workers >= 1 || matches!(db, Database::Postgres(_)),
            "--workers 0 (an API-only node) needs a PostgreSQL --db that nodes with workers share"
        );
        let queue_capacity = args.queue_capacity.or(file.queue_capacity).unwrap_or(64);
        anyhow::ensure!(queue_capacity >= 1, "--queue-capacity must be at least 1");
        Ok(Config {
            addr: args.addr,
            db,
            workers,
            node: node_name(),
            lease: Duration::from_secs(file.lease_s.unwrap_or(10).max(1)),
            owners: keys.iter().map(|k| owner_of(k)).collect(),
            cors_origins: file.cors_origins.unwrap_or_default(),
            queue_capacity,
            job_time_limit: Duration::from_secs(
                args.job_time_limit_s
                    .or(file.job_time_limit_s)
                    .unwrap_or(3600),
            ),
            simulate_time_limit: Duration::from_secs(file.simulate_time_limit_s.unwrap_or(20)),
            body_limit_bytes: file.body_limit_bytes.unwrap_or(8 << 20),
            scan_limit_bytes: file.scan_limit_bytes.unwrap_or(256 << 20),
        })
    }

    pub fn auth_enabled(&self) -> bool {
        !self.owners.is_empty()
    }
}

/// The host's name and this process's id.
fn node_name() -> String {
    let host = std::fs::read_to_string("/etc/hostname")
        .ok()
        .map(|h| h.trim().to_string())
        .filter(|h| !h.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "node".to_string());
    format!("{host}-{}", std::process::id())
}

/// A key's owner id: its SHA-256, hex (keys themselves are never stored).
pub fn owner_of(key: &str) -> String {
    Sha256::digest(key.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}
