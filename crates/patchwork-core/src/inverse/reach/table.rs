//! What one patch makes: the bend and twist per unit length of a balloon
//! carrying one patch of the longest length the bounds allow, for each
//! width and angle of a grid, from the FE model.
//!
//! The patch sits in the middle of a short balloon. Over the middle half of
//! the patch the inflated centreline is close to a helix: its curvature and
//! torsion are those of the helix fitted to the centroids of the mesh's
//! rings there (least squares on T′ = d × T for its Darboux vector
//! d = τT + κB, see `verdict.rs`). The torsion is the centreline's, not the
//! material's: an inclined patch bends the tube towards a side that turns
//! round it along the patch (tan Θ = φR₀/H, as KSA has it), which twists the
//! centreline far more than the material twists.

use std::sync::atomic::{AtomicBool, Ordering};

use serde::{Deserialize, Serialize};

use crate::curve::{AnalysisOptions, Curve, Point, analyse};
use crate::design::{Design, Patch};
use crate::fe::{SimulateError, SimulateOptions, Simulation};
use crate::parallel::map_in_threads;

use super::super::caches::Caches;
use super::super::variables::VariableBounds;
use super::helix::HelixFit;
use super::measure::{analysed_smooth, bends};

/// Patch angles of the table (degrees, up to the bounds' limit).
const ANGLES_DEG: [f64; 7] = [0.0, 10.0, 20.0, 30.0, 45.0, 60.0, 75.0];

/// Widths of the table, as fractions of the way from the narrowest to the
/// widest patch the bounds allow.
const WIDTH_FRACTIONS: [f64; 3] = [0.0, 0.5, 1.0];

/// One entry: what a patch of this width and angle makes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PatchResponse {
    pub width_mm: f64,
    pub theta_deg: f64,
    /// Bend per unit inflated length (mm⁻¹).
    pub curvature_per_mm: f64,
    /// Twist per unit inflated length (mm⁻¹, signed: positive is
    /// right-handed).
    pub torsion_per_mm: f64,
    /// The tightest bend per length over a window of the shortest patch
    /// length (`h_min_mm`) anywhere along the patch, measured as the
    /// verdict measures targets (`measure.rs`): an inclined patch bends
    /// the tube unevenly, most near its ends (at 30° about 1.3 times its
    /// middle's helix, at 45° 1.8 times), so the windows of a centreline
    /// it makes reach this, not `curvature_per_mm`.
    #[serde(default)]
    pub peak_curvature_per_mm: f64,
}

impl PatchResponse {
    /// (κ, |τ|) at the peak bend, with the middle helix's twist per bend.
    pub fn peak(&self) -> (f64, f64) {
        let (bend, twist) = (self.curvature_per_mm, self.torsion_per_mm.abs());
        match self.peak_curvature_per_mm > bend && bend > 0.0 {
            true => (
                self.peak_curvature_per_mm,
                twist * self.peak_curvature_per_mm / bend,
            ),
            false => (bend, twist),
        }
    }
}

/// The bend and twist one patch makes, for each width and angle of a grid
/// within the bounds, on a model of the run's balloon.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReachTable {
    /// The patch length of every entry (the longest the bounds allow).
    pub patch_length_mm: f64,
    pub entries: Vec<PatchResponse>,
}

impl ReachTable {
    /// The table for `base`'s balloon, patch material and pressure, over
    /// `bounds`' widths and angles, on `model`, the grid's balloons solved
    /// on up to `threads` threads (each cold: the table is the same for any
    /// thread count). A width or angle whose balloon does not solve is left
    /// out; an error only if none solves. Once `cancel` is set no further
    /// solve starts and the table holds what was solved before: the caller
    /// checks `cancel` before using it.
    pub fn compute(
        base: &Design,
        bounds: &VariableBounds,
        model: &SimulateOptions,
        caches: &Caches,
        threads: usize,
        cancel: &AtomicBool,
    ) -> Result<ReachTable, SimulateError> {
        let h = bounds.h_max_mm;
        let grid = ReachTable::grid(bounds);
        let solved = map_in_threads(&grid, threads, &|&(width, theta)| {
            if cancel.load(Ordering::Relaxed) {
                return None;
            }
            let design = one_patch(base, h, width, theta);
            let simulation = caches.simulate(&design, model);
            Some(simulation.map(|simulation| {
                let (curvature, torsion) = middle_helix(&design, &simulation);
                PatchResponse {
                    width_mm: width,
                    theta_deg: theta,
                    curvature_per_mm: curvature,
                    torsion_per_mm: torsion,
                    peak_curvature_per_mm: peak_bend(&design, &simulation, bounds.h_min_mm)
                        .max(curvature),
                }
            }))
        });
        let mut entries = Vec::new();
        let mut last_error = None;
        for result in solved.into_iter().flatten() {
            match result {
                Ok(entry) => entries.push(entry),
                Err(error) => last_error = Some(error),
            }
        }
        match (entries.is_empty(), last_error) {
            (true, Some(error)) => Err(error),
            _ => Ok(ReachTable {
                patch_length_mm: h,
                entries,
            }),
        }
    }

