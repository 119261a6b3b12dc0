//! `patchwork copy-jobs`: every job of one job store into another — from a
//! SQLite file into PostgreSQL when a lab outgrows one machine, or back.
//! Each job goes with its events, iterations and result files, in one
//! transaction; a job the destination already has is skipped, so a copy
//! that stopped half-way can simply be run again. The balloon profiles go
//! too; one whose key already has a profile of its name there is kept as
//! the destination has it. A job whose idempotency
//! key another job of the destination already holds is not copied, and
//! the command says so and fails. The source is read, never
//! changed (apart from migrating it, as `serve` would).

use anyhow::{Context, Result, bail};
use clap::Args;

use super::store::Database;

#[derive(Debug, Args)]
pub struct CopyJobsArgs {
    /// The store to copy from: a SQLite file or postgres://USER:PASSWORD@HOST:PORT/DB.
    /// Stop the servers that use it first: a job that was running is copied as
    /// queued, to resume from its checkpoint wherever the copy is served.
    #[arg(long)]
    pub from: String,
    /// The store to copy into (created and migrated if it is a missing SQLite
    /// file; a PostgreSQL database must exist).
    #[arg(long)]
    pub to: String,
}

/// How many jobs a copy wrote and skipped.
#[derive(Debug, Default)]
struct Tally {
    copied: usize,
    skipped: usize,
    events: usize,
    files: usize,
    /// Jobs not copied: their owner's idempotency key belongs to another
    /// job in the destination.
    clashes: Vec<String>,
    profiles: usize,
    /// Profiles the destination already had (by key and name).
    profiles_kept: usize,
}

pub fn run(args: CopyJobsArgs) -> Result<()> {
    let (from, to) = (Database::parse(&args.from), Database::parse(&args.to));
    if args.from == args.to {
        bail!("--from and --to are the same store ({from})");
    }
    if let Database::Sqlite(path) = &from
        && !path.exists()
    {
        bail!("--from: no such file {}", path.display());
    }
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .context("starting the async runtime")?;
    let tally = runtime.block_on(copy(&from, &to))?;
    println!(
        "copied {} ({}, {}) and {} from {from} to {to}; {} and {} already there, skipped",
        count(tally.copied, "job"),
        count(tally.events, "event"),
        count(tally.files, "file"),
        count(tally.profiles, "balloon profile"),
        count(tally.skipped, "job"),
        count(tally.profiles_kept, "profile"),
    );
    if let [first, ..] = tally.clashes.as_slice() {
        bail!(
            "{} not copied: the destination has another job with the same API key and \
             Idempotency-Key (first: {first})",
            count(tally.clashes.len(), "job")
        );
    }
    Ok(())
}

/// "1 job", "2 jobs".
fn count(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}

async fn copy(from: &Database, to: &Database) -> Result<Tally> {
    let source = from
        .open()
        .await
        .with_context(|| format!("--from: opening {from}"))?;
    let destination = to
        .open()
        .await
        .with_context(|| format!("--to: opening {to}"))?;
    let mut tally = Tally::default();
    let ids = source.job_ids().await.context("--from: listing jobs")?;
    for (done, id) in ids.iter().enumerate() {
        if done > 0 && done % 100 == 0 {
            eprintln!("{done} of {} jobs read", ids.len());
        }
        let Some(job) = source
            .export_job(id)
            .await
            .with_context(|| format!("--from: reading job {id}"))?
        else {
            continue; // deleted meanwhile
        };
        let written = destination
            .import_job(&job)
            .await
            .with_context(|| format!("--to: writing job {id}"))?;
        if written {
            tally.copied += 1;
            tally.events += job.events.len();
            tally.files += job.files.len();
        } else if destination.job(id, None).await?.is_some() {
            tally.skipped += 1;
        } else {
            tally.clashes.push(id.clone());
        }
    }
    for profile in source
        .all_profiles()
        .await
        .context("--from: reading the balloon profiles")?
    {
        let written = destination
            .import_profile(&profile)
            .await
            .with_context(|| format!("--to: writing the balloon profile {}", profile.name))?;
        match written {
            true => tally.profiles += 1,
            false => tally.profiles_kept += 1,
        }
    }
    // Jobs copied from a store that predates job specs get theirs here, so
    // that a server already running on the destination can run them.
    super::upgrade::derive_specs(destination.as_ref())
        .await
        .context("--to: deriving the job specs of copied jobs")?;
    Ok(tally)
}
