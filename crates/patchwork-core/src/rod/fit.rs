//! What one patch does to the rod, fitted to an FE solve of a balloon that
//! carries it alone: the curvature, twist, phase and stretch change
//! ([`PatchRod`]) whose rod puts every ring's centre nearest the FE ring's
//! at the same material height, by Levenberg–Marquardt over the unit cube
//! of the quantities' ranges, from two starts of the twist: none, and the
//! patch's own turn round the tube, tan Θ / R₀. A patch at Θ ≥ 0 turns its
//! bend one way round the tube (every fit from 10° to 70° does), so the
//! twist is kept non-negative (−Θ is the mirror image, `table.rs`).

use std::f64::consts::PI;

use nalgebra::DVector;

use super::bare::BareTube;
use super::integrate::{PatchRod, Placed, centres};
use crate::design::Patch;
use crate::fe::centreline::Ring;
use crate::least_squares::{Iterate, Residuals, Settings, minimise};

/// The range of each fitted quantity: curvature (rad/mm), twist (rad/mm),
/// phase (rad), stretch change.
const RANGES: [(f64, f64); 4] = [(0.0, 1.0), (0.0, 4.0), (-PI, PI), (-3.6, 1.0)];

/// Evaluations of each start's fit.
const BUDGET: usize = 400;

/// One patch's balloon as FE solved it.
struct OnePatch<'a> {
    patch: Patch,
    radius: f64,
    length: f64,
    bare: &'a BareTube,
    rings: &'a [Ring],
}

/// The point `u` of the unit cube as the quantities of `ranges`.
pub(super) fn in_ranges(u: &[f64], ranges: &[(f64, f64)]) -> Vec<f64> {
    (u.iter().zip(ranges))
        .map(|(u, (lo, hi))| lo + u * (hi - lo))
        .collect()
}

/// The rod's centre minus the FE ring's centre at every ring of `rings` but
/// the clamp's (mm, three per ring), the rod on a balloon of `radius` and
/// `length` whose bare tube is `bare`, carrying `placed`.
pub(super) fn ring_gaps(
    (radius, length): (f64, f64),
    bare: &BareTube,
    placed: &[Placed],
    rings: &[Ring],
) -> Vec<f64> {
    let heights: Vec<f64> = rings[1..].iter().map(|r| r.y).collect();
    let c = centres(radius, length, bare, placed, &heights);
    (c.iter().zip(&rings[1..]))
        .flat_map(|(c, r)| {
            let d = c - r.centre;
            [d.x, d.y, d.z]
        })
        .collect()
}

fn rod_at(u: &[f64]) -> PatchRod {
    let q = in_ranges(u, &RANGES);
    PatchRod {
        curvature: q[0],
        twist: q[1],
        phase: q[2],
        stretch: q[3],
    }
}

fn unit(value: f64, (lo, hi): (f64, f64)) -> f64 {
    ((value - lo) / (hi - lo)).clamp(0.0, 1.0)
}

impl OnePatch<'_> {
    /// The rod's centre minus the FE ring's centre at every ring but the
    /// clamp's (mm, three per ring).
    fn gaps(&self, rod: PatchRod) -> DVector<f64> {
        let placed = [Placed {
            patch: self.patch,
            rod,
        }];
        let size = (self.radius, self.length);
        DVector::from_vec(ring_gaps(size, self.bare, &placed, self.rings))
    }
}

impl Residuals for OnePatch<'_> {
    type State = DVector<f64>;

    fn residuals(&self, state: &DVector<f64>) -> Option<DVector<f64>> {
        Some(state.clone())
    }

    fn solve(&self, u: &[f64], _near: &DVector<f64>) -> Option<DVector<f64>> {
        Some(self.gaps(rod_at(u)))
    }
}

/// The rod of `patch` fitted to `rings`, the FE rings (equally spaced in
/// material height from the clamp) of a balloon of `radius` and `length`
/// carrying `patch` alone, whose bare tube is `bare`; and the fit's RMS
/// distance between the rod's centres and the rings' (mm).
pub fn fit_patch(
    patch: Patch,
    radius: f64,
    length: f64,
    bare: &BareTube,
    rings: &[Ring],
) -> (PatchRod, f64) {
    let problem = OnePatch {
        patch,
        radius,
        length,
        bare,
        rings,
    };
    let wrap = patch.theta().tan() / radius;
    let settings = Settings {
        step: 1e-6,
        ..Settings::default()
    };
    let fits = [0.0, wrap.abs()].map(|twist| {
        let u = vec![
            unit(0.05, RANGES[0]),
            unit(twist, RANGES[1]),
            unit(0.0, RANGES[2]),
            unit(-1.0, RANGES[3]),
        ];
        let state = problem.gaps(rod_at(&u));
        let start = Iterate::new(&problem, u, state).ok()?;
        let solution = minimise(&problem, start, BUDGET, None, &settings, &mut |_, _, _| {});
        let best = solution.ok()?.best;
        Some((rod_at(&best.u), best.error))
    });
    let (rod, error) = fits
        .into_iter()
        .flatten()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("the fit's evaluations cannot fail");
    let rms = error / ((rings.len() - 1) as f64).sqrt();
    (rod, rms)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rings of a balloon whose centreline is the rod of `rod` itself: the
    /// fit finds `rod` again.
    #[test]
    fn the_fit_recovers_a_rod_from_its_own_centres() {
        let bare = BareTube::uniform(3.5);
        let patch = Patch {
            x_mm: 0.0,
            y_mm: 50.0,
            h_mm: 20.0,
            w_mm: 2.0,
            theta_deg: 30.0,
        };
        let rod = PatchRod {
            curvature: 0.08,
            twist: 0.15,
            phase: -0.2,
            stretch: -1.2,
        };
        let heights: Vec<f64> = (0..=200).map(|k| k as f64 * 0.5).collect();
        let placed = [Placed { patch, rod }];
        let centres = centres(3.18, 100.0, &bare, &placed, &heights[1..]);
        let rings: Vec<Ring> = std::iter::once(crate::curve::Point::zeros())
            .chain(centres)
            .zip(&heights)
            .map(|(centre, &y)| Ring {
                y,
                centre,
                radius: 10.0,
            })
            .collect();
        let (fitted, rms) = fit_patch(patch, 3.18, 100.0, &bare, &rings);
        assert!(rms < 1e-6, "{rms}");
        assert!(
            (fitted.curvature - rod.curvature).abs() < 1e-6,
            "{fitted:?}"
        );
        assert!((fitted.twist - rod.twist).abs() < 1e-5, "{fitted:?}");
        assert!((fitted.phase - rod.phase).abs() < 1e-5, "{fitted:?}");
        assert!((fitted.stretch - rod.stretch).abs() < 1e-6, "{fitted:?}");
    }
}