    /// The (width, angle) of each entry a table within `bounds` holds when
    /// every balloon of the grid solved.
    pub fn grid(bounds: &VariableBounds) -> Vec<(f64, f64)> {
        WIDTH_FRACTIONS
            .into_iter()
            .flat_map(|fraction| {
                let width = bounds.w_min_mm + fraction * (bounds.w_max_mm - bounds.w_min_mm);
                (ANGLES_DEG.into_iter())
                    .filter(|t| *t <= bounds.theta_limit_deg)
                    .map(move |theta| (width, theta))
            })
            .collect()
    }

    /// Whether this table holds an entry for every point of `bounds`' grid,
    /// for patches of the longest length the bounds allow.
    pub fn is_complete(&self, bounds: &VariableBounds) -> bool {
        let grid = ReachTable::grid(bounds);
        self.patch_length_mm == bounds.h_max_mm
            && self.entries.len() == grid.len()
            && (self.entries.iter().zip(&grid))
                .all(|(e, &(w, t))| e.width_mm == w && e.theta_deg == t)
    }

    /// The entries of the widest patch, by angle: the edge of what the
    /// bounds can make.
    pub fn widest(&self) -> Vec<PatchResponse> {
        let widest = self
            .entries
            .iter()
            .map(|e| e.width_mm)
            .fold(f64::NEG_INFINITY, f64::max);
        let mut edge: Vec<PatchResponse> = self
            .entries
            .iter()
            .copied()
            .filter(|e| e.width_mm == widest)
            .collect();
        edge.sort_by(|a, b| a.theta_deg.total_cmp(&b.theta_deg));
        edge
    }
}

/// `base`'s balloon with one patch of length `h` in its middle, its length
/// the patch's axial extent and two balloon diameters either side (the ends
/// stay out of the measured middle).
fn one_patch(base: &Design, h: f64, width: f64, theta_deg: f64) -> Design {
    let radius = base.balloon.radius_mm;
    let axial = h * theta_deg.to_radians().cos() + width * theta_deg.to_radians().sin();
    let mut design = Design {
        patches: vec![],
        ..base.clone()
    };
    design.balloon.length_mm = axial + 8.0 * radius;
    design.patches = vec![Patch {
        x_mm: 0.0,
        y_mm: 0.5 * design.balloon.length_mm,
        h_mm: h,
        w_mm: width,
        theta_deg,
    }];
    design
}

/// κ and τ of the inflated centreline over the middle half of the design's
/// one patch (its axial extent): the helix fitted to the centroids of the
/// mesh's rings there (`HelixFit`, from tangents and curvature vectors).
fn middle_helix(design: &Design, simulation: &Simulation) -> (f64, f64) {
    let patch = &design.patches[0];
    let axial = 2.0 * patch.axial_half_extent();
    let (a, b) = (
        nearest_ring(simulation, patch.y_mm - 0.25 * axial),
        nearest_ring(simulation, patch.y_mm + 0.25 * axial),
    );
    // Three rings more either side for the derivative stencils.
    let last = simulation.mesh.ring_y.len() - 1;
    let (from, to) = (a.saturating_sub(3), (b + 3).min(last));
    let centroids: Vec<Point> = (from..=to)
        .map(|ring| {
            let nodes = &simulation.positions[ring_nodes(simulation, ring)];
            nodes.iter().sum::<Point>() / nodes.len() as f64
        })
        .collect();
    let Ok(centreline) = Curve::from_points(centroids) else {
        return (0.0, 0.0);
    };
    let analysis = analyse(&centreline, &AnalysisOptions::default());
    HelixFit::new(&analysis).between(a - from, b - from)
}

/// The largest bend per length over windows of `bend_mm` centred within
/// the patch's inflated axial extent, on the simulation's centreline (the
/// one targets are compared with).
fn peak_bend(design: &Design, simulation: &Simulation, bend_mm: f64) -> f64 {
    let centreline = &simulation.centreline;
    let stretch = centreline.length() / design.balloon.length_mm;
    let middle = 0.5 * centreline.length();
    let half = design.patches[0].axial_half_extent() * stretch;
    let analysis = analysed_smooth(centreline, bend_mm);
    bends(&analysis, bend_mm)
        .into_iter()
        .zip(&analysis.s)
        .filter(|(_, s)| (**s - middle).abs() <= half)
        .map(|(bend, _)| bend)
        .fold(0.0, f64::max)
}

fn ring_nodes(simulation: &Simulation, ring: usize) -> std::ops::Range<usize> {
    let around = simulation.mesh.around;
    ring * around..(ring + 1) * around
}

fn nearest_ring(simulation: &Simulation, y: f64) -> usize {
    let rings = &simulation.mesh.ring_y;
    (0..rings.len())
        .min_by(|&i, &j| (rings[i] - y).abs().total_cmp(&(rings[j] - y).abs()))
        .unwrap_or(0)
}

#[cfg(test)]
#[path = "table_tests.rs"]
mod tests;
