//! A calibration job: the core's `calibrate_watched` on a blocking thread,
//! each iteration's progress recorded (the job's progress and a `progress`
//! event), and the ending: calibration.json (the result) and options.json
//! (the calibrated balloon and patch, as a design takes them), saved as the
//! owner's balloon profile where the job asks. A calibration has no
//! checkpoint: one interrupted by a shutdown starts again.

use std::sync::atomic::Ordering;
use std::time::Duration;

use patchwork_core::calibrate::{
    Calibration, CalibrationError, CalibrationProgress, Parameter, calibrate_watched,
};
use patchwork_core::design::{Balloon, PatchSpec};
use patchwork_core::fabrication::OutputFile;
use serde_json::{Value, json};
use tokio::sync::mpsc;

use super::ending::{Ran, fail, finish, finite, unless_done, until_stored};
use super::holding::Holding;
use crate::service::job_state::EventKind;
use crate::service::profile::Profile;
use crate::service::spec::CalibrateSpec;
use crate::service::state::AppState;
use crate::service::store::{Claim, Lease};

/// A calibration that finished: its answer, the materials as a profile,
/// and where to save them.
struct CalibrationDone {
    calibration: Calibration,
    profile: Profile,
    save_as: Option<String>,
    owner: String,
}

pub(super) async fn run(state: &AppState, claim: Claim, spec: CalibrateSpec) {
    let Claim { job, lease, .. } = claim;
    tracing::info!("starting a calibration");
    let holding = Holding::start(state, &lease, Duration::ZERO);
    let stage = json!({"stage": "calibrate"});
    let fence = Some(lease.attempt);
    if let Err(e) = state.emit(&lease.id, EventKind::Stage, &stage, fence).await {
        tracing::error!("recording the stage: {e}");
    }
    let (tx, mut rx) = mpsc::unbounded_channel::<CalibrationProgress>();
    let span = tracing::Span::current();
    let compute = {
        let control = holding.control.clone();
        tokio::task::spawn_blocking(move || {
            let _entered = span.enter();
            let CalibrateSpec {
                balloon,
                patch,
                measurements,
                fit,
                ..
            } = &spec;
            let answer = calibrate_watched(
                balloon,
                &patch.material,
                measurements,
                fit,
                &control.cancel,
                &mut |p| {
                    let _ = tx.send(p.clone());
                },
            );
            (spec, answer)
        })
    };
    let mut solves = 0;
    while let Some(progress) = rx.recv().await {
        let added = progress.solves.saturating_sub(solves) as u64;
        state
            .counters
            .forward_solves
            .fetch_add(added, Ordering::Relaxed);
        solves = progress.solves;
        if let Err(e) = record(state, &lease, &progress).await {
            tracing::error!("recording progress: {e}");
        }
    }
    let outcome = compute.await;
    holding.computed(state, &lease);
    let ran = match outcome {
        Ok((spec, Ok(calibration))) => Ran::Done(CalibrationDone {
            profile: profile_of(&spec, &calibration),
            calibration,
            save_as: spec.save_as,
            owner: job.owner,
        }),
        Ok((_, Err(CalibrationError::Cancelled))) => Ran::Stopped,
        Ok((_, Err(e))) => Ran::Failed(e.to_string()),
        Err(e) => Ran::Failed(format!("internal error: {e}")),
    };
    if let Some(done) = unless_done(state, &lease, ran, holding.control.reason()).await {
        succeed(state, &lease, &done).await;
    }
    holding.release();
}

/// The progress as the job and its `progress` event show it.
fn progress_json(p: &CalibrationProgress) -> Value {
    let values = by_name(p.values.iter().copied());
    json!({
        "stage": "calibrate",
        "iteration": p.iteration,
        "solves": p.solves,
        "rms_percent": finite(p.rms_percent),
        "parameters": values,
    })
}

async fn record(
    state: &AppState,
    lease: &Lease,
    p: &CalibrationProgress,
) -> Result<(), sqlx::Error> {
    let progress = progress_json(p);
    (state.store)
        .record_progress(lease, &progress.to_string(), None)
        .await?;
    let fence = Some(lease.attempt);
    state
        .emit(&lease.id, EventKind::Progress, &progress, fence)
        .await
}

/// The spec's balloon and patch made of the calibrated materials.
fn profile_of(spec: &CalibrateSpec, c: &Calibration) -> Profile {
    Profile {
        balloon: Balloon {
            material: c.material.clone(),
            ..spec.balloon.clone()
        },
        patch: PatchSpec {
            material: c.patch_material.clone(),
            ..spec.patch.clone()
        },
    }
}

/// Saves the profile (where asked), then stores the result, its files and
/// the `done` event, and marks the job succeeded.
async fn succeed(state: &AppState, lease: &Lease, done: &CalibrationDone) {
    let written = serde_json::to_string_pretty(&done.calibration)
        .and_then(|c| Ok((c, serde_json::to_string_pretty(&done.profile)?)));
    let (result, options) = match written {
        Ok(written) => written,
        Err(e) => return fail(state, lease, &format!("writing the result files: {e}")).await,
    };
    if let Some(name) = &done.save_as {
        let saved = until_stored(state, "saving the balloon profile", || {
            (state.store).put_profile(&done.owner, name, &options, Some(&lease.id))
        });
        if let Err(e) = saved.await {
            let error = format!("saving the balloon profile `{name}`: {e}");
            return fail(state, lease, &error).await;
        }
    }
    let files = [
        json_file("calibration.json", &result),
        json_file("options.json", &options),
    ];
    let c = &done.calibration;
    let parameters = by_name(c.parameters.iter().map(|f| (f.parameter, f.value)));
    let mut event = json!({
        "result": format!("/v1/jobs/{}/result", lease.id),
        "rms_percent": finite(c.rms_percent),
        "parameters": parameters,
        "warnings": c.warnings,
        "solves": c.solves,
    });
    if let Some(name) = &done.save_as {
        event["profile"] = json!(format!("/v1/balloons/{name}"));
    }
    if finish(state, lease, &result, &files, &event.to_string()).await {
        tracing::info!(rms_percent = c.rms_percent, solves = c.solves, "succeeded");
    }
}

/// Parameter values as a JSON object by name (NaN as null).
fn by_name(values: impl Iterator<Item = (Parameter, f64)>) -> serde_json::Map<String, Value> {
    values
        .map(|(p, v)| (p.name().to_string(), json!(finite(v))))
        .collect()
}

fn json_file(name: &'static str, text: &str) -> OutputFile {
    OutputFile {
        name,
        content_type: "application/json",
        body: format!("{text}\n").into_bytes(),
    }
}
