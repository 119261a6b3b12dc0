//! Synchronous quick looks: `POST /v1/curve`, `POST /v1/ksa`,
//! `POST /v1/simulate` (with a time cap) and `GET /v1/presets`. The
//! computation runs on a blocking thread.

use std::time::{Duration, Instant};

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use patchwork_core::curve::{Curve, Preset, Units};
use patchwork_core::design::Design;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::section::CutElements;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::inverse::Smoothing;
use patchwork_core::inverse::input::{InputReport, check_smoothing, prepare};
use patchwork_core::ksa::{KsaParams, Stretch, ksa};
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use super::problem::{ApiJson, Problem};
use super::request::{CurveSpec, validate_design};
use super::state::AppState;
use crate::reports::{CurveReport, KsaReport, SimulateReport, Surface};

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
    /// The longest patch (mm): a longer run becomes a train of patches, as
    /// in a design's seed; absent = one patch per run (the authors').
    max_patch_mm: Option<f64>,
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
            max_patch_mm: None,
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

/// The largest smoothing σ (mm) `POST /v1/curve` takes, as its schema says.
const MAX_SMOOTHING_MM: f64 = 1e6;

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
    if let Some(longest) = body.max_patch_mm {
        within("max_patch_mm", longest, LENGTH_RANGE)?;
    }
    let curve = body.curve.load(body.units, "curve")?;
    let params = KsaParams {
        l0_mm: body.l0_mm,
        r0_mm: body.r0_mm,
        kappa_tol: body.kappa_tol,
        merge_mm: body.merge_mm,
        width_mm: body.width_mm,
        stretch: body.stretch.map_or(Stretch::Uniform, Stretch::Fixed),
        max_patch_mm: body.max_patch_mm,
        ..KsaParams::default()
    };
    blocking(move || {
        ksa(&curve, &params)
            .map(|r| Json(KsaReport::new(&curve, r, &params)))
            .map_err(|e| Problem::invalid("curve", e.to_string()))
    })
    .await?
}

/// `POST /v1/curve`: the curve as a design job would read it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveRequest {
    curve: CurveSpec,
    #[serde(default)]
    units: Units,
    /// As a job's `options.smooth_mm`: absent, chosen from the noise found.
    #[serde(default)]
    smooth_mm: Option<f64>,
}

/// The target as the design sees it: its points after smoothing, their
/// length, κ and τ, and what the smoothing found and did.
#[derive(Debug, Serialize)]
pub struct CurvePreview {
    #[serde(flatten)]
    report: CurveReport,
    points_mm: Vec<[f64; 3]>,
    /// The points as given, when the smoothing moved them.
    #[serde(skip_serializing_if = "Option::is_none")]
    given_mm: Option<Vec<[f64; 3]>>,
    input: InputReport,
}

pub async fn curve_route(
    ApiJson(body): ApiJson<CurveRequest>,
) -> Result<Json<CurvePreview>, Problem> {
    let curve = body.curve.load(body.units, "curve")?;
    let smoothing = body.smooth_mm.map_or(Smoothing::Auto, Smoothing::Sigma);
    if let Some(sigma) = body.smooth_mm {
        within("smooth_mm", sigma, (0.0, MAX_SMOOTHING_MM))?;
    }
    check_smoothing(&curve, smoothing).map_err(|e| Problem::invalid("smooth_mm", e.to_string()))?;
    blocking(move || {
        let (prepared, input) = prepare(&curve, smoothing, KsaParams::default().kappa_tol)
            .map_err(|e| Problem::invalid("curve", e.to_string()))?;
        let xyz = |c: &Curve| c.points().iter().map(|p| [p.x, p.y, p.z]).collect();
        Ok(Json(CurvePreview {
            report: CurveReport::new(&prepared),
            points_mm: xyz(&prepared),
            given_mm: input.changed_target().then(|| xyz(&curve)),
            input,
        }))
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
    /// Also answer the inflated membrane (`surface`).
    #[serde(default)]
    surface: bool,
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
    let surface = body.surface;
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
        Ok(Ok(Ok(sim))) => {
            let mut report = SimulateReport::new(&sim);
            report.surface = surface.then(|| Surface::new(&sim));
            Ok(Json(report))
        }
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
