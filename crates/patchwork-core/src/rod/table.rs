//! The rod of a scene: what each patch does to it, tabulated over patch
//! length, width and angle within the bounds from FE solves of one patch
//! alone (`fit.rs`), and the bare tube's stretch from an FE bare balloon;
//! between the grid's points each quantity is interpolated linearly along
//! every axis (clamped at its ends), and a patch at −Θ is the mirror image
//! of one at Θ.

use serde::{Deserialize, Serialize};

use super::bare::BareTube;
use super::correction::Correction;
use super::fit::fit_patch;
use super::integrate::{PatchRod, Placed, centres};
use crate::curve::{Curve, CurveError, Point};
use crate::design::{Design, Patch};
use crate::fe::{SimulateError, SimulateOptions, simulate};
use crate::inverse::VariableBounds;
use crate::parallel::map_in_threads;

/// Uninflated length (mm) of the balloons the table is solved on, each
/// patch at its middle: beyond either end's influence (about 12 mm) for
/// the longest patch of the default bounds.
const BALLOON_MM: f64 = 100.0;

/// Rings of those solves (every 0.5 mm).
const RINGS: usize = 201;

/// Patch angles of the grid (degrees, up to the bounds' limit, which is
/// added).
const ANGLES_DEG: [f64; 7] = [0.0, 10.0, 20.0, 30.0, 45.0, 60.0, 70.0];

/// The rod's cross-sections per uninflated millimetre.
const SECTIONS_PER_MM: f64 = 2.0;

/// Patch lengths, widths and angles (degrees) of the grid, each ascending,
/// and each point's rod and its fit's RMS distance to FE (mm), lengths
/// slowest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RodTable {
    pub bare: BareTube,
    pub lengths_mm: Vec<f64>,
    pub widths_mm: Vec<f64>,
    pub angles_deg: Vec<f64>,
    pub entries: Vec<PatchRod>,
    pub fit_mm: Vec<f64>,
}

/// The grid's axes within `bounds`: patch lengths, widths and angles.
pub fn axes(bounds: &VariableBounds) -> [Vec<f64>; 3] {
    let three = |lo: f64, hi: f64| vec![lo, 0.5 * (lo + hi), hi];
    let limit = bounds.theta_limit_deg;
    let mut angles: Vec<f64> = ANGLES_DEG.into_iter().filter(|a| *a < limit).collect();
    angles.push(limit);
    [
        three(bounds.h_min_mm, bounds.h_max_mm),
        three(bounds.w_min_mm, bounds.w_max_mm),
        angles,
    ]
}

