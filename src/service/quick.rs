//! Synchronous quick looks: `POST /v1/ksa`, `POST /v1/simulate` (with a time
//! cap) and `GET /v1/presets`. The computation runs on a blocking thread.

use std::time::{Duration, Instant};

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use patchwork_core::curve::{Preset, Units};
use patchwork_core::design::Design;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::section::CutElements;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::ksa::{KsaParams, Stretch, ksa};
use serde::Deserialize;
use serde_json::{Value, json};

use super::problem::{ApiJson, Problem};
use super::request::{CurveSpec, validate_design};
use super::state::AppState;
use crate::reports::{KsaReport, SimulateReport};

/// `POST /v1/ksa`; every field but `curve` defaults to the reference scene.
#[derive(Debug, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct KsaRequest {
    curve: CurveSpec,
    units: Units,
    l0_mm: f64,
    r0_mm: f64,
    kappa_tol: f64,
    merge_mm: f64,
    width_mm: f64,
    /// Axial stretch λ; absent = the authors' uniform L_curve / L₀.
    stretch: Option<f64>,
}

impl Default for KsaRequest {
    fn default() -> Self {
        let p = KsaParams::default();
        KsaRequest {
            // An empty curve: `CurveSpec::load` names the missing curve.
            curve: CurveSpec::default(),
            units: Units::Mm,
            l0_mm: p.l0_mm,
            r0_mm: p.r0_mm,
            kappa_tol: p.kappa_tol,
            merge_mm: p.merge_mm,
            width_mm: p.width_mm,
            stretch: None,
        }
    }
}

/// `value` within `[min, max]`, else a problem naming `field`.
fn within(field: &str, value: f64, (min, max): (f64, f64)) -> Result<(), Problem> {
    if (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(Problem::invalid(
            field,
            format!("{field} must be between {min} and {max}, got {value}"),
        ))
    }
}

/// Ranges of KSA's parameters: lengths in mm, κ in mm⁻¹, the stretch λ.
const LENGTH_RANGE: (f64, f64) = (0.001, 100_000.0);
const KAPPA_RANGE: (f64, f64) = (1e-6, 10.0);
const STRETCH_RANGE: (f64, f64) = (0.01, 100.0);

/// Runs CPU work off the async runtime.
async fn blocking<T: Send + 'static>(
    work: impl FnOnce() -> T + Send + 'static,
) -> Result<T, Problem> {
    tokio::task::spawn_blocking(work)
        .await
        .map_err(Problem::internal)
}

pub async fn ksa_route(ApiJson(body): ApiJson<KsaRequest>) -> Result<Json<KsaReport>, Problem> {
    for (field, value, range) in [
        ("l0_mm", body.l0_mm, LENGTH_RANGE),
        ("r0_mm", body.r0_mm, LENGTH_RANGE),
        ("kappa_tol", body.kappa_tol, KAPPA_RANGE),
        ("merge_mm", body.merge_mm, LENGTH_RANGE),
        ("width_mm", body.width_mm, LENGTH_RANGE),
    ] {
        within(field, value, range)?;
    }
    if let Some(lambda) = body.stretch {
        within("stretch", lambda, STRETCH_RANGE)?;
    }
    let curve = body.curve.load(body.units, "curve")?;
    let params = KsaParams {
        l0_mm: body.l0_mm,
        r0_mm: body.r0_mm,
        kappa_tol: body.kappa_tol,
        merge_mm: body.merge_mm,
        width_mm: body.width_mm,
        stretch: body.stretch.map_or(Stretch::Uniform, Stretch::Fixed),
        ..KsaParams::default()
    };
    blocking(move || {
        ksa(&curve, &params)
            .map(|r| Json(KsaReport::new(&curve, r)))
            .map_err(|e| Problem::invalid("curve", e.to_string()))
    })
    .await?
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulateRequest {
    design: Design,
    /// Element size (mm); with `straight_mm` as in
    /// [`MeshSpec::from_options`].
    #[serde(default)]
    mesh_mm: Option<f64>,
    /// Axial element size along bare stretches (local refinement).
    #[serde(default)]
    straight_mm: Option<f64>,
    #[serde(default = "default_rings")]
    rings: usize,
    /// How elements that a patch outline cuts are modelled.
    #[serde(default)]
    cut_elements: CutElements,
}

fn default_rings() -> usize {
    72
}

/// Finest element size the synchronous route accepts (a design job may go finer).
const MIN_SYNC_MESH_MM: f64 = 0.5;

pub async fn simulate_route(
    State(state): State<AppState>,
    ApiJson(body): ApiJson<SimulateRequest>,
) -> Result<Json<SimulateReport>, Problem> {
    validate_design(&body.design, "design")?;
    let mesh = MeshSpec::from_options(body.mesh_mm, body.straight_mm);
    if !(mesh.element_mm.is_finite()
        && mesh.element_mm >= MIN_SYNC_MESH_MM
        && mesh.element_mm <= 20.0)
    {
        return Err(Problem::invalid(
            "mesh_mm",
            format!("mesh_mm must be between {MIN_SYNC_MESH_MM} and 20 mm"),
        ));
    }
    if let Some(straight) = mesh.straight_mm
        && !MeshSpec::straight_fits(mesh.element_mm, straight)
    {
        return Err(Problem::invalid(
            "straight_mm",
            "straight_mm must be between mesh_mm and 100 times mesh_mm",
        ));
    }
    if !(8..=2000).contains(&body.rings) {
        return Err(Problem::invalid(
            "rings",
            "rings must be between 8 and 2000",
        ));
    }
    let cap = state.config.simulate_time_limit;
    let options = SimulateOptions {
        mesh,
        rings: body.rings,
        cut_elements: body.cut_elements,
        time_limit: Some(cap),
        ..SimulateOptions::default()
    };
    let started = Instant::now();
    let work = blocking(move || simulate(&body.design, &options));
    // The solver honours the cap itself, checked between Newton iterations
    // (building a large mesh and one iteration on it are not); this guards
    // the response regardless.
    let outcome = tokio::time::timeout(cap * 3 + Duration::from_secs(5), work).await;
    state.counters.simulate.record(started.elapsed());
    match outcome {
        Ok(Ok(Ok(sim))) => Ok(Json(SimulateReport::new(&sim))),
        Ok(Ok(Err(e))) => Err(Problem::invalid("design", e.to_string())),
        Ok(Err(p)) => Err(p),
        Err(_) => {
            let mut p = Problem::new(
                StatusCode::SERVICE_UNAVAILABLE,
                format!(
                    "the simulation exceeded the {} s cap of this synchronous route; \
                     use a coarser mesh_mm or submit a design job",
                    cap.as_secs()
                ),
            );
            p.retry_after_s = Some(10);
            Err(p)
        }
    }
}

pub async fn presets() -> Json<Value> {
    let list: Vec<Value> = Preset::NAMES
        .iter()
        .map(|name| {
            let params = Preset::from_name(name, json!({}))
                .ok()
                .and_then(|p| serde_json::to_value(p).ok())
                .and_then(|v| v.get("params").cloned())
                .unwrap_or_else(|| json!({"name": ["hilbert", "pancake", "spring"]}));
            json!({ "name": name, "params": params })
        })
        .collect();
    Json(json!({ "presets": list }))
}
