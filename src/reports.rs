//! The JSON answers of `ksa` and `simulate`, shared by the CLI (`--json`) and
//! the API (`POST /v1/ksa`, `POST /v1/simulate`): one schema everywhere.

use patchwork_core::curve::Curve;
use patchwork_core::design::Patch;
use patchwork_core::fe::Simulation;
use patchwork_core::ksa::KsaResult;
use serde::Serialize;

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
}

impl KsaReport {
    pub fn new(curve: &Curve, result: KsaResult) -> KsaReport {
        KsaReport {
            stretch: result.stretch,
            curve_length_mm: curve.length(),
            uninflated_length_to_cut_mm: curve.length() / result.stretch,
            patches: result.patches,
            clipped: result.clipped,
            runs_off_balloon: result.off_balloon.len(),
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
        }
    }
}