impl RodTable {
    /// The table of `base`'s balloon, patch material and pressure over
    /// `bounds`, every balloon solved with `options` on up to `threads`
    /// threads. An error if the bare balloon or any patch's does not solve.
    /// Once `stop` answers true no further solve starts, and the table
    /// holds the entries solved before (not
    /// [`complete`](RodTable::is_complete)).
    pub fn compute(
        base: &Design,
        bounds: &VariableBounds,
        options: &SimulateOptions,
        threads: usize,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<RodTable, SimulateError> {
        let options = SimulateOptions {
            rings: RINGS,
            threads: 1,
            ..*options
        };
        let mut bare_design = base.clone();
        bare_design.balloon.length_mm = BALLOON_MM;
        bare_design.patches.clear();
        let bare = simulate(&bare_design, &options)?;
        let bare = BareTube::from_rings(&bare.rings).expect("more than four rings");
        let [lengths_mm, widths_mm, angles_deg] = axes(bounds);
        let grid: Vec<Patch> = (lengths_mm.iter())
            .flat_map(|&h_mm| widths_mm.iter().map(move |&w_mm| (h_mm, w_mm)))
            .flat_map(|(h_mm, w_mm)| {
                angles_deg.iter().map(move |&theta_deg| Patch {
                    x_mm: 0.0,
                    y_mm: BALLOON_MM / 2.0,
                    h_mm,
                    w_mm,
                    theta_deg,
                })
            })
            .collect();
        let radius = base.balloon.radius_mm;
        let fitted = map_in_threads(&grid, threads, &|&patch| {
            if stop() {
                return None;
            }
            let design = Design {
                patches: vec![patch],
                ..bare_design.clone()
            };
            let fitted = simulate(&design, &options)
                .map(|solved| fit_patch(patch, radius, BALLOON_MM, &bare, &solved.rings));
            Some(fitted)
        });
        let fitted: Vec<(PatchRod, f64)> =
            fitted.into_iter().flatten().collect::<Result<_, _>>()?;
        let (entries, fit_mm) = fitted.into_iter().unzip();
        Ok(RodTable {
            bare,
            lengths_mm,
            widths_mm,
            angles_deg,
            entries,
            fit_mm,
        })
    }

    /// Whether every point of the grid within `bounds` has its entry.
    pub fn is_complete(&self, bounds: &VariableBounds) -> bool {
        let [a, b, c] = axes(bounds);
        let whole = a.len() * b.len() * c.len();
        (a == self.lengths_mm && b == self.widths_mm && c == self.angles_deg)
            && self.entries.len() == whole
    }

    /// What `patch` does to the rod: the grid's entries interpolated at its
    /// length, width and |Θ|, mirrored for Θ < 0.
    pub fn lookup(&self, patch: &Patch) -> PatchRod {
        let (a, b, c) = (&self.lengths_mm, &self.widths_mm, &self.angles_deg);
        let (ia, ta) = bracket(a, patch.h_mm);
        let (ib, tb) = bracket(b, patch.w_mm);
        let (ic, tc) = bracket(c, patch.theta_deg.abs());
        let mut sum = [0.0; 4];
        for (da, wa) in [(0, 1.0 - ta), (1, ta)] {
            for (db, wb) in [(0, 1.0 - tb), (1, tb)] {
                for (dc, wc) in [(0, 1.0 - tc), (1, tc)] {
                    let k = ((ia + da) * b.len() + ib + db) * c.len() + ic + dc;
                    let e = &self.entries[k];
                    let w = wa * wb * wc;
                    let q = [e.curvature, e.twist, e.phase, e.stretch];
                    sum.iter_mut().zip(q).for_each(|(s, q)| *s += w * q);
                }
            }
        }
        let mirror = if patch.theta_deg < 0.0 { -1.0 } else { 1.0 };
        PatchRod {
            curvature: sum[0],
            twist: mirror * sum[1],
            phase: mirror * sum[2],
            stretch: sum[3],
        }
    }

    /// The entry of each of `design`'s patches.
    pub fn entries(&self, design: &Design) -> Vec<PatchRod> {
        design.patches.iter().map(|p| self.lookup(p)).collect()
    }

    /// The rod's centreline of `design` (on this table's balloon radius,
    /// patch and pressure), from the clamp's centre.
    pub fn centreline(&self, design: &Design) -> Result<Curve, CurveError> {
        self.corrected_centreline(design, &[])
    }

    /// [`centreline`](RodTable::centreline) with each patch's entry
    /// corrected by its own of `corrections` (none if they are not one
    /// per patch).
    pub fn corrected_centreline(
        &self,
        design: &Design,
        corrections: &[Correction],
    ) -> Result<Curve, CurveError> {
        let length = design.balloon.length_mm;
        let n = (length * SECTIONS_PER_MM).ceil().max(1.0) as usize;
        let heights: Vec<f64> = (1..=n).map(|k| length * k as f64 / n as f64).collect();
        let corrected = corrections.len() == design.patches.len();
        let placed: Vec<Placed> = (design.patches.iter().enumerate())
            .map(|(k, p)| {
                let entry = self.lookup(p);
                Placed {
                    patch: *p,
                    rod: match corrected {
                        true => corrections[k].apply(entry),
                        false => entry,
                    },
                }
            })
            .collect();
        let radius = design.balloon.radius_mm;
        let c = centres(radius, length, &self.bare, &placed, &heights);
        Curve::from_points(std::iter::once(Point::zeros()).chain(c).collect())
    }
}

/// The interval of `axis` (ascending) around `v` and `v`'s fraction across
/// it, clamped to the axis's ends.
fn bracket(axis: &[f64], v: f64) -> (usize, f64) {
    if axis.len() < 2 {
        return (0, 0.0);
    }
    let k = axis.partition_point(|&a| a <= v).clamp(1, axis.len() - 1) - 1;
    let t = ((v - axis[k]) / (axis[k + 1] - axis[k])).clamp(0.0, 1.0);
    (k, t)
}
