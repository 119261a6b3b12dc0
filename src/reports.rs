//! The JSON answers of `curve`, `ksa` and `simulate`, shared by the CLI
//! (`--json`) and the API (`POST /v1/curve`, `POST /v1/ksa`,
//! `POST /v1/simulate`): one schema everywhere.

use patchwork_core::curve::{AnalysisOptions, Curve, analyse};
use patchwork_core::design::Patch;
use patchwork_core::fe::Simulation;
use patchwork_core::fe::contact::{SelfContact, self_contacts};
use patchwork_core::ksa::{KsaParams, KsaResult};
use serde::Serialize;

/// A curve's length, curvature and torsion along it.
#[derive(Debug, Serialize)]
pub struct CurveReport {
    pub length_mm: f64,
    pub points: usize,
    pub s_mm: Vec<f64>,
    pub curvature_per_mm: Vec<f64>,
    /// 0 where undefined (see `torsion_defined`).
    pub torsion_per_mm: Vec<f64>,
    /// False where κ is too small for torsion to mean anything.
    pub torsion_defined: Vec<bool>,
}

impl CurveReport {
    pub fn new(curve: &Curve) -> CurveReport {
        let analysis = analyse(curve, &AnalysisOptions::default());
        CurveReport {
            length_mm: curve.length(),
            points: curve.len(),
            s_mm: analysis.s,
            curvature_per_mm: analysis.curvature,
            torsion_per_mm: analysis.torsion,
            torsion_defined: analysis.torsion_defined,
        }
    }
}

#[derive(Debug, Serialize)]
pub struct KsaReport {
    pub stretch: f64,
    pub curve_length_mm: f64,
    /// Uninflated length whose inflated length equals the curve's at `stretch`.
    pub uninflated_length_to_cut_mm: f64,
    pub patches: Vec<Patch>,
    /// Indices of patches clipped to stay on the balloon.
    pub clipped: Vec<usize>,
    /// Number of curved stretches beyond the balloon's end (no patch placed).
    pub runs_off_balloon: usize,
    /// The balloon the patches are placed on (KSA's L₀ and R₀): `simulate`
    /// takes this report as the reference scene on that balloon.
    pub balloon_length_mm: f64,
    pub balloon_radius_mm: f64,
}

impl KsaReport {
    pub fn new(curve: &Curve, result: KsaResult, params: &KsaParams) -> KsaReport {
        KsaReport {
            stretch: result.stretch,
            curve_length_mm: curve.length(),
            uninflated_length_to_cut_mm: curve.length() / result.stretch,
            patches: result.patches,
            clipped: result.clipped,
            runs_off_balloon: result.off_balloon.len(),
            balloon_length_mm: params.l0_mm,
            balloon_radius_mm: params.r0_mm,
        }
    }
}

#[derive(Debug, Serialize)]
pub struct SimulateReport {
    pub converged: bool,
    pub centreline_mm: Vec<[f64; 3]>,
    pub inflated_length_mm: f64,
    pub hoop_stretch_mid: f64,
    pub axial_stretch_mid: f64,
    pub curvature_per_mm: Vec<f64>,
    pub torsion_per_mm: Vec<f64>,
    pub newton_iterations: usize,
    pub elapsed_ms: f64,
    pub stable: bool,
    pub relative_residual: f64,
    pub volume_mm3: f64,
    /// Where the inflated tube passes through itself; empty when it clears.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub self_contact: Vec<SelfContact>,
    /// The inflated membrane, when asked for (`surface: true`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub surface: Option<Surface>,
}

/// The inflated membrane as rings of nodes: `positions_mm` holds the tube's
/// rings from the clamped base, then the end cap's rings, `around` nodes
/// each, then the cap's pole. Neighbouring rings make the surface's
/// quadrilaterals; the last ring and the pole its closing fan.
#[derive(Debug, Serialize)]
pub struct Surface {
    pub around: usize,
    /// Node positions (mm), rounded to 0.001 mm.
    pub positions_mm: Vec<[f64; 3]>,
    /// Fraction of each node's neighbourhood covered by patches (0–1, mean
    /// of the elements around it; rounded to 0.01).
    pub patch_share: Vec<f64>,
}

impl Surface {
    pub fn new(sim: &Simulation) -> Surface {
        let round = |v: f64, step: f64| (v / step).round() * step;
        let nodes = sim.positions.len();
        let mut share = vec![0.0; nodes];
        let mut count = vec![0usize; nodes];
        for (triangle, s) in sim.mesh.triangles.iter().zip(&sim.patch_share) {
            for &node in triangle {
                share[node] += s;
                count[node] += 1;
            }
        }
        Surface {
            around: sim.mesh.around,
            positions_mm: sim
                .positions
                .iter()
                .map(|p| [round(p.x, 1e-3), round(p.y, 1e-3), round(p.z, 1e-3)])
                .collect(),
            patch_share: share
                .iter()
                .zip(&count)
                .map(|(s, &n)| round(s / n.max(1) as f64, 0.01))
                .collect(),
        }
    }
}

impl SimulateReport {
    pub fn new(sim: &Simulation) -> SimulateReport {
        SimulateReport {
            converged: true,
            centreline_mm: sim
                .centreline
                .points()
                .iter()
                .map(|p| [p.x, p.y, p.z])
                .collect(),
            inflated_length_mm: sim.inflated_length_mm,
            hoop_stretch_mid: sim.hoop_stretch_mid,
            axial_stretch_mid: sim.axial_stretch_mid,
            curvature_per_mm: sim.curvature.clone(),
            torsion_per_mm: sim.torsion.clone(),
            newton_iterations: sim.stats.iterations,
            elapsed_ms: sim.elapsed.as_secs_f64() * 1e3,
            stable: sim.stats.stable,
            relative_residual: sim.stats.residual,
            volume_mm3: sim.volume_mm3,
            self_contact: self_contacts(&sim.rings),
            surface: None,
        }
    }
}
